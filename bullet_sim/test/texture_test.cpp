// Textures and materials against what the files say: images decoded by libpng and libjpeg, a textured quad
// (written here as COLLADA and as OBJ + MTL) drawn with each quadrant of its texture where its texture
// coordinates put it, in camera images and snapshots alike; Gazebo material names; textures loaded once.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <jpeglib.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>

#include "bullet_sim/assets/gazebo_materials.h"
#include "bullet_sim/assets/mesh.h"
#include "bullet_sim/render/image.h"
#include "bullet_sim/render/offscreen_renderer.h"
#include "bullet_sim/scene/scene_builder.h"
#include "bullet_sim/scene/simulation_images.h"
#include "test_support.h"

namespace bullet_sim {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

constexpr int kColourTolerance = 3;  // [0, 255] per channel: GL's rounding of lit, filtered texels

/// A directory of its own, removed with everything in it.
class TemporaryDirectory {
 public:
  TemporaryDirectory() {
    std::string pattern = (fs::temp_directory_path() / "texture_test_XXXXXX").string();
    if (!mkdtemp(pattern.data())) throw std::runtime_error("mkdtemp failed for [" + pattern + "]");
    path_ = pattern;
  }
  ~TemporaryDirectory() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  TemporaryDirectory(const TemporaryDirectory&) = delete;
  TemporaryDirectory& operator=(const TemporaryDirectory&) = delete;

  /// Writes `text` to `name` in the directory; its path.
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(path_ / name) << text;
    return file(name);
  }
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  fs::path path_;
};

struct Quadrant {
  const char* name;
  Eigen::Vector3i rgb;
  Eigen::Vector2d uv;  ///< its centre in texture coordinates (v up)
};

// The test texture: red top left, blue top right, green bottom left, yellow bottom right.
const Quadrant kQuadrants[] = {{"red", {255, 0, 0}, {0.25, 0.75}},
                               {"blue", {0, 0, 255}, {0.75, 0.75}},
                               {"green", {0, 255, 0}, {0.25, 0.25}},
                               {"yellow", {255, 255, 0}, {0.75, 0.25}}};

Image quadrantImage(int side = 64) {
  Image image{side, side, std::vector<uint8_t>(static_cast<size_t>(side) * side * 4)};
  for (int row = 0; row < side; ++row) {
    for (int column = 0; column < side; ++column) {
      const Eigen::Vector3i& rgb = kQuadrants[(row < side / 2 ? 0 : 2) + (column < side / 2 ? 0 : 1)].rgb;
      uint8_t* pixel = &image.rgba[(static_cast<size_t>(row) * side + column) * 4];
      for (int c = 0; c < 3; ++c) pixel[c] = static_cast<uint8_t>(rgb[c]);
      pixel[3] = 255;
    }
  }
  return image;
}

std::string writePngFile(const TemporaryDirectory& directory, const std::string& name, const Image& image) {
  std::string error;
  EXPECT_TRUE(writePng(directory.file(name), image, &error)) << error;
  return directory.file(name);
}

std::string writeJpegFile(const TemporaryDirectory& directory, const std::string& name, const Image& image) {
  const std::string path = directory.file(name);
  FILE* file = std::fopen(path.c_str(), "wb");
  jpeg_compress_struct info{};
  jpeg_error_mgr errors{};
  info.err = jpeg_std_error(&errors);
  jpeg_create_compress(&info);
  jpeg_stdio_dest(&info, file);
  info.image_width = image.width;
  info.image_height = image.height;
  info.input_components = 4;
  info.in_color_space = JCS_EXT_RGBA;
  jpeg_set_defaults(&info);
  jpeg_set_quality(&info, 95, TRUE);
  jpeg_start_compress(&info, TRUE);
  while (info.next_scanline < info.image_height) {
    JSAMPROW row =
        const_cast<uint8_t*>(&image.rgba[static_cast<size_t>(info.next_scanline) * image.width * 4]);
    jpeg_write_scanlines(&info, &row, 1);
  }
  jpeg_finish_compress(&info);
  jpeg_destroy_compress(&info);
  std::fclose(file);
  return path;
}

