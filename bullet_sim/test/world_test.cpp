// Checks the SDF world layer against the geometry the shipped worlds document, and that every kind of broken
// world fails with a message naming the file and the offending element.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "bullet_sim/assets/gazebo_materials.h"
#include "bullet_sim/model/model_geometry.h"
#include "bullet_sim/model/world.h"

namespace bullet_sim {
namespace {

constexpr double kExact = 1e-9;  // [m] for dimensions the world files state exactly

struct Box3 {
  Eigen::Vector3d min;
  Eigen::Vector3d max;
};

std::string packageDirectory(const std::string& package) {
  const auto directory = PackageResolver::fromEnvironment().packageDirectory(package);
  return directory ? *directory : "<no package [" + package + "] in ROS_PACKAGE_PATH>";
}

std::string fixture(const std::string& name) {
  return packageDirectory("bullet_sim") + "/test/fixtures/worlds/" + name;
}

WorldSpec load(const std::string& path, std::vector<std::string>* warnings = nullptr) {
  return loadWorld(path, PackageResolver::fromEnvironment(), warnings);
}

WorldSpec parse(const std::string& text, std::vector<std::string>* warnings = nullptr) {
  return parseWorld(text, "inline.world", PackageResolver::fromEnvironment(), warnings);
}

/// The SpecError message of loading `path`, or "" when it loads.
std::string loadError(const std::string& path) {
  try {
    load(path);
  } catch (const SpecError& error) {
    return error.what();
  }
  return "";
}

const WorldModelSpec* findModel(const WorldSpec& world, const std::string& name) {
  for (const auto& model : world.models) {
    if (model.name == name) return &model;
  }
  return nullptr;
}

/// World-frame bounding box of a shape placed at `pose` (model_geometry's, checked on its own below).
Box3 boxOf(const Shape& shape, const Eigen::Isometry3d& pose) {
  const Eigen::AlignedBox3d box = boundingBox(shape, pose);
  EXPECT_FALSE(box.isEmpty()) << "no bounding box for shape type " << static_cast<int>(shape.type);
  return {box.min(), box.max()};
}

/// Bounding boxes of every collision of the world, except the ground plane.
std::vector<Box3> obstacleBoxes(const WorldSpec& world) {
  std::vector<Box3> boxes;
  for (const auto& model : world.models) {
    for (const auto& collision : model.collisions) {
      if (collision.shape.type == Shape::Type::kPlane) continue;
      boxes.push_back(boxOf(collision.shape, model.pose * collision.origin));
    }
  }
  return boxes;
}

bool contains(const Box3& box, const Eigen::Vector3d& point) {
  return (point.array() >= box.min.array()).all() && (point.array() <= box.max.array()).all();
}

/// Distance [m] in the xy-plane from (x, y) to the box's footprint.
double footprintDistance(const Box3& box, double x, double y) {
  const double dx = std::max({box.min.x() - x, 0.0, x - box.max.x()});
  const double dy = std::max({box.min.y() - y, 0.0, y - box.max.y()});
  return std::hypot(dx, dy);
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(WorldSpec, EmptyWorldHasOnlyTheGroundPlane) {
  std::vector<std::string> warnings;
  const WorldSpec world = load(packageDirectory("bullet_sim") + "/worlds/empty.world", &warnings);
  EXPECT_TRUE(warnings.empty()) << (warnings.empty() ? "" : warnings.front());
  EXPECT_EQ(world.name, "default");
  EXPECT_DOUBLE_EQ(world.max_step_size, 0.001);
  EXPECT_DOUBLE_EQ(world.real_time_factor, 1.0);
  EXPECT_TRUE(world.gravity.isApprox(Eigen::Vector3d(0, 0, -9.81)));  // DESIGN §4; SDF's default is -9.8
  ASSERT_EQ(world.models.size(), 1u) << "the sun is a light, not a model";
  const WorldModelSpec& ground = world.models.front();
  EXPECT_EQ(ground.name, "ground_plane");
  EXPECT_TRUE(ground.is_static);
  ASSERT_EQ(ground.collisions.size(), 1u);
  EXPECT_EQ(ground.collisions[0].shape.type, Shape::Type::kPlane);
  EXPECT_TRUE(ground.collisions[0].shape.plane_normal.isApprox(Eigen::Vector3d::UnitZ()));
  EXPECT_TRUE((ground.pose * ground.collisions[0].origin).isApprox(Eigen::Isometry3d::Identity()));

  // The visual plane becomes a thin 100 x 100 m grey box whose top face is the floor.
  ASSERT_EQ(ground.visuals.size(), 1u);
  const Visual& floor = ground.visuals[0];
  EXPECT_EQ(floor.shape.type, Shape::Type::kBox);
  EXPECT_DOUBLE_EQ(floor.shape.box_size.x(), 100);
  EXPECT_DOUBLE_EQ(floor.shape.box_size.y(), 100);
  EXPECT_NEAR(boxOf(floor.shape, floor.origin).max.z(), 0, kExact);
  EXPECT_EQ(floor.material, "Gazebo/Grey");
  EXPECT_TRUE(floor.rgba.isApprox(*gazeboMaterialColour("Gazebo/Grey")));
}

TEST(WorldSpec, TestRoomInnerFacesAreAtThePublishedCoordinates) {
  const WorldSpec world = load(packageDirectory("bullet_sim") + "/worlds/test_room.world");
  const std::vector<Box3> walls = obstacleBoxes(world);
  ASSERT_EQ(walls.size(), 4u);
  // The face of each wall that looks into the room, found from the wall's position.
  std::vector<double> east, west, north, south;
  for (const Box3& wall : walls) {
    const Eigen::Vector3d centre = (wall.min + wall.max) / 2;
    EXPECT_NEAR(wall.min.z(), 0.0, kExact);
    EXPECT_NEAR(wall.max.z(), 1.0, kExact);
    const Eigen::Vector3d size = wall.max - wall.min;
    EXPECT_NEAR(std::min(size.x(), size.y()), 0.1, kExact) << "wall thickness";
    if (centre.x() > 2.5) east.push_back(wall.min.x());
    if (centre.x() < -2.5) west.push_back(wall.max.x());
    if (centre.y() > 1.5) north.push_back(wall.min.y());
    if (centre.y() < -1.5) south.push_back(wall.max.y());
  }
  ASSERT_EQ(east.size(), 1u);
  ASSERT_EQ(west.size(), 1u);
  ASSERT_EQ(north.size(), 1u);
  ASSERT_EQ(south.size(), 1u);
  EXPECT_NEAR(east[0], 3.0, kExact);
  EXPECT_NEAR(west[0], -3.0, kExact);
  EXPECT_NEAR(north[0], 2.0, kExact);
  EXPECT_NEAR(south[0], -2.0, kExact);
}

TEST(WorldSpec, TestRoomIsClosed) {
  const WorldSpec world = load(packageDirectory("bullet_sim") + "/worlds/test_room.world");
  const std::vector<Box3> walls = obstacleBoxes(world);
  // Walk a rectangle through the middle of the walls' thickness, corners included, every 5 mm at 0.5 m high:
  // every point is inside a wall, so no ray from inside can leave the room.
  const double x_edge = 3.05, y_edge = 2.05, step = 0.005;
  std::vector<Eigen::Vector3d> ring;
  for (double t = -1; t <= 1 + 1e-12; t += step / x_edge) {
    ring.emplace_back(t * x_edge, y_edge, 0.5);
    ring.emplace_back(t * x_edge, -y_edge, 0.5);
  }
  for (double t = -1; t <= 1 + 1e-12; t += step / y_edge) {
    ring.emplace_back(x_edge, t * y_edge, 0.5);
    ring.emplace_back(-x_edge, t * y_edge, 0.5);
  }
  for (const Eigen::Vector3d& point : ring) {
    const bool in_a_wall =
        std::any_of(walls.begin(), walls.end(), [&](const Box3& wall) { return contains(wall, point); });
    EXPECT_TRUE(in_a_wall) << "gap in the walls at (" << point.transpose() << ")";
  }
}

class HomeWorld : public ::testing::Test {
 protected:
  void SetUp() override {
    world_ = load(packageDirectory("bullet_sim_bringup") + "/worlds/home.world", &warnings_);
  }
  WorldSpec world_;
  std::vector<std::string> warnings_;
};

TEST_F(HomeWorld, LoadsWithoutWarningsAndIsFurnished) {
  EXPECT_TRUE(warnings_.empty()) << warnings_.front();
  EXPECT_DOUBLE_EQ(world_.max_step_size, 0.001);
  ASSERT_NE(findModel(world_, "ground_plane"), nullptr);
  ASSERT_NE(findModel(world_, "walls"), nullptr);
  const size_t furniture = world_.models.size() - 2;
  EXPECT_GE(furniture, 10u);
  EXPECT_LE(furniture, 15u);
}

TEST_F(HomeWorld, IsStaticBoxesAndCylinders) {
  for (const auto& model : world_.models) {
    EXPECT_TRUE(model.is_static) << model.name;
    EXPECT_FALSE(model.collisions.empty()) << model.name;
    EXPECT_EQ(model.collisions.size(), model.visuals.size()) << model.name << ": one visual per collision";
    for (const auto& collision : model.collisions) {
      const Shape::Type type = collision.shape.type;
      EXPECT_TRUE(type == Shape::Type::kBox || type == Shape::Type::kCylinder ||
                  (type == Shape::Type::kPlane && model.name == "ground_plane"))
          << model.name << " has shape type " << static_cast<int>(type);
    }
  }
}

TEST_F(HomeWorld, FlatIsTenByEightMetresAndEverythingIsInside) {
  const std::vector<Box3> obstacles = obstacleBoxes(world_);
  Box3 all{Eigen::Vector3d::Constant(1e9), Eigen::Vector3d::Constant(-1e9)};
  for (const Box3& box : obstacles) {
    all.min = all.min.cwiseMin(box.min);
    all.max = all.max.cwiseMax(box.max);
    EXPECT_GE(box.min.z(), -kExact) << "nothing is below the floor";
  }
  // The outer walls' outer faces: 10 x 8 m of free floor plus 0.1 m of wall on each side.
  EXPECT_NEAR(all.min.x(), -5.1, kExact);
  EXPECT_NEAR(all.max.x(), 5.1, kExact);
  EXPECT_NEAR(all.min.y(), -4.1, kExact);
  EXPECT_NEAR(all.max.y(), 4.1, kExact);
  EXPECT_NEAR(all.max.z(), 2.5, kExact) << "wall height";
}

TEST_F(HomeWorld, TwoMetresAroundTheOriginAreFree) {
  for (const auto& model : world_.models) {
    for (const auto& collision : model.collisions) {
      if (collision.shape.type == Shape::Type::kPlane) continue;
      const Box3 box = boxOf(collision.shape, model.pose * collision.origin);
      EXPECT_GT(footprintDistance(box, 0, 0), 2.0)
          << model.name << " intrudes on the free circle at the origin";
    }
  }
}

TEST_F(HomeWorld, DoorwaysLetAWheelchairThrough) {
  // The doorways the file's comment documents: a 1.2 m opening through a 0.1 m thick wall, floor to 2 m.
  struct Doorway {
    std::string name;
    Box3 opening;
  };
  const double margin = 0.001;  // [m] so the door jambs themselves do not count
  const std::vector<Doorway> doorways = {
      {"kitchen - living room", {{-2.35, -1.6 + margin, 0}, {-2.25, -0.4 - margin, 2}}},
      {"bedroom - hall", {{-2.35, 2.65 + margin, 0}, {-2.25, 3.85 - margin, 2}}},
      {"living room - hall", {{-0.6 + margin, 2.45, 0}, {0.6 - margin, 2.55, 2}}},
  };
  for (const Doorway& doorway : doorways) {
    for (const Box3& box : obstacleBoxes(world_)) {
      const bool overlaps = (box.min.array() < doorway.opening.max.array()).all() &&
                            (box.max.array() > doorway.opening.min.array()).all();
      EXPECT_FALSE(overlaps) << "doorway [" << doorway.name << "] is blocked";
    }
  }
}

TEST(WorldSpec, FoldsModelLinkAndCollisionPoses) {
  const WorldSpec world = parse(R"(<sdf version="1.6"><world name="w">
    <model name="crate">
      <static>true</static>
      <pose>1 2 0 0 0 1.5707963267948966</pose>
      <link name="body">
        <pose>1 0 0 0 0 0</pose>
        <collision name="lid"><pose>0 0 0.5 0 0 0</pose><geometry><box><size>1 2 0.1</size></box></geometry></collision>
        <visual name="lid"><pose>0 0 0.5 0 0 0</pose><geometry><sphere><radius>0.3</radius></sphere></geometry></visual>
      </link>
      <model name="handle">
        <pose>0 1 0 0 0 0</pose>
        <link name="grip">
          <collision name="bar"><geometry><cylinder><radius>0.02</radius><length>0.3</length></cylinder></geometry></collision>
        </link>
      </model>
    </model>
  </world></sdf>)");
  ASSERT_EQ(world.models.size(), 1u);
  const WorldModelSpec& crate = world.models[0];
  EXPECT_TRUE(crate.pose.translation().isApprox(Eigen::Vector3d(1, 2, 0)));
  ASSERT_EQ(crate.collisions.size(), 2u) << "the nested model's collision is folded into the crate";
  // Model frame: link at (1, 0, 0), collision 0.5 above it.
  EXPECT_TRUE(crate.collisions[0].origin.translation().isApprox(Eigen::Vector3d(1, 0, 0.5)));
  EXPECT_TRUE(crate.collisions[0].shape.box_size.isApprox(Eigen::Vector3d(1, 2, 0.1)));
  // World frame: the model's 90 degree yaw turns its +x into world +y.
  EXPECT_TRUE((crate.pose * crate.collisions[0].origin).translation().isApprox(Eigen::Vector3d(1, 3, 0.5)));
  EXPECT_TRUE(crate.collisions[1].origin.translation().isApprox(Eigen::Vector3d(0, 1, 0)));
  EXPECT_EQ(crate.collisions[1].shape.type, Shape::Type::kCylinder);
  EXPECT_DOUBLE_EQ(crate.collisions[1].shape.radius, 0.02);
  EXPECT_DOUBLE_EQ(crate.collisions[1].shape.length, 0.3);
  ASSERT_EQ(crate.visuals.size(), 1u);
  EXPECT_EQ(crate.visuals[0].shape.type, Shape::Type::kSphere);
  EXPECT_TRUE(crate.visuals[0].origin.translation().isApprox(Eigen::Vector3d(1, 0, 0.5)));
  // The links, for the world API: a nested model's carry its name.
  ASSERT_EQ(crate.links.size(), 2u);
  EXPECT_EQ(crate.links[0].name, "body");
  EXPECT_TRUE(crate.links[0].pose.translation().isApprox(Eigen::Vector3d(1, 0, 0)));
  EXPECT_EQ(crate.links[0].collisions, std::vector<std::string>{"lid"});
  EXPECT_EQ(crate.links[1].name, "handle::grip");
  EXPECT_TRUE(crate.links[1].pose.translation().isApprox(Eigen::Vector3d(0, 1, 0)));
}

/// A world whose <physics> holds `tags`.
std::string withPhysics(const std::string& tags) {
  return R"(<sdf version="1.6"><world name="w"><physics type="ode">)" + tags + "</physics></world></sdf>";
}

// Gazebo steps a world of type dart or simbody on that engine; here Bullet steps it, and one warning says so.
TEST(WorldSpec, APhysicsTypeOtherThanOdeOrBulletIsSteppedByBulletWithAWarning) {
  for (const std::string type : {"dart", "simbody"}) {
    std::vector<std::string> warnings;
    parse(R"(<sdf version="1.6"><world name="w"><physics type=")" + type +
              R"("><max_step_size>0.001</max_step_size></physics></world></sdf>)",
          &warnings);
    ASSERT_EQ(warnings.size(), 1u) << type;
    EXPECT_TRUE(contains(warnings[0], "type [" + type + "]: bullet_sim steps every world with Bullet"))
        << warnings[0];
  }
  for (const std::string type : {"ode", "bullet"}) {
    std::vector<std::string> warnings;
    parse(R"(<sdf version="1.6"><world name="w"><physics type=")" + type +
              R"("><max_step_size>0.001</max_step_size></physics></world></sdf>)",
          &warnings);
    EXPECT_TRUE(warnings.empty()) << type << ": " << (warnings.empty() ? "" : warnings[0]);
  }
}

