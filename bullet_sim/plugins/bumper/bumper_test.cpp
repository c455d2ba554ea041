// Bumpers: a car driven into test_room.world's east wall, and the collision names a contact sensor watches.
// Stepped in-process, no roscore.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "plugins/bumper/bumper.h"
#include "plugins/wheeled_drive/wheeled_drive.h"
#include "bullet_sim/simulation/simulation.h"
#include "test/multi_sensor_robot.h"
#include "test/test_support.h"

namespace bullet_sim {
namespace {

using test::loadWarnings;

using ::testing::Contains;
using ::testing::HasSubstr;

constexpr char kBumperLink[] = R"(
  <joint name="bumper_joint" type="fixed">
    <parent link="base_link"/><child link="bumper_link"/><origin xyz="0.21 0 0.05"/>
  </joint>
  <link name="bumper_link">
    <collision><geometry><box size="0.02 0.3 0.06"/></geometry></collision>
  </link>
  <gazebo reference="bumper_link">
    <sensor type="contact" name="bumper">
      <update_rate>50</update_rate>
      <contact><collision>COLLISION</collision></contact>
      <plugin name="bumper_plugin" filename="libgazebo_ros_bumper.so">
        <bumperTopicName>bumper</bumperTopicName>
      </plugin>
    </sensor>
  </gazebo>
</robot>)";

/// two_wheeler.urdf with a diff drive, a bumper plate 0.22 m ahead of base_footprint and a contact sensor
/// watching `collision`.
std::string bumperCar(const std::string& collision, const std::string& wheel_model) {
  std::string bumper = kBumperLink;
  bumper.replace(bumper.find("COLLISION"), 9, collision);
  std::string urdf = test::readFile(test::fixture("robots/two_wheeler.urdf"));
  urdf.replace(urdf.find("</robot>"), 8, bumper);
  return test::withPlugin(urdf, "drive", "libgazebo_ros_diff_drive.so",
                          {{"leftJoint", "left_wheel_joint"},
                           {"rightJoint", "right_wheel_joint"},
                           {"wheelSeparation", "0.35"},
                           {"wheelDiameter", "0.1"},
                           {"wheelModel", wheel_model}});
}

constexpr char kLumpedBumper[] = "base_footprint_fixed_joint_lump__bumper_link_collision_1";

TEST(Bumper, ARobotDrivenIntoAWallReportsItsBumperTouchingItAndNothingBefore) {
  for (const std::string& wheel_model : test::kWheelModels) {
    SCOPED_TRACE(wheel_model);
    Simulation simulation(test::shippedWorld("test_room.world"));
    Robot& robot = simulation.spawn("car", test::parseQuietly(bumperCar(kLumpedBumper, wheel_model), "car"),
                                    {.x = 2.0});
    const Bumper& bumper = *test::pluginsOf<Bumper>(robot).at(0);
    WheeledDrive& drive = *test::pluginsOf<WheeledDrive>(robot).at(0);
    const auto front = [&] { return robot.body().linkPose("bumper_link").translation().x() + 0.01; };
    uint64_t seen = 0;
    int empty_updates = 0;
    while (front() < 3.0 - 1e-3) {
      ASSERT_LT(simulation.time(), 10.0) << "the car never reached the wall";
      drive.setCommand(0.3, 0, simulation.time());
      simulation.step();
      if (test::countOf<ContactsSample>(bumper) == seen) continue;
      seen = test::countOf<ContactsSample>(bumper);
      EXPECT_THAT(test::latestOf<ContactsSample>(bumper).states, testing::IsEmpty())
          << "the plate is " << 3.0 - front() << " m off";
      ++empty_updates;
    }
    EXPECT_GT(empty_updates, 50) << "a bumper publishes every update, empty while nothing touches";
    ASSERT_TRUE(test::stepUntil(
        simulation, [&] { return !test::latestOf<ContactsSample>(bumper).states.empty(); }, 1.0,
        "the bumper's contact"));
    for (int i = 0; i < 200; ++i) {
      drive.setCommand(0.3, 0, simulation.time());
      simulation.step();
    }
    const ContactsSample& contacts = test::latestOf<ContactsSample>(bumper);
    EXPECT_EQ(contacts.frame_id, "world");
    ASSERT_EQ(contacts.states.size(), 1u) << "the wheels and the caster on the ground are other collisions";
    const ContactsSample::State& state = contacts.states[0];
    EXPECT_EQ(state.collision1, std::string("car::base_footprint::") + kLumpedBumper);
    EXPECT_EQ(state.collision2, "room::wall_east::collision");
    ASSERT_FALSE(state.positions.empty());
    for (size_t i = 0; i < state.positions.size(); ++i) {
      EXPECT_NEAR(state.positions[i].x(), 3.0, 0.005);
      EXPECT_LT((state.normals[i] - Eigen::Vector3d(-1, 0, 0)).norm(), 1e-6);
    }
    EXPECT_LT(state.total_wrench.force.x(), -1.0) << "the wall pushes the car back";
    EXPECT_THAT(state.info, HasSubstr("my geom:car::base_footprint::" + std::string(kLumpedBumper)));
  }
}

TEST(Bumper, ACollisionNamedAsBeforeLumpingIsWatchedWithAWarning) {
  const std::string urdf = bumperCar("bumper_link_collision", "contact");
  EXPECT_THAT(loadWarnings(urdf),
              Contains(HasSubstr("<contact><collision> [bumper_link_collision] is the name of link "
                                 "[bumper_link]'s collision before Gazebo lumps that link into "
                                 "[base_footprint]; there it is [" +
                                 std::string(kLumpedBumper) + "], and Gazebo's bumper, finding no "
                                 "[bumper_link_collision], reports nothing: bullet_sim watches [" +
                                 std::string(kLumpedBumper) + "]")));
  const ModelSpec model = parseModel(urdf, "car", PackageResolver::fromEnvironment());
  for (const auto& plugin : model.plugins) {
    if (const auto* bumper = plugin.configAs<BumperConfig>()) {
      ASSERT_EQ(bumper->collisions.size(), 1u);
      EXPECT_EQ(bumper->collisions[0].name, kLumpedBumper);
    }
  }
}

TEST(Bumper, ACollisionNamingNothingIsAWarningWithASuggestion) {
  EXPECT_THAT(loadWarnings(bumperCar("base_footprint_fixed_joint_lump__bumper_link_collision_2", "contact")),
              Contains(HasSubstr("<contact><collision> "
                                 "[base_footprint_fixed_joint_lump__bumper_link_collision_2] is no collision "
                                 "of link [base_footprint] as Gazebo names them (did you mean [" +
                                 std::string(kLumpedBumper) + "]?): it reports nothing, as in Gazebo")));
}

}  // namespace
}  // namespace bullet_sim