// A 0.6 m square in its frame's y-z plane, facing -x, its texture upright for a camera looking along +x:
// u = 0 at +y (the camera's left), v = 0 at -z. COLLADA's coordinates stand as written, whatever up_axis.
const char* kQuadObj = R"(mtllib quad.mtl
v 0 0.3 -0.3
v 0 -0.3 -0.3
v 0 -0.3 0.3
v 0 0.3 0.3
vt 0 0
vt 1 0
vt 1 1
vt 0 1
usemtl painted
f 1/1 2/2 3/3
f 1/1 3/3 4/4
)";

std::string quadMtl(const std::string& texture, const std::string& kd = "1 1 1") {
  return "newmtl painted\nKd " + kd + "\nmap_Kd " + texture + "\n";
}

std::string quadDae(const std::string& texture) {
  return R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="meter" meter="1"/><up_axis>Z_UP</up_axis></asset>
  <library_images><image id="image"><init_from>)" +
         texture + R"(</init_from></image></library_images>
  <library_effects><effect id="effect"><profile_COMMON>
    <newparam sid="surface"><surface type="2D"><init_from>image</init_from></surface></newparam>
    <newparam sid="sampler"><sampler2D><source>surface</source></sampler2D></newparam>
    <technique sid="common"><lambert>
      <diffuse><texture texture="sampler" texcoord="uv"/></diffuse>
    </lambert></technique>
  </profile_COMMON></effect></library_effects>
  <library_materials><material id="painted"><instance_effect url="#effect"/></material></library_materials>
  <library_geometries><geometry id="quad"><mesh>
    <source id="positions">
      <float_array id="positions-array" count="12">0 0.3 -0.3 0 -0.3 -0.3 0 -0.3 0.3 0 0.3 0.3</float_array>
      <technique_common><accessor source="#positions-array" count="4" stride="3">
        <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
      </accessor></technique_common></source>
    <source id="uvs"><float_array id="uvs-array" count="8">0 0 1 0 1 1 0 1</float_array>
      <technique_common><accessor source="#uvs-array" count="4" stride="2">
        <param name="S" type="float"/><param name="T" type="float"/></accessor></technique_common></source>
    <vertices id="vertices"><input semantic="POSITION" source="#positions"/></vertices>
    <triangles material="painted" count="2">
      <input semantic="VERTEX" source="#vertices" offset="0"/>
      <input semantic="TEXCOORD" source="#uvs" offset="1" set="0"/>
      <p>0 0 1 1 2 2 0 0 2 2 3 3</p>
    </triangles>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="scene"><node id="node">
    <instance_geometry url="#quad"><bind_material><technique_common>
      <instance_material symbol="painted" target="#painted">
        <bind_vertex_input semantic="uv" input_semantic="TEXCOORD" input_set="0"/>
      </instance_material>
    </technique_common></bind_material></instance_geometry>
  </node></visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>)";
}

/// Writes the quadrant texture and the quad as `format` ("dae" or "obj") into `directory`; the mesh's path.
std::string writeTexturedQuad(const TemporaryDirectory& directory, const std::string& format) {
  writePngFile(directory, "quadrants.png", quadrantImage());
  if (format == "dae") return directory.write("quad.dae", quadDae("quadrants.png"));
  directory.write("quad.mtl", quadMtl("quadrants.png"));
  return directory.write("quad.obj", kQuadObj);
}

/// A world holding the quad at `pose` ("x y z roll pitch yaw"), its visual's <material> being `material`.
std::string quadWorld(const std::string& mesh, const std::string& material = "",
                      const std::string& pose = "1.5 0 0.5 0 0 0") {
  return R"(<sdf version="1.6"><world name="w"><model name="quad"><static>true</static><pose>)" + pose +
         R"(</pose><link name="l"><visual name="v"><geometry><mesh><uri>)" + mesh +
         "</uri></mesh></geometry>" + material + "</visual></link></model></world></sdf>";
}

