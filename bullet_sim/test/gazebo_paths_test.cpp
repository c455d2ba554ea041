// Gazebo's paths: model:// through GAZEBO_MODEL_PATH, the packages' gazebo_model_path exports, the models we
// ship and ~/.gazebo/models; model.config's choice of SDF file; worlds/... through GAZEBO_RESOURCE_PATH and
// gazebo_media_path exports; DAE and OBJ meshes in worlds; the stock models at their published sizes.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "bullet_sim/assets/gazebo_materials.h"
#include "bullet_sim/model/model_geometry.h"
#include "bullet_sim/model/model.h"
#include "bullet_sim/model/world.h"
#include "test_support.h"

namespace bullet_sim {
namespace {

namespace fs = std::filesystem;

constexpr double kExact = 1e-6;  // [m] for sizes the files state exactly (meshes are stored as floats)

const std::string& fixtures() {
  static const std::string root = test::packageFile("bullet_sim", "test/fixtures/gazebo_paths");
  return root;
}

/// A resolver whose package search path is the fixtures' packages (yard_gazebo, zoo_gazebo) and whose
/// home holds ~/.gazebo/models/lamp_post.
PackageResolver fixtureResolver(std::vector<std::string> gazebo_model_path = {},
                                std::vector<std::string> gazebo_resource_path = {}) {
  GazeboEnvironment environment;
  environment.model_path = std::move(gazebo_model_path);
  environment.resource_path = std::move(gazebo_resource_path);
  environment.home = fixtures() + "/home";
  return PackageResolver({fixtures() + "/packages"}, environment);
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

const WorldModelSpec& model(const WorldSpec& world, const std::string& name) {
  for (const auto& candidate : world.models) {
    if (candidate.name == name) return candidate;
  }
  throw std::runtime_error("world [" + world.name + "] has no model [" + name + "]");
}

/// The world-frame bounding box of a model's collisions (or visuals).
Eigen::AlignedBox3d extent(const WorldModelSpec& model, bool visuals = false) {
  Eigen::AlignedBox3d box;
  if (visuals) {
    for (const auto& visual : model.visuals)
      box.extend(boundingBox(visual.shape, model.pose * visual.origin));
  } else {
    for (const auto& collision : model.collisions) {
      box.extend(boundingBox(collision.shape, model.pose * collision.origin));
    }
  }
  return box;
}

void expectBox(const Eigen::AlignedBox3d& box, const Eigen::Vector3d& min, const Eigen::Vector3d& max) {
  EXPECT_TRUE(box.min().isApprox(min, kExact) || (box.min() - min).norm() < kExact) << box.min().transpose();
  EXPECT_TRUE(box.max().isApprox(max, kExact) || (box.max() - max).norm() < kExact) << box.max().transpose();
}

TEST(GazeboPaths, ModelPathIsTheEnvironmentThenExportsThenOurModelsThenHome) {
  const PackageResolver resolver = fixtureResolver({fixtures() + "/env_models"}, {fixtures() + "/resources"});
  const std::vector<std::string> expected_models = {
      fixtures() + "/env_models",
      fixtures() + "/packages/yard_gazebo/models",
      fixtures() + "/packages/zoo_gazebo/models",
      test::packageFile("bullet_sim", "models"),
      fixtures() + "/home/.gazebo/models",
  };
  EXPECT_EQ(resolver.gazeboPaths().modelPath(), expected_models);
  const std::vector<std::string> expected_resources = {fixtures() + "/resources",
                                                       fixtures() + "/packages/yard_gazebo"};
  EXPECT_EQ(resolver.gazeboPaths().resourcePath(), expected_resources);
}

TEST(GazeboPaths, ModelConfigPicksTheHighestVersionThatSdformatReads) {
  std::string error;
  const auto file = modelSdfFile(fixtures() + "/packages/yard_gazebo/models/crate", &error);
  ASSERT_TRUE(file) << error;
  EXPECT_EQ(*file, fixtures() + "/packages/yard_gazebo/models/crate/model.sdf")
      << "not model-1_4 nor model-2_0";
}

TEST(GazeboPaths, WorldFromAPackageExportLoadsItsModelsAndMeshes) {
  const PackageResolver resolver = fixtureResolver();
  std::string error;
  const auto path = findWorldFile("worlds/yard.world", resolver, &error);
  ASSERT_TRUE(path) << error;
  EXPECT_EQ(*path, fixtures() + "/packages/yard_gazebo/worlds/yard.world") << "through gazebo_media_path";
  std::vector<std::string> warnings;
  const WorldSpec world = loadWorld(*path, resolver, &warnings);
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  EXPECT_EQ(world.models.size(), 6u) << "ground plane, two crates, pillar, barrel, lamp post";

  // The crate's OBJ mesh, 0.5 x 0.4 x 0.3 m, is its collision and its visual; the second crate is turned.
  const WorldModelSpec& crate = model(world, "crate");
  ASSERT_EQ(crate.collisions.size(), 1u);
  EXPECT_EQ(crate.collisions[0].shape.type, Shape::Type::kMesh);
  expectBox(extent(crate), {1.75, -0.2, 0}, {2.25, 0.2, 0.3});
  expectBox(extent(crate, true), {1.75, -0.2, 0}, {2.25, 0.2, 0.3});
  EXPECT_EQ(crate.visuals.at(0).material, "Gazebo/Wood");
  expectBox(extent(model(world, "crate_2")), {-2.2, -0.25, 0}, {-1.8, 0.25, 0.3});

  // The pillar's COLLADA mesh is in centimetres (<unit meter="0.01">), scaled 2 x 1 x 1 by the SDF.
  expectBox(extent(model(world, "pillar")), {-0.2, 2.9, 0}, {0.2, 3.1, 1.0});
  expectBox(extent(model(world, "pillar"), true), {-0.2, 2.9, 0}, {0.2, 3.1, 1.0});

  // The barrel from the second package's export, the lamp post from ~/.gazebo/models.
  expectBox(extent(model(world, "barrel")), {-0.3, -3.3, 0.05}, {0.3, -2.7, 0.95});
  expectBox(extent(model(world, "lamp_post")), {3.95, 3.95, -1}, {4.05, 4.05, 2});
}

TEST(GazeboPaths, GazeboModelPathComesBeforeThePackagesExports) {
  const WorldSpec world = parseWorld(
      "<sdf version='1.6'><world name='w'><include><uri>model://crate</uri></include></world></sdf>",
      "inline.world", fixtureResolver({fixtures() + "/env_models"}), nullptr);
  ASSERT_EQ(world.models.size(), 1u);
  EXPECT_EQ(world.models[0].name, "env_crate");
}

TEST(GazeboPaths, ResourcePathFindsWorldsBeforeOurs) {
  std::string error;
  const auto found =
      findWorldFile("worlds/resource.world", fixtureResolver({}, {fixtures() + "/resources"}), &error);
  ASSERT_TRUE(found) << error;
  EXPECT_EQ(*found, fixtures() + "/resources/worlds/resource.world");
  // gazebo_ros's default world_name: our empty world stands in for Gazebo's.
  const auto empty = findWorldFile("worlds/empty.world", PackageResolver::fromEnvironment(), &error);
  ASSERT_TRUE(empty) << error;
  EXPECT_EQ(*empty, test::packageFile("bullet_sim", "worlds/empty.world"));
}

// Gazebo's media folder leads the packages' gazebo_media_path exports: worlds/empty.world is Gazebo's own
// (ours stands in for it) even where a package exports its own worlds/empty.world.
TEST(GazeboPaths, OurWorldsComeBeforeThePackagesExportsAndAfterTheEnvironment) {
  GazeboEnvironment environment;
  environment.home = fixtures() + "/home";
  const std::string ours = test::packageFile("bullet_sim", "");
  const PackageResolver resolver(
      {fixtures() + "/packages", fs::path(ours).parent_path().parent_path().string()}, environment);
  std::string error;
  const auto empty = findWorldFile("worlds/empty.world", resolver, &error);
  ASSERT_TRUE(empty) << error;
  EXPECT_EQ(*empty, test::packageFile("bullet_sim", "worlds/empty.world")) << "not yard_gazebo's";
  const auto yard = findWorldFile("worlds/yard.world", resolver, &error);
  ASSERT_TRUE(yard) << error;
  EXPECT_EQ(*yard, fixtures() + "/packages/yard_gazebo/worlds/yard.world");
  environment.resource_path = {fixtures() + "/resources"};
  const PackageResolver with_variable({fixtures() + "/packages"}, environment);
  EXPECT_EQ(with_variable.gazeboPaths().resourcePath().front(), fixtures() + "/resources");
}

TEST(GazeboPaths, ModelUrisResolveForUrdfMeshesToo) {
  const PackageResolver resolver = fixtureResolver();
  std::string error;
  const auto mesh = resolver.resolve("model://pillar/meshes/pillar.dae", &error);
  ASSERT_TRUE(mesh) << error;
  EXPECT_EQ(*mesh, fixtures() + "/packages/yard_gazebo/models/pillar/meshes/pillar.dae");

  EXPECT_FALSE(resolver.resolve("model://pillar/meshes/missing.dae", &error));
  EXPECT_TRUE(contains(error, "model [pillar] has no file [meshes/missing.dae]")) << error;
  EXPECT_TRUE(contains(error, fixtures() + "/packages/yard_gazebo/models")) << error;
  EXPECT_FALSE(resolver.resolve("model://pilar", &error));
  EXPECT_TRUE(contains(error, "unknown model [pilar] (did you mean [pillar]?)")) << error;
}

TEST(GazeboPaths, ModelFolderWithoutModelConfigIsAnError) {
  try {
    parseWorld(
        "<sdf version='1.6'><world name='w'><include><uri>model://folder_without_config</uri></include>"
        "</world></sdf>",
        "inline.world", fixtureResolver({fixtures() + "/env_models"}), nullptr);
    FAIL() << "a model folder without model.config loaded";
  } catch (const SpecError& error) {
    EXPECT_TRUE(contains(error.what(), "folder_without_config] has no model.config")) << error.what();
    EXPECT_TRUE(contains(error.what(), "<sdf version=\"1.6\">model.sdf</sdf>")) << error.what();
  }
}

TEST(FindModel, PrintsTheSdfFileOfAModelOrWhereItLooked) {
  const std::string tool = std::string("GAZEBO_MODEL_PATH=") + fixtures() + "/env_models " + FIND_MODEL;
  const test::CommandResult found = test::run(tool + " crate");
  EXPECT_EQ(found.status, 0) << found.errors;
  EXPECT_EQ(found.output, fixtures() + "/env_models/crate/model.sdf\n");
  const test::CommandResult shipped = test::run(tool + " cafe_table");
  EXPECT_EQ(shipped.output, test::packageFile("bullet_sim", "models/cafe_table/model.sdf") + "\n");

  const test::CommandResult unknown = test::run(tool + " crat");
  EXPECT_EQ(unknown.status, 1);
  EXPECT_TRUE(contains(unknown.errors, "unknown model [crat] (did you mean [crate]?)")) << unknown.errors;
  EXPECT_TRUE(contains(unknown.errors, fixtures() + "/env_models")) << unknown.errors;

  const test::CommandResult path = test::run(tool + " --path");
  EXPECT_EQ(path.output.substr(0, path.output.find('\n')), fixtures() + "/env_models");
  EXPECT_TRUE(contains(test::run(tool + " --list").output, "\ncrate\n"));
  EXPECT_EQ(test::run(tool).status, 2) << "usage";
}

TEST(GazeboPaths, MaterialScriptsFromModelFoldersAndTheResourcePathGiveColours) {
  std::vector<std::string> warnings;
  const auto visual = [](const std::string& uri, const std::string& name) {
    return "<visual name='" + name +
           "'><geometry><box><size>1 1 1</size></box></geometry><material><script>"
           "<uri>" +
           uri + "</uri><name>" + name + "</name></script></material></visual>";
  };
  const WorldSpec world =
      parseWorld("<sdf version='1.6'><world name='w'><model name='m'><static>true</static><link name='l'>" +
                     visual("model://crate/materials/scripts", "Yard/Rust") +
                     visual("model://crate/materials/scripts", "Yard/DarkRust") +
                     visual("file://media/materials/scripts/yard.material", "Yard/Grass") +
                     visual("file://media/materials/scripts/yard.material", "Yard/Nothing") +
                     "</link></model></world></sdf>",
                 "inline.world", fixtureResolver(), &warnings);
  const std::vector<Visual>& visuals = world.models.at(0).visuals;
  ASSERT_EQ(visuals.size(), 4u);
  EXPECT_TRUE(visuals[0].rgba.isApprox(Eigen::Vector4d(0.6, 0.3, 0.1, 1))) << "its diffuse colour";
  EXPECT_TRUE(visuals[1].rgba.isApprox(Eigen::Vector4d(0.6, 0.3, 0.1, 1))) << "inherited from Yard/Rust";
  EXPECT_TRUE(visuals[2].rgba.isApprox(Eigen::Vector4d(0.1, 0.5, 0.1, 1))) << "its ambient colour";
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_TRUE(contains(warnings[0], "material [Yard/DarkRust]: its texture [rust.png] was not found"))
      << warnings[0];
  EXPECT_TRUE(contains(warnings[0], "drawn in its colour")) << warnings[0];
  EXPECT_TRUE(contains(warnings[1], "unknown Gazebo material [Yard/Nothing]")) << warnings[1];
}

// Gazebo loads every script in media/materials/scripts of its resource path for every visual: a URDF's
// <gazebo reference><material> and an SDF script whose own <uri>s do not define the name find them there.
TEST(GazeboPaths, MaterialScriptsOnTheResourcePathColourUrdfAndSdfVisuals) {
  const std::string urdf =
      R"(<robot name="r"><link name="a"><inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1" ixy="0"
      ixz="0" iyz="0"/></inertial><visual><geometry><box size="1 1 1"/></geometry></visual></link>
      <gazebo reference="a"><material>Yard/Grass</material></gazebo></robot>)";
  std::vector<std::string> warnings;
  const ModelSpec robot = parseModel(urdf, "yard.urdf", fixtureResolver(), &warnings);
  EXPECT_TRUE(robot.link("a")->visuals.at(0).rgba.isApprox(Eigen::Vector4d(0.1, 0.5, 0.1, 1)));
  EXPECT_EQ(robot.link("a")->visuals.at(0).paint, MeshPaint::kUniform);
  const WorldSpec world = parseWorld(
      "<sdf version='1.6'><world name='w'><model name='m'><static>true</static><link name='l'>"
      "<visual name='v'><geometry><box><size>1 1 1</size></box></geometry><material><script>"
      "<uri>model://crate/materials/scripts</uri><name>Yard/Grass</name></script></material></visual>"
      "</link></model></world></sdf>",
      "inline.world", fixtureResolver(), &warnings);
  EXPECT_TRUE(world.models.at(0).visuals.at(0).rgba.isApprox(Eigen::Vector4d(0.1, 0.5, 0.1, 1)));
  EXPECT_TRUE(warnings.empty()) << warnings.at(0);
  // Without the export that brings the script, the name is unknown: one warning each.
  GazeboEnvironment environment;
  environment.home = fixtures() + "/home";
  const PackageResolver bare({}, environment);
  const ModelSpec plain = parseModel(urdf, "yard.urdf", bare, &warnings);
  EXPECT_TRUE(plain.link("a")->visuals.at(0).rgba.isApprox(Visual().rgba)) << "the URDF colour is kept";
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_TRUE(contains(warnings[0], "<material>Yard/Grass</material> is neither")) << warnings[0];
}

/// A stock model and the extent of its collisions at the origin, from the sizes Gazebo's model publishes.
struct StockModel {
  std::string name;
  Eigen::Vector3d min, max;
};

class StockModels : public ::testing::TestWithParam<StockModel> {};

TEST_P(StockModels, LoadWithoutWarningsAtTheirPublishedSizes) {
  std::vector<std::string> warnings;
  const WorldSpec world = parseWorld("<sdf version='1.6'><world name='w'><include><uri>model://" +
                                         GetParam().name + "</uri></include></world></sdf>",
                                     "inline.world", PackageResolver::fromEnvironment(), &warnings);
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  const WorldModelSpec& stock = model(world, GetParam().name);
  EXPECT_TRUE(stock.is_static);
  expectBox(extent(stock), GetParam().min, GetParam().max);
  EXPECT_FALSE(stock.visuals.empty());
  for (const auto& visual : stock.visuals) {
    EXPECT_TRUE(gazeboMaterialColour(visual.material)) << "[" << visual.material << "] has a colour";
  }
}

const StockModel kStockModels[] = {
    {"cafe_table", {-0.4565, -0.4565, 0}, {0.4565, 0.4565, 0.775}},
    {"bookshelf", {-0.46, -0.395, 0}, {0.46, 0.01, 1.2}},
    {"jersey_barrier", {-2.03271, -0.40535, 0}, {2.03271, 0.40535, 1.143}},
    {"construction_cone", {-0.2515, -0.2515, 0}, {0.2515, 0.2515, 1.082}},
};

INSTANTIATE_TEST_SUITE_P(Shipped, StockModels, ::testing::ValuesIn(kStockModels),
                         [](const ::testing::TestParamInfo<StockModel>& info) { return info.param.name; });

}  // namespace
}  // namespace bullet_sim