TEST(WorldSpec, PhysicsPacesByTheUpdateRateAndWithoutOneByTheRealTimeFactor) {
  std::vector<std::string> warnings;
  WorldSpec world = parse(withPhysics("<max_step_size>0.002</max_step_size><real_time_update_rate>0"
                                      "</real_time_update_rate><real_time_factor>0</real_time_factor>"),
                          &warnings);
  EXPECT_DOUBLE_EQ(world.max_step_size, 0.002);
  EXPECT_DOUBLE_EQ(world.real_time_update_rate, 0) << "as fast as possible, the RL idiom";
  EXPECT_TRUE(warnings.empty());
  world = parse(withPhysics("<max_step_size>0.004</max_step_size><real_time_factor>2</real_time_factor>"));
  EXPECT_DOUBLE_EQ(world.real_time_update_rate, 500) << "2 x real time in steps of 4 ms";
  world = parse(withPhysics("<real_time_update_rate>3000</real_time_update_rate>"), &warnings);
  EXPECT_DOUBLE_EQ(world.real_time_update_rate, 3000);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_TRUE(contains(warnings[0], "real_time_factor [1] disagrees with real_time_update_rate [3000]"))
      << warnings[0];
  EXPECT_TRUE(contains(warnings[0], "(3 x real time)")) << warnings[0];
}