WorldSpec parse(const std::string& sdf, std::vector<std::string>* warnings = nullptr) {
  return parseWorld(sdf, "texture_test.world", PackageResolver::fromEnvironment(), warnings);
}

// The camera: at (0, 0, 0.5) looking along +x, 160 x 120 px, 1 rad wide.
constexpr int kWidth = 160, kHeight = 120;
constexpr double kFov = 1.0;

ImageRequest cameraRequest() {
  ImageRequest request;
  request.pose = Eigen::Translation3d(0, 0, 0.5);
  request.width = kWidth;
  request.height = kHeight;
  request.horizontal_fov = kFov;
  return request;
}

/// The pixel a world point lands in, by the pinhole model of cameraRequest.
Eigen::Vector2i pinhole(const Eigen::Vector3d& point) {
  const double focal = kWidth / (2 * std::tan(kFov / 2));
  const Eigen::Vector3d seen = point - Eigen::Vector3d(0, 0, 0.5);
  return {static_cast<int>(std::floor(kWidth / 2.0 - focal * seen.y() / seen.x())),
          static_cast<int>(std::floor(kHeight / 2.0 - focal * seen.z() / seen.x()))};
}

/// What a surface of colour `rgb` shows when it faces the camera (normal -x), lit by the default light.
Eigen::Vector3i lit(const Eigen::Vector3d& rgb) {
  const Eigen::Vector3d shaded = Lighting().shade(rgb.homogeneous(), -Eigen::Vector3d::UnitX());
  return (255 * shaded).array().round().cast<int>();
}

/// Where the quad's texture coordinates (u, v) lie in the world, the quad standing at (1.5, 0, 0.5).
Eigen::Vector3d onQuad(const Eigen::Vector2d& uv) {
  return {1.5, 0.3 - 0.6 * uv.x(), 0.5 - 0.3 + 0.6 * uv.y()};
}

Eigen::Vector3i rgbAt(const std::vector<uint8_t>& rgb, const Eigen::Vector2i& pixel) {
  const uint8_t* value = &rgb[(static_cast<size_t>(pixel.y()) * kWidth + pixel.x()) * 3];
  return {value[0], value[1], value[2]};
}

void expectQuadrants(const std::vector<uint8_t>& rgb, const std::string& what,
                     const Eigen::Vector3d& tint = Eigen::Vector3d::Ones()) {
  for (const Quadrant& quadrant : kQuadrants) {
    const Eigen::Vector2i pixel = pinhole(onQuad(quadrant.uv));
    const Eigen::Vector3i expected = lit(quadrant.rgb.cast<double>().cwiseProduct(tint) / 255);
    const Eigen::Vector3i actual = rgbAt(rgb, pixel);
    EXPECT_LE((actual - expected).cwiseAbs().maxCoeff(), kColourTolerance)
        << what << ": the " << quadrant.name << " quadrant at pixel " << pixel.transpose() << " shows "
        << actual.transpose() << ", not " << expected.transpose();
  }
}

/// Renders `world` as a camera sees it and as a snapshot draws it, and checks the quadrants in both.
void expectQuadrantsSeen(const WorldSpec& world, const std::string& what,
                         const Eigen::Vector3d& tint = Eigen::Vector3d::Ones()) {
  OffscreenRenderer renderer;
  Simulation simulation(world, SimulationOptions{});
  SimulationImages images(simulation, [&]() -> SceneRenderer& { return renderer; });
  RenderedImage frame;
  images.render(cameraRequest(), frame);
  expectQuadrants(frame.rgb, what + ", camera image", tint);
  const Image snapshot = renderer.render(images.sceneFor(cameraRequest()), kWidth, kHeight);
  std::vector<uint8_t> rgb;
  dropAlpha(snapshot.rgba.data(), snapshot.rgba.size() / 4, rgb);
  expectQuadrants(rgb, what + ", snapshot", tint);
}

