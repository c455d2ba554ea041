// Meshes as ROS tools read them: COLLADA in its file's axes (no up-axis turn), scaled by its <unit meter>;
// and read once for every model in the process that holds them.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include <Eigen/Geometry>

#include "bullet_sim/assets/mesh.h"

namespace bullet_sim {
namespace {

/// A COLLADA file holding one box of `size` (in the file's units) whose corner is at the origin.
std::string colladaBox(const std::string& up_axis, double meter, const Eigen::Vector3d& size) {
  std::ostringstream positions;
  for (int corner = 0; corner < 8; ++corner) {
    positions << ((corner & 1) ? size.x() : 0) << " " << ((corner & 2) ? size.y() : 0) << " "
              << ((corner & 4) ? size.z() : 0) << " ";
  }
  const std::string faces = "0 2 1 1 2 3 4 5 6 5 7 6 0 1 4 1 5 4 2 6 3 3 6 7 0 4 2 2 4 6 1 3 5 3 7 5";
  std::ostringstream dae;
  dae << "<?xml version='1.0'?><COLLADA xmlns='http://www.collada.org/2005/11/COLLADASchema' version='1.4.1'>"
      << "<asset><unit meter='" << meter << "' name='unit'/><up_axis>" << up_axis << "</up_axis></asset>"
      << "<library_geometries><geometry id='box'><mesh>"
      << "<source id='box-positions'><float_array id='box-array' count='24'>" << positions.str()
      << "</float_array><technique_common><accessor source='#box-array' count='8' stride='3'>"
      << "<param name='X' type='float'/><param name='Y' type='float'/><param name='Z' type='float'/>"
      << "</accessor></technique_common></source>"
      << "<vertices id='box-vertices'><input semantic='POSITION' source='#box-positions'/></vertices>"
      << "<triangles count='12'><input semantic='VERTEX' source='#box-vertices' offset='0'/><p>" << faces
      << "</p></triangles></mesh></geometry></library_geometries>"
      << "<library_visual_scenes><visual_scene id='scene'><node id='box-node'>"
      << "<instance_geometry url='#box'/></node></visual_scene></library_visual_scenes>"
      << "<scene><instance_visual_scene url='#scene'/></scene></COLLADA>";
  return dae.str();
}

Eigen::AlignedBox3d boundsOf(const std::string& dae_text, const std::string& name) {
  const std::filesystem::path path = std::filesystem::path(::testing::TempDir()) / name;
  std::ofstream(path) << dae_text;
  std::string error;
  const auto mesh = loadMesh(path.string(), Eigen::Vector3d::Ones(), &error);
  EXPECT_TRUE(mesh) << error;
  Eigen::AlignedBox3d bounds;
  if (mesh) {
    for (const auto& vertex : mesh->vertices) bounds.extend(vertex);
  }
  return bounds;
}

void expectBounds(const Eigen::AlignedBox3d& bounds, const Eigen::Vector3d& max, const std::string& what) {
  EXPECT_TRUE(bounds.min().isZero(1e-6)) << what << ": min " << bounds.min().transpose();
  EXPECT_TRUE(bounds.max().isApprox(max, 1e-6)) << what << ": max " << bounds.max().transpose();
}

// A jersey barrier drawn Z_UP stood 1.80 m tall, half underground, when assimp turned it to Y_UP.
TEST(Collada, AZUpFileKeepsItsAxes) {
  expectBounds(boundsOf(colladaBox("Z_UP", 1, {3.8, 0.6, 0.8}), "z_up.dae"), {3.8, 0.6, 0.8}, "Z_UP");
}

TEST(Collada, AYUpFileKeepsItsAxesToo) {
  expectBounds(boundsOf(colladaBox("Y_UP", 1, {1, 2, 3}), "y_up.dae"), {1, 2, 3}, "Y_UP");
}

TEST(Collada, TheUnitScalesTheVertices) {
  expectBounds(boundsOf(colladaBox("Z_UP", 0.01, {100, 50, 20}), "centimetres.dae"), {1, 0.5, 0.2},
               "Z_UP in centimetres");
  expectBounds(boundsOf(colladaBox("Y_UP", 0.0254, {10, 20, 30}), "inches.dae"), {0.254, 0.508, 0.762},
               "Y_UP in inches");
}

std::filesystem::path writeBox(const std::string& name, double size) {
  const std::filesystem::path path = std::filesystem::path(::testing::TempDir()) / name;
  std::ofstream(path) << colladaBox("Z_UP", 1, Eigen::Vector3d::Constant(size));
  return path;
}

// A fleet's next robot takes the meshes the first one holds, without importing the file again.
TEST(MeshCache, AnotherModelSharesAMeshThatIsStillHeld) {
  const std::filesystem::path path = writeBox("shared_box.dae", 0.5);
  std::string error;
  std::vector<std::string> first_warnings, second_warnings;
  MeshCache first, second;
  const auto held = first.load(path.string(), Eigen::Vector3d::Ones(), &error, &first_warnings);
  ASSERT_TRUE(held) << error;
  const auto shared = second.load(path.string(), Eigen::Vector3d::Ones(), &error, &second_warnings);
  EXPECT_EQ(shared.get(), held.get());
  EXPECT_EQ(second_warnings, first_warnings);
  const auto scaled = second.load(path.string(), Eigen::Vector3d::Constant(2), &error, nullptr);
  ASSERT_TRUE(scaled) << error;
  EXPECT_NE(scaled.get(), held.get()) << "another scale is another mesh";
}

// A mesh file edited between two spawns is read again: the second model gets the new shape.
TEST(MeshCache, AnEditedFileIsReadAgain) {
  const std::filesystem::path path = writeBox("edited_box.dae", 0.5);
  std::string error;
  MeshCache first, second;
  const auto before = first.load(path.string(), Eigen::Vector3d::Ones(), &error, nullptr);
  ASSERT_TRUE(before) << error;
  writeBox("edited_box.dae", 0.75);
  std::filesystem::last_write_time(path, std::filesystem::last_write_time(path) + std::chrono::seconds(1));
  const auto after = second.load(path.string(), Eigen::Vector3d::Ones(), &error, nullptr);
  ASSERT_TRUE(after) << error;
  Eigen::AlignedBox3d bounds;
  for (const auto& vertex : after->vertices) bounds.extend(vertex);
  EXPECT_TRUE(bounds.max().isApprox(Eigen::Vector3d::Constant(0.75), 1e-6)) << bounds.max().transpose();
}

}  // namespace
}  // namespace bullet_sim