TEST(WorldSpec, OdeSettingsAreKeptAsWrittenAndNamedInOneWarning) {
  std::vector<std::string> warnings;
  WorldSpec world = parse(withPhysics("<max_step_size>0.001</max_step_size>"), &warnings);
  EXPECT_EQ(world.ode.iters, 50) << "sdformat's default";
  EXPECT_DOUBLE_EQ(world.ode.sor, 1.3);
  EXPECT_DOUBLE_EQ(world.ode.erp, 0.2);
  EXPECT_EQ(world.ode.max_contacts, 20);
  EXPECT_TRUE(warnings.empty());
  // TurtleBot3's worlds write these.
  world =
      parse(withPhysics("<max_contacts>10</max_contacts><ode><solver><type>quick</type><iters>150</iters>"
                        "<sor>1.4</sor></solver><constraints><cfm>0.00001</cfm>"
                        "<contact_max_correcting_vel>2000</contact_max_correcting_vel></constraints></ode>"),
            &warnings);
  EXPECT_EQ(world.ode.iters, 150);
  EXPECT_EQ(world.ode.precon_iters, 0);
  EXPECT_DOUBLE_EQ(world.ode.sor, 1.4);
  EXPECT_DOUBLE_EQ(world.ode.cfm, 1e-5);
  EXPECT_DOUBLE_EQ(world.ode.erp, 0.2) << "not written: sdformat's default";
  EXPECT_DOUBLE_EQ(world.ode.contact_max_correcting_vel, 2000);
  EXPECT_DOUBLE_EQ(world.ode.contact_surface_layer, 0.001);
  EXPECT_EQ(world.ode.max_contacts, 10);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_TRUE(contains(warnings[0], "iters [150], sor [1.4], cfm [1e-05], contact_max_correcting_vel [2000], "
                                    "max_contacts [10] are reported by get_physics_properties"))
      << warnings[0];
  EXPECT_FALSE(contains(warnings[0], "erp")) << warnings[0];
  try {
    parse(withPhysics("<ode><solver><sor>nan</sor></solver><constraints><cfm>inf</cfm></constraints></ode>"));
    FAIL() << "a NaN sor loaded";
  } catch (const SpecError& error) {
    EXPECT_EQ(error.problems().size(), 2u) << error.what();
    EXPECT_TRUE(contains(error.what(), "sor [nan] is not finite")) << error.what();
    EXPECT_TRUE(contains(error.what(), "cfm [inf] is not finite")) << error.what();
  }
}