TEST(Texture, PngAndJpegDecodeToTheirPixels) {
  TemporaryDirectory directory;
  const Image image = quadrantImage(32);
  std::string error;
  const std::optional<Texture> png = loadTexture(writePngFile(directory, "q.png", image), &error);
  ASSERT_TRUE(png) << error;
  EXPECT_EQ(png->width, 32);
  EXPECT_EQ(png->rgba, image.rgba);
  // JPEG is lossy: each quadrant's centre keeps its colour within a few levels.
  const std::optional<Texture> jpeg = loadTexture(writeJpegFile(directory, "q.jpg", image), &error);
  ASSERT_TRUE(jpeg) << error;
  ASSERT_EQ(jpeg->width, 32);
  for (const Quadrant& quadrant : kQuadrants) {
    const int column = static_cast<int>(quadrant.uv.x() * 32),
              row = static_cast<int>((1 - quadrant.uv.y()) * 32);
    const uint8_t* pixel = &jpeg->rgba[(static_cast<size_t>(row) * 32 + column) * 4];
    const Eigen::Vector3i actual(pixel[0], pixel[1], pixel[2]);
    EXPECT_LE((actual - quadrant.rgb).cwiseAbs().maxCoeff(), 8)
        << quadrant.name << ": " << actual.transpose();
  }
}

TEST(Texture, DamagedOversizedAndOddFilesAreRefusedWithTheReason) {
  TemporaryDirectory directory;
  std::string error;
  EXPECT_FALSE(loadTexture(directory.write("text.png", "not an image"), &error));
  EXPECT_THAT(error, HasSubstr("text.png"));
  EXPECT_THAT(error, HasSubstr("not a PNG or a readable JPEG"));
  // A PNG cut short after its header.
  const std::string png = writePngFile(directory, "whole.png", quadrantImage());
  const std::string bytes = test::readFile(png);
  EXPECT_FALSE(loadTexture(directory.write("cut.png", bytes.substr(0, bytes.size() / 2)), &error));
  EXPECT_THAT(error, HasSubstr("damaged PNG"));
  EXPECT_FALSE(loadTexture("/dev/zero", &error));
  EXPECT_THAT(error, HasSubstr("not a regular file"));
  EXPECT_FALSE(loadTexture(directory.file("missing.png"), &error));
  EXPECT_THAT(error, HasSubstr("no such file"));

  // Over the limits: a PNG is refused; a JPEG is decoded smaller, as libjpeg scales by 1/2, 1/4 or 1/8.
  const TextureLimits limits{16 * 16, 16384};
  EXPECT_FALSE(loadTexture(png, &error, limits));
  EXPECT_THAT(error, HasSubstr("is 64 x 64 px, more than bullet_sim decodes (256 pixels"));
  const std::optional<Texture> jpeg =
      loadTexture(writeJpegFile(directory, "big.jpg", quadrantImage()), &error, limits);
  ASSERT_TRUE(jpeg) << error;
  EXPECT_EQ(jpeg->width, 16);
  EXPECT_EQ(jpeg->height, 16);
  const TextureLimits tiny{4, 16384};  // even 1/8 of 64 x 64 is 8 x 8
  EXPECT_FALSE(loadTexture(directory.file("big.jpg"), &error, tiny));
  EXPECT_THAT(error, HasSubstr("is 64 x 64 px"));
}

TEST(Texture, ACacheDecodesEachFileOnceAndBoundsWhatAllItsTexturesTake) {
  TemporaryDirectory directory;
  const std::string first = writePngFile(directory, "first.png", quadrantImage());  // 16 KiB of RGBA
  const std::string second = writePngFile(directory, "second.png", quadrantImage());
  TextureCache textures(24 << 10);
  std::string error;
  const std::shared_ptr<const Texture> texture = textures.load(first, &error);
  ASSERT_TRUE(texture) << error;
  EXPECT_EQ(textures.load(directory.file("./first.png"), &error), texture) << "the same file, decoded once";
  EXPECT_FALSE(textures.load(second, &error)) << "over the budget";
  EXPECT_THAT(error, HasSubstr("second.png"));
  EXPECT_THAT(error, HasSubstr("is not drawn"));
}

