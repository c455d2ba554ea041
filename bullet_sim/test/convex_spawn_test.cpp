// What keeps an arm's first spawn short: a link fixed to the world is not split into convex parts (it never
// moves, so it collides by its triangles, as Gazebo collides it), and the meshes of one spawn split side by
// side, with the same parts whatever the number of threads.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <array>
#include <filesystem>
#include <fstream>

#include "bullet_sim/assets/mesh.h"
#include "bullet_sim/model/convex_decomposition.h"
#include "bullet_sim/simulation/simulation.h"
#include "test_support.h"

namespace bullet_sim {
namespace {

namespace fs = std::filesystem;

using test::TemporaryFolder;

constexpr double kFloorTop = 0.05;  // [m] the trough's floor, inside
constexpr double kWallTop = 0.3;    // [m] its walls' tops
constexpr double kBoxSize = 0.1;    // [m] the box dropped into it

/// An ASCII STL of axis-aligned boxes, each {min x y z, max x y z}, 12 triangles each, facing out.
void writeBoxes(const fs::path& path, const std::vector<std::array<double, 6>>& boxes) {
  std::ofstream out(path);
  out << "solid boxes\n";
  for (const auto& b : boxes) {
    const auto corner = [&](int k) {
      return Eigen::Vector3d(b[(k & 1) ? 3 : 0], b[(k & 2) ? 4 : 1], b[(k & 4) ? 5 : 2]);
    };
    // Each face as its corners in order around it (corner k: max x, y, z where its bits 0, 1, 2 are set).
    const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                             {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& face : faces) {
      for (const std::array<int, 3> triangle : {std::array<int, 3>{face[0], face[1], face[2]},
                                                std::array<int, 3>{face[0], face[2], face[3]}}) {
        out << "facet normal 0 0 0\nouter loop\n";
        for (int k : triangle) out << "vertex " << corner(k).transpose() << "\n";
        out << "endloop\nendfacet\n";
      }
    }
  }
  out << "endsolid boxes\n";
}

/// A U-shaped trough, 0.5 m wide, 0.6 m long, its inside 0.3 m wide from kFloorTop to kWallTop: its hull is a
/// box, which would hold a box dropped into it at the walls' tops.
void writeTrough(const fs::path& path) {
  writeBoxes(path, {{-0.25, -0.3, 0, -0.15, 0.3, kWallTop},
                    {-0.15, -0.3, 0, 0.15, 0.3, kFloorTop},
                    {0.15, -0.3, 0, 0.25, 0.3, kWallTop}});
}

/// The trough as a robot's only link, fixed to the world.
std::string troughUrdf(const fs::path& mesh) {
  return R"(<robot name="trough">
  <link name="world"/>
  <joint name="anchor" type="fixed"><parent link="world"/><child link="trough"/></joint>
  <link name="trough">
    <collision><geometry><mesh filename=")" +
         mesh.string() + R"("/></geometry></collision>
  </link>
</robot>)";
}

std::string boxUrdf() {
  const std::string size = std::to_string(kBoxSize);
  return R"(<robot name="box"><link name="box">
  <inertial><mass value="1"/><inertia ixx="0.002" iyy="0.002" izz="0.002" ixy="0" ixz="0" iyz="0"/></inertial>
  <collision><geometry><box size=")" +
         size + " " + size + " " + size + R"("/></geometry></collision>
</link></robot>)";
}

TEST(WorldFixedMesh, IsNotSplitAndABoxDroppedIntoItRestsOnItsFloor) {
  TemporaryFolder folder;
  writeTrough(folder.path() / "trough.stl");
  SimulationOptions options;
  options.convex_cache_dir = (folder.path() / "convex").string();
  Simulation simulation(test::shippedWorld("empty.world"), options);
  SpawnPose at_origin;
  at_origin.z = 0;
  const fs::path mesh = folder.path() / "trough.stl";
  Robot& trough = simulation.spawn("trough", test::parseQuietly(troughUrdf(mesh), "trough"), at_origin);
  const Shape& shape = trough.body().spec().link("trough")->collisions.at(0).shape;
  ASSERT_EQ(shape.type, Shape::Type::kMesh);
  EXPECT_FALSE(shape.convex_parts);                      // no parts,
  EXPECT_FALSE(fs::exists(options.convex_cache_dir));  // and no CoACD run to make them
  SpawnPose above;
  above.z = kWallTop + 0.1;
  Robot& box = simulation.spawn("box", test::parseQuietly(boxUrdf(), "box"), above);
  for (int k = 0; k < 1500; ++k) simulation.step();
  // It fell between the walls onto the floor (by its hull it would sit on the walls' tops, at 0.35 m).
  const Eigen::Vector3d rest = box.body().linkPose("box").translation();
  EXPECT_NEAR(rest.z(), kFloorTop + kBoxSize / 2, 2e-3);
  EXPECT_NEAR(rest.x(), 0, 1e-3);
  EXPECT_NEAR(rest.y(), 0, 1e-3);
}

/// The six-axis arm's meshes that CoACD splits into several parts.
std::vector<TriangleMesh> armMeshes() {
  std::vector<TriangleMesh> meshes;
  for (const char* link : {"forearm_link", "shoulder_link", "upper_arm_link"}) {
    std::string error;
    auto mesh = loadMesh(test::fixture(std::string("self_collision/meshes/") + link + ".stl"),
                         Eigen::Vector3d::Ones(), &error);
    if (!mesh) throw std::runtime_error(error);
    meshes.push_back(*mesh);
  }
  return meshes;
}

TEST(ConvexDecomposer, SplitsTheSamePartsWithOneThreadAsWithTwo) {
  const std::vector<TriangleMesh> meshes = armMeshes();
  std::vector<const TriangleMesh*> batch;
  for (const TriangleMesh& mesh : meshes) batch.push_back(&mesh);
  batch.push_back(&meshes[0]);  // a mesh twice in one spawn is split once
  TemporaryFolder one_cache, two_cache;
  std::vector<std::string> one_warnings, two_warnings;
  const auto one = ConvexDecomposer(one_cache.path().string(), 1).decomposeAll(batch, Limits{}, one_warnings);
  const auto two = ConvexDecomposer(two_cache.path().string(), 2).decomposeAll(batch, Limits{}, two_warnings);
  ASSERT_EQ(one.size(), batch.size());
  ASSERT_EQ(two.size(), batch.size());
  for (size_t m = 0; m < batch.size(); ++m) {
    ASSERT_TRUE(one[m]) << one_warnings[m];
    ASSERT_TRUE(two[m]) << two_warnings[m];
    EXPECT_GE(one[m]->hulls.size(), 2u) << m;
    EXPECT_EQ(one[m]->hulls, two[m]->hulls) << m;
  }
  EXPECT_EQ(two[3], two[0]);
  // The cache holds one entry per mesh, whichever process ended first.
  size_t entries = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(two_cache.path())) ++entries;
  EXPECT_EQ(entries, meshes.size());
}

}  // namespace
}  // namespace bullet_sim