TEST(WorldSpec, ColoursComeFromDiffuseThenAmbientThenTheGazeboScript) {
  std::vector<std::string> warnings;
  const WorldSpec world = parse(R"(<sdf version="1.6"><world name="w"><model name="m"><static>true</static>
    <link name="l">
      <visual name="diffuse"><geometry><box><size>1 1 1</size></box></geometry>
        <material><ambient>0 0 1 1</ambient><diffuse>1 0 0 1</diffuse></material></visual>
      <visual name="ambient"><geometry><box><size>1 1 1</size></box></geometry>
        <material><ambient>0 0 1 1</ambient></material></visual>
      <visual name="script"><geometry><box><size>1 1 1</size></box></geometry>
        <material><script><uri>file://media/materials/scripts/gazebo.material</uri><name>Gazebo/Orange</name></script></material></visual>
      <visual name="glass"><transparency>0.75</transparency><geometry><box><size>1 1 1</size></box></geometry>
        <material><diffuse>0 1 0 1</diffuse></material></visual>
      <visual name="typo"><geometry><box><size>1 1 1</size></box></geometry>
        <material><script><uri>file://media/materials/scripts/gazebo.material</uri><name>Gazebo/Grren</name></script></material></visual>
    </link></model></world></sdf>)",
                                &warnings);
  const std::vector<Visual>& visuals = world.models.at(0).visuals;
  ASSERT_EQ(visuals.size(), 5u);
  EXPECT_TRUE(visuals[0].rgba.isApprox(Eigen::Vector4d(1, 0, 0, 1)));
  EXPECT_TRUE(visuals[1].rgba.isApprox(Eigen::Vector4d(0, 0, 1, 1)));
  EXPECT_EQ(visuals[2].material, "Gazebo/Orange");
  EXPECT_TRUE(visuals[2].rgba.isApprox(*gazeboMaterialColour("Gazebo/Orange")));
  EXPECT_TRUE(visuals[3].rgba.isApprox(Eigen::Vector4d(0, 1, 0, 0.25)));
  EXPECT_EQ(visuals[4].material, "Gazebo/Grren");
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_TRUE(contains(warnings[0], "[Gazebo/Grren]")) << warnings[0];
  EXPECT_TRUE(contains(warnings[0], "did you mean [Gazebo/Green]")) << warnings[0];
}