TEST(Mesh, DaeAndObjBringTheirTextureCoordinatesAndTexture) {
  for (const std::string format : {"dae", "obj"}) {
    TemporaryDirectory directory;
    const std::string path = writeTexturedQuad(directory, format);
    TextureCache textures;
    std::vector<std::string> warnings;
    std::string error;
    const std::optional<TriangleMesh> mesh =
        loadMesh(path, Eigen::Vector3d::Ones(), &error, &textures, &warnings);
    ASSERT_TRUE(mesh) << error;
    EXPECT_THAT(warnings, ::testing::IsEmpty());
    ASSERT_EQ(mesh->triangles.size(), 2u) << format;
    ASSERT_EQ(mesh->uvs.size(), mesh->vertices.size()) << format;
    ASSERT_EQ(mesh->parts.size(), 1u) << format;
    const MeshMaterial& material = mesh->materials.at(mesh->parts[0].material);
    ASSERT_TRUE(material.texture) << format;
    EXPECT_EQ(material.texture->width, 64);
    // Every vertex where it was written (COLLADA's Z_UP does not turn it), with its texture coordinates.
    for (size_t v = 0; v < mesh->vertices.size(); ++v) {
      const Eigen::Vector2d uv = mesh->uvs[v].cast<double>();
      EXPECT_TRUE(mesh->vertices[v].isApprox(onQuad(uv) - Eigen::Vector3d(1.5, 0, 0.5), 1e-6))
          << format << " vertex " << v << " at " << mesh->vertices[v].transpose() << " has uv "
          << uv.transpose();
    }
  }
}

TEST(TexturedQuad, CamerasAndSnapshotsShowEachQuadrantWhereTheTextureCoordinatesPutIt) {
  for (const std::string format : {"dae", "obj"}) {
    TemporaryDirectory directory;
    std::vector<std::string> warnings;
    const WorldSpec world = parse(quadWorld(writeTexturedQuad(directory, format)), &warnings);
    EXPECT_THAT(warnings, ::testing::IsEmpty());
    expectQuadrantsSeen(world, format);
  }
}

TEST(TexturedQuad, AColourTintsTheTextureAndAGazeboMaterialReplacesIt) {
  TemporaryDirectory directory;
  const std::string mesh = writeTexturedQuad(directory, "dae");
  // <diffuse> (as a URDF <color>) sets the colour of every part: the texture is multiplied by it.
  expectQuadrantsSeen(parse(quadWorld(mesh, "<material><diffuse>0.5 0.5 0.5 1</diffuse></material>")),
                      "tinted", Eigen::Vector3d::Constant(0.5));
  // A Gazebo material script replaces the mesh's materials: one colour all over.
  const WorldSpec world =
      parse(quadWorld(mesh,
                      "<material><script><uri>file://media/materials/scripts/gazebo.material</uri>"
                      "<name>Gazebo/Indigo</name></script></material>"));
  OffscreenRenderer renderer;
  Simulation simulation(world, SimulationOptions{});
  SimulationImages images(simulation, [&]() -> SceneRenderer& { return renderer; });
  RenderedImage frame;
  images.render(cameraRequest(), frame);
  for (const Quadrant& quadrant : kQuadrants) {
    const Eigen::Vector3i actual = rgbAt(frame.rgb, pinhole(onQuad(quadrant.uv)));
    EXPECT_LE((actual - lit(Eigen::Vector3d(0.33, 0, 0.5))).cwiseAbs().maxCoeff(), kColourTolerance)
        << quadrant.name << ": " << actual.transpose();
  }
}

