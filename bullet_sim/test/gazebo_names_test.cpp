// The names Gazebo gives collisions once it has lumped fixed joints (model/gazebo_names.h), on the
// multi-sensor test robot (test/fixtures/robots/multi_sensor_robot.urdf.xacro) and on two_wheeler.urdf.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <map>
#include <string>
#include <vector>

#include "bullet_sim/model/gazebo_names.h"
#include "multi_sensor_robot.h"
#include "test_support.h"

namespace bullet_sim {
namespace {

using test::multiSensorRobot;

TEST(GazeboNames, LumpedCollisionsAreNamedAsSdformatNamesThem) {
  const ModelSpec robot = multiSensorRobot();
  EXPECT_EQ(gazeboLink(robot, "bumper_link"), "base_footprint");
  std::vector<std::string> names;
  for (const GazeboCollision& collision : gazeboCollisions(robot)) {
    EXPECT_EQ(collision.gazebo_link, "base_footprint");
    names.push_back(collision.name);
  }
  // base_link's box, then base_link's fixed children by joint name.
  EXPECT_EQ(names, (std::vector<std::string>{"base_footprint_fixed_joint_lump__base_link_collision",
                                             "base_footprint_fixed_joint_lump__bumper_link_collision_1",
                                             "base_footprint_fixed_joint_lump__caster_fl_collision_2",
                                             "base_footprint_fixed_joint_lump__caster_fr_collision_3",
                                             "base_footprint_fixed_joint_lump__caster_rl_collision_4",
                                             "base_footprint_fixed_joint_lump__caster_rr_collision_5"}));
  EXPECT_EQ(unlumpedCollisionNames(robot, "bumper_link"), std::vector<std::string>{"bumper_link_collision"});
}

TEST(GazeboNames, NamedMovingAndPreservedLinksKeepTheirOwn) {
  // A named collision on a link of its own, a second collision, and a fixed joint kept by preserveFixedJoint.
  std::string urdf = test::readFile(test::fixture("robots/two_wheeler.urdf"));
  urdf = test::replaceAfter(urdf, "<link name=\"left_wheel\">", "<collision>", "<collision name=\"tyre\">");
  urdf = test::replaceAfter(urdf, "<link name=\"base_link\">", "</link>",
                            "<collision><geometry><sphere radius=\"0.01\"/></geometry></collision></link>");
  urdf = test::replaceAfter(urdf, "</robot>", "</robot>",
                            "<gazebo reference=\"caster_joint\"><preserveFixedJoint>true</preserveFixedJoint>"
                            "</gazebo></robot>");
  const ModelSpec robot = test::parseQuietly(urdf, "two_wheeler");
  std::map<std::string, std::string> names;
  for (const GazeboCollision& collision : gazeboCollisions(robot)) {
    const std::string key = collision.link + "/" + std::to_string(collision.index);
    names[key] = collision.gazebo_link + "::" + collision.name;
  }
  EXPECT_EQ(names["base_link/0"], "base_footprint::base_footprint_fixed_joint_lump__base_link_collision");
  EXPECT_EQ(names["base_link/1"], "base_footprint::base_footprint_fixed_joint_lump__base_link_collision_1");
  EXPECT_EQ(names["caster/0"], "caster::caster_collision");
  // sdformat adds the lump prefix to a name that does not start with its link's, lumped or not.
  EXPECT_EQ(names["left_wheel/0"], "left_wheel::left_wheel_fixed_joint_lump__tyre_collision");
  EXPECT_EQ(names["right_wheel/0"], "right_wheel::right_wheel_collision");
}

}  // namespace
}  // namespace bullet_sim