// A non-static model is a body (world_bodies_test simulates it); links joined to nothing are welded into one,
// with one warning saying so.
TEST(WorldSpec, NonStaticModelIsABodyAndLinksJoinedToNothingAreWeldedWithOneWarning) {
  std::vector<std::string> warnings;
  const WorldSpec world = parse(R"(<sdf version="1.6"><world name="w">
    <model name="ball"><link name="l">
      <collision name="c"><geometry><sphere><radius>0.1</radius></sphere></geometry></collision>
    </link></model>
    <model name="pair"><link name="a">
      <collision name="c"><geometry><box><size>1 1 1</size></box></geometry></collision>
    </link><link name="b">
      <collision name="c"><geometry><box><size>1 1 1</size></box></geometry></collision>
    </link></model>
  </world></sdf>)",
                                &warnings);
  ASSERT_EQ(world.models.size(), 2u);
  EXPECT_FALSE(world.models[0].is_static);
  EXPECT_FALSE(world.models[1].is_static);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_TRUE(contains(warnings[0], "model [pair]: links [b] are joined to nothing")) << warnings[0];
  EXPECT_TRUE(contains(warnings[0], "welds them to [a] as one rigid body")) << warnings[0];
}

TEST(WorldSpec, PluginsAndJointsAreIgnoredWithWarnings) {
  std::vector<std::string> warnings;
  parse(R"(<sdf version="1.6"><world name="w">
    <plugin name="state" filename="libgazebo_ros_state.so"/>
    <model name="door"><static>true</static>
      <link name="frame"><collision name="c"><geometry><box><size>1 0.1 2</size></box></geometry></collision></link>
      <link name="leaf"><collision name="c"><geometry><box><size>0.9 0.05 2</size></box></geometry></collision></link>
      <joint name="hinge" type="revolute"><parent>frame</parent><child>leaf</child><axis><xyz>0 0 1</xyz></axis></joint>
    </model>
  </world></sdf>)",
        &warnings);
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_TRUE(contains(warnings[0], "world plugin [state]")) << warnings[0];
  EXPECT_TRUE(contains(warnings[1], "model [door]: joints [hinge] ignored")) << warnings[1];
}

TEST(WorldSpec, MeshIsFoundRelativeToTheWorldFileAndScaled) {
  const WorldSpec world = load(fixture("mesh.world"));
  const Collision& collision = world.models.at(0).collisions.at(0);
  ASSERT_EQ(collision.shape.type, Shape::Type::kMesh);
  EXPECT_EQ(collision.shape.mesh_path, fixture("meshes/tetrahedron.stl"));
  ASSERT_TRUE(collision.shape.mesh);
  EXPECT_EQ(collision.shape.mesh->triangles.size(), 4u);
  Eigen::Vector3d max = Eigen::Vector3d::Zero();
  for (const auto& vertex : collision.shape.mesh->vertices) max = max.cwiseMax(vertex);
  EXPECT_TRUE(max.isApprox(Eigen::Vector3d(2, 3, 4))) << max.transpose();
}