TEST(TexturedQuad, AMissingTextureIsAWarningAndThePartShowsItsMaterialColour) {
  TemporaryDirectory directory;
  directory.write("quad.mtl", quadMtl("gone.png", "0 1 0"));
  std::vector<std::string> warnings;
  const WorldSpec world = parse(quadWorld(directory.write("quad.obj", kQuadObj)), &warnings);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_THAT(warnings[0], HasSubstr("texture [gone.png] not found"));
  EXPECT_THAT(warnings[0], HasSubstr(directory.file("gone.png")));
  EXPECT_THAT(warnings[0], HasSubstr("drawn in its material colour"));
  OffscreenRenderer renderer;
  Simulation simulation(world, SimulationOptions{});
  SimulationImages images(simulation, [&]() -> SceneRenderer& { return renderer; });
  RenderedImage frame;
  images.render(cameraRequest(), frame);
  const Eigen::Vector3i actual = rgbAt(frame.rgb, pinhole(onQuad({0.5, 0.5})));
  EXPECT_LE((actual - lit(Eigen::Vector3d(0, 1, 0))).cwiseAbs().maxCoeff(), kColourTolerance)
      << actual.transpose();
}

TEST(TexturedQuad, CopiesOfAModelShareOneMeshAndOneDecodedTexture) {
  TemporaryDirectory directory;
  const std::string dae = writeTexturedQuad(directory, "dae");
  directory.write("quad.mtl", quadMtl("quadrants.png"));
  const std::string obj = directory.write("quad.obj", kQuadObj);
  std::string models;
  for (int copy = 0; copy < 20; ++copy) {
    const std::string mesh = copy % 2 ? dae : obj;
    models += "<model name=\"quad" + std::to_string(copy) + "\"><static>true</static><pose>" +
              std::to_string(copy) +
              " 0 0 0 0 0</pose><link name=\"l\"><visual name=\"v\"><geometry><mesh><uri>" + mesh +
              "</uri></mesh></geometry></visual></link></model>";
  }
  const WorldSpec world = parse("<sdf version=\"1.6\"><world name=\"w\">" + models + "</world></sdf>");
  ASSERT_EQ(world.models.size(), 20u);
  std::set<const TriangleMesh*> meshes;
  std::set<const Texture*> textures;
  for (const WorldModelSpec& model : world.models) {
    const TriangleMesh& mesh = *model.visuals.at(0).shape.mesh;
    meshes.insert(&mesh);
    for (const MeshMaterial& material : mesh.materials) {
      if (material.texture) textures.insert(material.texture.get());
    }
  }
  EXPECT_EQ(meshes.size(), 2u) << "one per file";
  EXPECT_EQ(textures.size(), 1u) << "both files name quadrants.png";
}

TEST(GazeboMaterials, NamesFromEveryPartOfGazeboMaterialGiveTheirColours) {
  const std::pair<const char*, Eigen::Vector4d> kExpected[] = {
      {"Gazebo/Indigo", {0.33, 0, 0.5, 1}},
      {"Gazebo/DarkYellow", {0.7, 0.7, 0, 1}},
      {"Gazebo/DarkGray", {0.175, 0.175, 0.175, 1}},
      {"Gazebo/BlackTransparent", {0, 0, 0, 0.5}},
      {"Gazebo/BlueLaser", {0, 0, 1, 0.4}},
      {"Gazebo/Pioneer2Body", {0.681193, 0.000923, 0.000923, 1}},
      {"Gazebo/Gold", {0.8, 0.64869, 0.120759, 1}},
  };
  for (const auto& [name, rgba] : kExpected) {
    const std::optional<Eigen::Vector4d> colour = gazeboMaterialColour(name);
    ASSERT_TRUE(colour) << name;
    EXPECT_TRUE(colour->isApprox(rgba)) << name << ": " << colour->transpose();
  }
  for (const char* textured : {"Gazebo/Wood", "Gazebo/Grass", "Gazebo/Road", "Gazebo/CeilingTiled"}) {
    EXPECT_TRUE(gazeboMaterialColour(textured)) << textured;
  }
  EXPECT_FALSE(gazeboMaterialColour("Gazebo/DepthMap")) << "a shader, not a surface";
}

TEST(GazeboMaterials, AnUnknownNameIsWarnedAboutOnceNamingIt) {
  std::vector<std::string> warnings;
  const std::string box = "<geometry><box><size>1 1 1</size></box></geometry>";
  const std::string script =
      "<material><script><uri>model://shop/materials/scripts</uri><name>Shop/Floor</name>"
      "</script></material>";
  const WorldSpec world = parse(
      "<sdf version=\"1.6\"><world name=\"w\"><model name=\"m\"><static>true</static>"
      "<link name=\"l\"><visual name=\"a\">" +
          box + script + "</visual><visual name=\"b\">" + box + script +
          "</visual></link></model></world></sdf>",
      &warnings);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_THAT(warnings[0], HasSubstr("unknown Gazebo material [Shop/Floor]"));
  EXPECT_TRUE(world.models.at(0).visuals.at(1).rgba.isApprox(Visual().rgba)) << "shown in the default grey";

  // A URDF's <gazebo reference> material: known ones colour the link, an unknown one warns once.
  const std::string link =
      R"(<link name="%"><inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1" ixy="0"
    ixz="0" iyz="0"/></inertial><visual><geometry><box size="1 1 1"/></geometry></visual></link>)";
  std::string urdf = "<robot name=\"r\">";
  for (const char* name : {"a", "b", "c"}) urdf += std::regex_replace(link, std::regex("%"), name);
  urdf += R"(<joint name="ab" type="fixed"><parent link="a"/><child link="b"/></joint>
    <joint name="ac" type="fixed"><parent link="a"/><child link="c"/></joint>
    <gazebo reference="a"><material>Gazebo/DarkYellow</material></gazebo>
    <gazebo reference="b"><material>Shop/Floor</material></gazebo>
    <gazebo reference="c"><material>Shop/Floor</material></gazebo></robot>)";
  warnings.clear();
  const ModelSpec model = parseModel(urdf, "materials.urdf", PackageResolver::fromEnvironment(), &warnings);
  EXPECT_TRUE(model.link("a")->visuals.at(0).rgba.isApprox(Eigen::Vector4d(0.7, 0.7, 0, 1)));
  EXPECT_EQ(model.link("a")->visuals.at(0).paint, MeshPaint::kUniform);
  ASSERT_EQ(warnings.size(), 1u) << ::testing::PrintToString(warnings);
  EXPECT_THAT(warnings[0], HasSubstr("<material>Shop/Floor</material> is neither a Gazebo material we know"));
}

// <material value="..."/> reads as <material>...</material>, as sdformat reads every such element (mu1 too).
TEST(GazeboMaterials, TheValueAttributeFormNamesTheMaterial) {
  const std::string urdf =
      R"(<robot name="r"><link name="a"><inertial><mass value="1"/><inertia ixx="1" iyy="1"
    izz="1" ixy="0" ixz="0" iyz="0"/></inertial><visual><geometry><box size="1 1 1"/></geometry></visual></link>
    <gazebo reference="a"><material value="Gazebo/DarkYellow"/></gazebo></robot>)";
  std::vector<std::string> warnings;
  const ModelSpec model = parseModel(urdf, "value_form.urdf", PackageResolver::fromEnvironment(), &warnings);
  EXPECT_TRUE(model.link("a")->visuals.at(0).rgba.isApprox(Eigen::Vector4d(0.7, 0.7, 0, 1)));
  EXPECT_EQ(warnings, std::vector<std::string>{});
}