/// A world file that must not load, and parts of the error it must give.
struct BrokenWorld {
  std::string name;  ///< names the test case
  std::string fixture;
  std::vector<std::string> said;
};

class WorldSpecErrors : public ::testing::TestWithParam<BrokenWorld> {};

TEST_P(WorldSpecErrors, AreNamedWithTheFileAndTheElement) {
  const std::string message = loadError(fixture(GetParam().fixture));
  EXPECT_TRUE(contains(message, GetParam().fixture)) << message;
  for (const auto& part : GetParam().said) EXPECT_TRUE(contains(message, part)) << part << "\n" << message;
}

const BrokenWorld kBrokenWorlds[] = {
    {"MissingFile", "no_such.world", {"no such file"}},
    {"IncludedFolderWithoutModelConfig",
     "fail_include_without_model_config.world",
     {"fail_include_without_model_config.world:6]", "meshes] has no model.config", "<sdf version="}},
    {"MalformedXmlNamesTheElement",
     "fail_malformed.world",
     {"fail_malformed.world:7]", "malformed XML", "name=link"}},
    {"HeightmapIsUnsupported",
     "fail_heightmap.world",
     {"model [hills] link [terrain] collision [ground]", "unsupported geometry [heightmap]"}},
};

INSTANTIATE_TEST_SUITE_P(Fixtures, WorldSpecErrors, ::testing::ValuesIn(kBrokenWorlds),
                         [](const ::testing::TestParamInfo<BrokenWorld>& info) { return info.param.name; });

TEST(WorldSpecErrorList, TwoProblemsAreReportedInOneError) {
  // The unknown model is the second problem only when models must all be found.
  const std::string path = fixture("fail_two_problems.world");
  try {
    loadWorld(path, PackageResolver::fromEnvironment(), nullptr, {.strict_models = true});
    FAIL() << "fail_two_problems.world loaded";
  } catch (const SpecError& error) {
    const std::string message = error.what();
    EXPECT_TRUE(contains(message, "fail_two_problems.world")) << message;
    ASSERT_EQ(error.problems().size(), 2u) << message;
    EXPECT_TRUE(contains(message, "unknown model [coffee_machine]")) << message;
    EXPECT_TRUE(
        contains(message, "model [pill] link [body] collision [collision]: unsupported geometry [capsule]"))
        << message;
  }
}

TEST(WorldSpec, UnknownModelIsSkippedWithOneWarningAndTheRestLoads) {
  std::vector<std::string> warnings;
  const WorldSpec world = load(fixture("unknown_model.world"), &warnings);
  ASSERT_EQ(world.models.size(), 1u);
  EXPECT_EQ(world.models[0].name, "shelf");
  ASSERT_EQ(warnings.size(), 1u) << "one warning for both includes of the model";
  const std::string& warning = warnings[0];
  EXPECT_TRUE(contains(warning, "unknown_model.world:7] skipped (2 includes)")) << warning;
  EXPECT_TRUE(contains(warning, "unknown model [ground_plan] (did you mean [ground_plane]?)")) << warning;
  EXPECT_TRUE(contains(warning, packageDirectory("bullet_sim") + "/models")) << "names the folders searched";
  EXPECT_TRUE(contains(warning, "GAZEBO_MODEL_PATH")) << "says how to add a model";
  EXPECT_TRUE(contains(warning, "gazebo_model_path=")) << warning;
  EXPECT_FALSE(contains(warning, "model://ground_plan/")) << "names the model, not a path in it";

  try {
    loadWorld(fixture("unknown_model.world"), PackageResolver::fromEnvironment(), nullptr,
              {.strict_models = true});
    FAIL() << "an unknown model loaded with strict_models";
  } catch (const SpecError& error) {
    ASSERT_EQ(error.problems().size(), 1u) << error.what();
    EXPECT_TRUE(contains(error.what(), "unknown model [ground_plan]")) << error.what();
    EXPECT_TRUE(contains(error.what(), "~strict_models")) << error.what();
  }
}