// A material script's texture shows, from afar, as its mean colour times the script's colour: the script's
// own media folders and those its <uri>s name are searched, and a URDF finds scripts on the resource path.
TEST(GazeboMaterials, AScriptsTextureGivesItsMeanColourTimesTheScriptsColour) {
  TemporaryDirectory resource;  // a GAZEBO_RESOURCE_PATH folder
  fs::create_directories(resource.file("media/materials/scripts"));
  fs::create_directories(resource.file("media/materials/textures"));
  fs::create_directories(resource.file("pictures"));
  writePngFile(resource, "media/materials/textures/quadrants.png", quadrantImage());  // mean (0.5 0.5 0.25)
  Image blue{2, 2, std::vector<uint8_t>(16, 255)};
  for (size_t at = 0; at < blue.rgba.size(); at += 4) blue.rgba[at] = blue.rgba[at + 1] = 0;
  writePngFile(resource, "pictures/blue.png", blue);
  const auto block = [](const std::string& name, const std::string& pass) {
    return "material " + name + "\n{\n  technique\n  {\n    pass\n    {\n" + pass + "\n    }\n  }\n}\n";
  };
  resource.write("media/materials/scripts/shop.material",
                 block("Shop/Tiles", "texture_unit { texture quadrants.png }") +
                     block("Shop/DimTiles", "diffuse 0.5 0.5 0.5 1\ntexture_unit { texture quadrants.png }") +
                     block("Shop/Blue", "texture_unit { texture blue.png }") +
                     block("Shop/Lost", "diffuse 0 1 0 1\ntexture_unit { texture gone.png }"));
  GazeboEnvironment environment;
  environment.resource_path = {resource.file("")};
  const PackageResolver resolver({}, environment);
  int visuals_made = 0;
  const auto visual = [&](const std::string& name, const std::string& uris) {
    return "<visual name='v" + std::to_string(visuals_made++) +
           "'><geometry><box><size>1 1 1</size></box></geometry><material>" + "<script>" + uris + "<name>" +
           name + "</name></script></material></visual>";
  };
  const std::string scripts = "<uri>file://media/materials/scripts/shop.material</uri>";
  std::vector<std::string> warnings;
  const WorldSpec world = parseWorld(
      "<sdf version='1.6'><world name='w'><model name='m'><static>true</static><link name='l'>" +
          visual("Shop/Tiles", scripts) + visual("Shop/DimTiles", scripts) +
          visual("Shop/Blue", scripts + "<uri>file://" + resource.file("pictures") + "</uri>") +
          visual("Shop/Lost", scripts) + visual("Shop/Lost", scripts) + "</link></model></world></sdf>",
      "shop.world", resolver, &warnings);
  const std::vector<Visual>& visuals = world.models.at(0).visuals;
  ASSERT_EQ(visuals.size(), 5u);
  EXPECT_TRUE(visuals[0].rgba.isApprox(Eigen::Vector4d(0.5, 0.5, 0.25, 1))) << visuals[0].rgba.transpose();
  EXPECT_TRUE(visuals[1].rgba.isApprox(Eigen::Vector4d(0.25, 0.25, 0.125, 1))) << visuals[1].rgba.transpose();
  EXPECT_TRUE(visuals[2].rgba.isApprox(Eigen::Vector4d(0, 0, 1, 1))) << "found in its <uri>'s folder";
  EXPECT_TRUE(visuals[3].rgba.isApprox(Eigen::Vector4d(0, 1, 0, 1))) << "its colour, the texture missing";
  ASSERT_EQ(warnings.size(), 1u) << ::testing::PrintToString(warnings);
  EXPECT_THAT(warnings[0], HasSubstr("material [Shop/Lost]: its texture [gone.png] was not found"));
  EXPECT_THAT(warnings[0], HasSubstr("drawn in its colour"));
  // A URDF's <gazebo reference> material finds the resource path's scripts and textures.
  warnings.clear();
  const ModelSpec robot = parseModel(
      R"(<robot name="r"><link name="a"><inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1" ixy="0"
      ixz="0" iyz="0"/></inertial><visual><geometry><box size="1 1 1"/></geometry></visual></link>
      <gazebo reference="a"><material>Shop/Tiles</material></gazebo></robot>)",
      "shop.urdf", resolver, &warnings);
  EXPECT_TRUE(robot.link("a")->visuals.at(0).rgba.isApprox(Eigen::Vector4d(0.5, 0.5, 0.25, 1)));
  EXPECT_THAT(warnings, ::testing::IsEmpty());
}

}  // namespace
}  // namespace bullet_sim