TEST(WorldSpec, ShapesWhoseMeshIsMissingAreSkippedWithOneWarningPerMeshAndTheRestLoads) {
  std::vector<std::string> warnings;
  const WorldSpec world = load(fixture("missing_meshes.world"), &warnings);
  ASSERT_EQ(world.models.size(), 4u);
  const WorldModelSpec* mailbox = findModel(world, "mailbox");
  ASSERT_NE(mailbox, nullptr);
  ASSERT_EQ(mailbox->collisions.size(), 1u) << "only the post, whose box needs no mesh";
  EXPECT_EQ(mailbox->collisions[0].shape.type, Shape::Type::kBox);
  EXPECT_TRUE(mailbox->visuals.empty());
  ASSERT_NE(findModel(world, "table"), nullptr);
  EXPECT_TRUE(findModel(world, "table")->collisions.empty());
  ASSERT_NE(findModel(world, "ground_plane"), nullptr);
  const WorldModelSpec* cone = findModel(world, "cone");
  ASSERT_NE(cone, nullptr);
  ASSERT_EQ(cone->collisions.size(), 1u) << "model:///construction_cone is model://construction_cone";
  EXPECT_EQ(cone->collisions[0].shape.mesh_path,
            packageDirectory("bullet_sim") + "/models/construction_cone/meshes/construction_cone.stl");

  ASSERT_EQ(warnings.size(), 2u) << "one warning per mesh, not per visual or collision";
  const std::string& mailbox_warning = warnings[0];
  EXPECT_TRUE(contains(mailbox_warning, "model [mailbox] link [link] collision [collision]: mesh "
                                        "[model://mailbox/meshes/mailbox.dae] cannot be found"))
      << mailbox_warning;
  EXPECT_TRUE(contains(mailbox_warning, "unknown model [mailbox]")) << mailbox_warning;
  EXPECT_TRUE(contains(mailbox_warning, packageDirectory("bullet_sim") + "/models"))
      << "the folders searched";
  EXPECT_TRUE(contains(mailbox_warning, "GAZEBO_MODEL_PATH")) << mailbox_warning;
  EXPECT_TRUE(contains(mailbox_warning, "gazebo_model_path=")) << mailbox_warning;
  EXPECT_TRUE(contains(warnings[1], "model [cafe_table] has no file [meshes/cafe_table.dae]")) << warnings[1];

  try {
    loadWorld(fixture("missing_meshes.world"), PackageResolver::fromEnvironment(), nullptr,
              {.strict_models = true});
    FAIL() << "a world with missing meshes loaded with strict_models";
  } catch (const SpecError& error) {
    ASSERT_EQ(error.problems().size(), 2u) << error.what();
    EXPECT_TRUE(
        contains(error.what(), "[model://mailbox/meshes/mailbox.dae] cannot be found (~strict_models"))
        << error.what();
  }
}

TEST(WorldSpec, AMissingMeshInAModelToSpawnIsAnError) {
  try {
    readSdfModel(R"(<sdf version="1.6"><model name="statue"><link name="body"><collision name="shell">
      <geometry><mesh><uri>meshes/does_not_exist.stl</uri></mesh></geometry></collision></link></model></sdf>)",
                 "statue.sdf", PackageResolver::fromEnvironment(), nullptr);
    FAIL() << "a model to spawn loaded without its collision mesh";
  } catch (const SpecError& error) {
    EXPECT_TRUE(contains(error.what(), "model [statue] link [body] collision [shell]")) << error.what();
    EXPECT_TRUE(contains(error.what(), "meshes/does_not_exist.stl")) << error.what();
  }
}

TEST(WorldSpec, CopiesOfAnUnknownModelAreSkippedWithItNamed) {
  std::string includes;
  for (int i = 1; i <= 3; ++i) {
    includes += "<include><uri>model://ground_plan</uri><name>g" + std::to_string(i) + "</name><pose>" +
                std::to_string(i) + " 0 0 0 0 0</pose></include>";
  }
  std::vector<std::string> warnings;
  const WorldSpec world =
      parse("<sdf version=\"1.6\"><world name=\"w\">" + includes + "</world></sdf>", &warnings);
  EXPECT_TRUE(world.models.empty());
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_TRUE(contains(warnings[0], "unknown model [ground_plan]")) << warnings[0];
  EXPECT_EQ(warnings[1], "models [g2], [g3] repeat [g1], which is skipped: they are skipped too");
}

TEST(WorldSpecErrorList, NonPositiveSizesAreRejected) {
  try {
    parse(R"(<sdf version="1.6"><world name="w"><model name="flat"><static>true</static><link name="l">
      <collision name="c"><geometry><box><size>1 0 1</size></box></geometry></collision>
    </link></model></world></sdf>)");
    FAIL() << "a box with a zero size loaded";
  } catch (const SpecError& error) {
    EXPECT_TRUE(contains(error.what(), "inline.world")) << error.what();
    EXPECT_TRUE(
        contains(error.what(), "model [flat] link [l] collision [c]: box size [1 0 1] must be positive"))
        << error.what();
  }
}

TEST(GazeboMaterials, KnownNamesHaveTheirColourAndOthersNone) {
  EXPECT_TRUE(gazeboMaterialColour("Gazebo/Red")->isApprox(Eigen::Vector4d(1, 0, 0, 1)));
  EXPECT_TRUE(gazeboMaterialColour("Gazebo/Gray")->isApprox(*gazeboMaterialColour("Gazebo/Grey")));
  EXPECT_FALSE(gazeboMaterialColour("Gazebo/NoSuchColour"));
  const std::vector<std::string> names = gazeboMaterialNames();
  EXPECT_EQ(std::set<std::string>(names.begin(), names.end()).size(), names.size()) << "duplicate names";
  for (const auto& name : names) {
    const Eigen::Vector4d rgba = *gazeboMaterialColour(name);
    EXPECT_TRUE((rgba.array() >= 0).all() && (rgba.array() <= 1).all()) << name;
  }
}

}  // namespace
}  // namespace bullet_sim

namespace bullet_sim {
namespace {

TEST(ModelGeometry, BoundingBoxesOfTurnedShapesAreTheirWorldExtents) {
  Shape box;
  box.type = Shape::Type::kBox;
  box.box_size = Eigen::Vector3d(1, 2, 3);
  Shape cylinder;
  cylinder.type = Shape::Type::kCylinder;
  cylinder.radius = 0.5;
  cylinder.length = 2;
  Shape sphere;
  sphere.type = Shape::Type::kSphere;
  sphere.radius = 1;
  const Eigen::Isometry3d at(Eigen::Translation3d(1, 2, 3));
  const auto extent = [&](const Shape& shape, const Eigen::Matrix3d& turn) -> Eigen::Vector3d {
    const Eigen::AlignedBox3d box = boundingBox(shape, at * Eigen::Isometry3d(turn));
    return box.max() - box.min();
  };
  const Eigen::Matrix3d quarter_z = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Matrix3d quarter_y = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();
  EXPECT_TRUE(extent(box, quarter_z).isApprox(Eigen::Vector3d(2, 1, 3)));
  EXPECT_TRUE(extent(cylinder, quarter_y).isApprox(Eigen::Vector3d(2, 1, 1)));  // lying along x
  EXPECT_TRUE(extent(sphere, quarter_y).isApprox(Eigen::Vector3d(2, 2, 2)));
  const Eigen::AlignedBox3d ball = boundingBox(sphere, at);
  EXPECT_TRUE(ball.min().isApprox(Eigen::Vector3d(0, 1, 2)));
}

/// A static model of a 1 x 2 x 3 m red box at `pose`, written as a world's <model>.
std::string redBox(const std::string& name, const std::string& pose) {
  return "<model name=\"" + name + "\"><static>true</static><pose>" + pose +
         "</pose><link name=\"link\">"
         "<collision name=\"c\"><geometry><box><size>1 2 3</size></box></geometry></collision>"
         "<visual name=\"v\"><geometry><box><size>1 2 3</size></box></geometry>"
         "<material><diffuse>1 0 0 1</diffuse></material></visual></link></model>\n";
}

TEST(WorldSpec, ModelsThatRepeatOneAnotherAreReadOnceAndPlacedEach) {
  // The poses as sdformat reads them: x y z, then roll about x, pitch about y, yaw about z, all fixed axes.
  const std::vector<std::pair<std::string, std::string>> boxes = {
      {"a", "0 0 1.5 0 0 0"}, {"b", "3 -4 1.5 0 0 1.2"}, {"c", "-2 5 2 0.3 -0.4 2.5"}};
  std::string text = "<sdf version=\"1.6\"><world name=\"w\">\n";
  for (const auto& [name, pose] : boxes) text += redBox(name, pose);
  text +=
      "<include><uri>model://ground_plane</uri><name>floor_1</name></include>\n"
      "<include><uri>model://ground_plane</uri><name>floor_2</name><pose>0 0 -1 0 0 0</pose></include>\n"
      "</world></sdf>\n";
  const WorldSpec world = parse(text);
  ASSERT_EQ(world.models.size(), 5u);
  for (const auto& [name, pose_text] : boxes) {
    SCOPED_TRACE(name);
    const WorldModelSpec* model = findModel(world, name);
    ASSERT_NE(model, nullptr);
    std::istringstream in(pose_text);
    double x, y, z, roll, pitch, yaw;
    in >> x >> y >> z >> roll >> pitch >> yaw;
    const Eigen::Matrix3d rotation = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                                      Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                                      Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                                         .toRotationMatrix();
    EXPECT_TRUE(model->pose.translation().isApprox(Eigen::Vector3d(x, y, z), kExact));
    EXPECT_TRUE(model->pose.linear().isApprox(rotation, kExact));
    ASSERT_EQ(model->collisions.size(), 1u);
    EXPECT_TRUE(model->collisions[0].shape.box_size.isApprox(Eigen::Vector3d(1, 2, 3)));
    EXPECT_EQ(model->collisions[0].name, name + "::link::c") << "a copy's collisions carry its own name";
    ASSERT_EQ(model->visuals.size(), 1u);
    EXPECT_TRUE(model->visuals[0].rgba.isApprox(Eigen::Vector4d(1, 0, 0, 1)));
  }
  ASSERT_NE(findModel(world, "floor_2"), nullptr);
  EXPECT_NEAR(findModel(world, "floor_2")->pose.translation().z(), -1, kExact);
  EXPECT_EQ(findModel(world, "floor_1")->collisions[0].shape.type, Shape::Type::kPlane);
}

TEST(WorldSpec, AProblemOfModelsThatRepeatOneAnotherIsReportedAtEachOfThem) {
  // Lines 2, 3 and 4: each model's size is zero.
  std::string text = "<sdf version=\"1.6\"><world name=\"w\">\n";
  for (const char* name : {"a", "b", "c"}) {
    text += "<model name=\"" + std::string(name) +
            "\"><static>true</static><link name=\"link\"><collision "
            "name=\"c\"><geometry><box><size>0 1 1</size></box></geometry></collision></link></model>\n";
  }
  text += "</world></sdf>\n";
  try {
    parse(text);
    FAIL() << "loaded";
  } catch (const SpecError& e) {
    ASSERT_EQ(e.problems().size(), 3u) << e.what();
    for (int line = 2; line <= 4; ++line)
      EXPECT_THAT(e.what(), ::testing::HasSubstr("[inline.world:" + std::to_string(line) + "] model [" +
                                                 std::string(1, static_cast<char>('a' + line - 2)) + "]"));
  }
}

}  // namespace
}  // namespace bullet_sim
