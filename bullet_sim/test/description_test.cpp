// Checks every robot description the workspace ships: it expands, parses, loads its meshes, has valid
// inertia, rests on its wheels at the zero pose, and its drive plugin agrees with its joint geometry.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <urdf/model.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "bullet_sim/model/model_geometry.h"
#include "bullet_sim/model/model.h"
#include "plugins/ackermann_drive/ackermann_drive.h"
#include "plugins/imu/imu.h"
#include "plugins/pinhole_camera/pinhole_camera.h"
#include "plugins/ray_lidar/ray_lidar.h"
#include "bullet_sim/plugins/registry.h"
#include "plugins/wheeled_drive/wheeled_drive.h"
#include "test_support.h"

namespace bullet_sim {
namespace {

using ::testing::HasSubstr;

constexpr double kGroundTolerance = 0.002;    // [m] wheel bottoms vs z = 0 of base_footprint
constexpr double kGeometryTolerance = 0.001;  // [m] plugin figures vs joint geometry

struct RobotCase {
  std::string label;
  std::string package;
  std::string xacro;  // relative to the package
  std::string xacro_args;
  std::set<std::string> links;
  std::set<std::string> joints;  // the seed's; ours may add base_footprint_joint
  size_t wheels;
  size_t ray_sensors;
};

using test::CommandResult;
using test::run;

class Description : public ::testing::TestWithParam<RobotCase> {
 protected:
  void SetUp() override {
    const RobotCase& robot = GetParam();
    const auto package = PackageResolver::fromEnvironment().packageDirectory(robot.package);
    ASSERT_TRUE(package) << "package [" << robot.package << "] not in ROS_PACKAGE_PATH";
    xacro_file_ = *package + "/" + robot.xacro;
    static std::map<std::string, CommandResult> expanded;  // xacro takes ~0.3 s; expand each case once
    const std::string command = "xacro '" + xacro_file_ + "' " + robot.xacro_args;
    if (!expanded.count(command)) expanded[command] = run(command);
    expansion_ = expanded[command];
    ASSERT_EQ(expansion_.status, 0) << command << " failed:\n" << expansion_.errors;
    try {
      model_ = parseModel(expansion_.output, xacro_file_, PackageResolver::fromEnvironment(), &warnings_);
    } catch (const std::exception& e) {
      FAIL() << e.what();
    }
  }

  /// The config of the first plugin whose config is a `Config`, or nullptr.
  template <class Config>
  const Config* config() const {
    for (const auto& p : model_.plugins) {
      if (const auto* found = p.configAs<Config>()) return found;
    }
    return nullptr;
  }

  std::string xacro_file_;
  CommandResult expansion_;
  ModelSpec model_;
  std::vector<std::string> warnings_;
};

TEST_P(Description, PassesCheckUrdf) {
  char urdf_file[] = "/tmp/description_test_XXXXXX.urdf";
  const int fd = mkstemps(urdf_file, 5);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(write(fd, expansion_.output.data(), expansion_.output.size()),
            static_cast<ssize_t>(expansion_.output.size()));
  close(fd);
  const CommandResult check = run(std::string("check_urdf ") + urdf_file);
  std::remove(urdf_file);
  EXPECT_EQ(check.status, 0) << check.output << check.errors;
  EXPECT_THAT(check.output, HasSubstr("Successfully Parsed XML"));
}

TEST_P(Description, ParsesWithUrdfModelAndLoadsWithoutWarnings) {
  urdf::Model urdf_model;
  EXPECT_TRUE(urdf_model.initString(expansion_.output));
  EXPECT_EQ(warnings_, std::vector<std::string>{});
}

TEST_P(Description, HasTheSeedsLinkAndJointNames) {
  const auto names = model_.linkNames();
  EXPECT_EQ(std::set<std::string>(names.begin(), names.end()), GetParam().links);
  for (const auto& joint : GetParam().joints)
    EXPECT_TRUE(model_.joint(joint)) << "no joint [" << joint << "]";
  EXPECT_EQ(model_.root, "base_footprint");
}

TEST_P(Description, EveryVisualIsAMeshWithTriangles) {
  for (const auto& link : model_.links) {
    for (const auto& visual : link.visuals) {
      ASSERT_EQ(visual.shape.type, Shape::Type::kMesh) << "link [" << link.name << "]";
      ASSERT_TRUE(visual.shape.mesh) << visual.shape.mesh_path;
      EXPECT_GT(visual.shape.mesh->triangles.size(), 0u) << visual.shape.mesh_path;
    }
  }
}

TEST_P(Description, EveryLinkWithCollisionHasValidInertia) {
  for (const auto& link : model_.links) {
    if (link.collisions.empty()) continue;
    ASSERT_TRUE(link.inertial) << "link [" << link.name << "] collides but has no <inertial>";
    const auto problem = inertiaProblem(link.inertial->mass, link.inertial->inertia);
    EXPECT_FALSE(problem) << "link [" << link.name << "]: " << problem.value_or("");
  }
}

TEST_P(Description, WheelsTouchTheGroundAndNothingSinks) {
  const auto poses = linkPosesAtZero(model_);
  size_t wheels = 0;
  for (const auto& link : model_.links) {
    const JointSpec* joint = model_.parentJoint(link.name);
    const bool rolls = joint && joint->type == JointSpec::Type::kContinuous;
    for (const auto& collision : link.collisions) {
      const double lowest = lowestPoint(collision.shape, poses.at(link.name) * collision.origin);
      EXPECT_GT(lowest, -kGroundTolerance) << "link [" << link.name << "] sinks into the ground";
      const bool round =
          collision.shape.type == Shape::Type::kCylinder || collision.shape.type == Shape::Type::kSphere;
      if (rolls && round) {
        EXPECT_NEAR(lowest, 0.0, kGroundTolerance) << "wheel [" << link.name << "] does not touch z = 0";
        ++wheels;
      }
    }
  }
  EXPECT_EQ(wheels, GetParam().wheels);
}

TEST_P(Description, DrivePluginAgreesWithJointGeometry) {
  std::vector<std::array<std::string, 2>> axles;    // left joint, right joint
  double separation = 0, diameter = 0;              // [m] as the plugin states them
  if (const auto* drive = config<DriveConfig>()) {  // Gazebo classic's diff drive and skid steer
    for (size_t i = 0; i < drive->left_joints.size() && i < drive->right_joints.size(); ++i)
      axles.push_back({drive->left_joints[i], drive->right_joints[i]});
    separation = drive->wheel_separation;
    diameter = drive->wheel_diameter;
  } else {
    // Our Ackermann extension drives the rear axle; its figures are optional (the plugin reads the URDF).
    const auto* car = config<AckermannConfig>();
    ASSERT_TRUE(car) << "no diff-drive, skid-steer or Ackermann plugin";
    axles.push_back({car->rear_left_joint, car->rear_right_joint});
    if (!car->track_width || !car->wheel_radius)
      GTEST_SKIP() << "the Ackermann plugin gives no <track_width> and <wheel_radius> to check";
    separation = *car->track_width;
    diameter = 2 * *car->wheel_radius;
  }
  const auto poses = linkPosesAtZero(model_);

  Eigen::Vector3d first_axis = Eigen::Vector3d::Zero();
  for (const auto& [left_name, right_name] : axles) {
    const JointSpec* left = model_.joint(left_name);
    const JointSpec* right = model_.joint(right_name);
    ASSERT_TRUE(left && right) << "plugin names joints [" << left_name << "], [" << right_name << "]";
    const Eigen::Isometry3d left_pose = poses.at(left->child);
    const Eigen::Isometry3d right_pose = poses.at(right->child);
    const Eigen::Vector3d left_axis = left_pose.linear() * left->axis;
    const Eigen::Vector3d right_axis = right_pose.linear() * right->axis;
    if (first_axis.isZero()) first_axis = left_axis;
    EXPECT_GT(left_axis.dot(first_axis), 0.99) << "[" << left_name << "] turns the other way";
    EXPECT_GT(right_axis.dot(first_axis), 0.99) << "[" << right_name << "] turns the other way";
    EXPECT_NEAR(std::abs((left_pose.translation() - right_pose.translation()).dot(left_axis)), separation,
                kGeometryTolerance)
        << left_name << " / " << right_name;
    for (const JointSpec* joint : {left, right}) {
      const LinkSpec* wheel = model_.link(joint->child);
      ASSERT_FALSE(wheel->collisions.empty());
      const Shape& shape = wheel->collisions.front().shape;
      ASSERT_EQ(shape.type, Shape::Type::kCylinder) << "wheel [" << wheel->name << "]";
      EXPECT_NEAR(2 * shape.radius, diameter, kGeometryTolerance);
    }
  }
}

TEST_P(Description, SensorFrameNamesExist) {
  for (const auto& plugin : model_.plugins) {
    if (!plugin.sensor) continue;
    const auto* lidar = plugin.configAs<RayLidarConfig>();
    const auto* imu = plugin.configAs<ImuConfig>();
    const auto* camera = plugin.configAs<PinholeCameraConfig>();
    ASSERT_TRUE(lidar || imu || camera) << plugin.where() << " is not a lidar, an IMU or a camera";
    const std::string& frame = lidar ? lidar->frame : imu ? imu->frame : camera->frame;
    EXPECT_TRUE(model_.link(frame)) << plugin.where() << " <frameName>" << frame;
  }
}

TEST_P(Description, RevoluteJointsHaveRealLimits) {
  for (const auto& joint : model_.joints) {
    if (joint.type != JointSpec::Type::kRevolute) continue;
    EXPECT_GT(joint.effort, 0) << "joint [" << joint.name << "]";
    EXPECT_GT(joint.velocity, 0) << "joint [" << joint.name << "]";
    EXPECT_LE(std::abs(joint.lower), 2 * M_PI) << "joint [" << joint.name << "] limits look like degrees";
    EXPECT_LE(std::abs(joint.upper), 2 * M_PI) << "joint [" << joint.name << "] limits look like degrees";
  }
}

TEST_P(Description, LidarsCastNoBeamTwice) {
  size_t lidars = 0;
  for (const auto& plugin : model_.plugins) {
    const auto* lidar = plugin.configAs<RayLidarConfig>();
    if (!lidar) continue;
    ++lidars;
    // Gazebo spaces N beams (max - min) / (N - 1) apart; the beam after the last must not wrap onto the
    // first.
    const double increment = (lidar->max_angle - lidar->min_angle) / (lidar->beams() - 1);
    EXPECT_LE(lidar->max_angle - lidar->min_angle + increment, 2 * M_PI + 1e-9) << plugin.where();
  }
  EXPECT_EQ(lidars, GetParam().ray_sensors);
}

const std::set<std::string> kSmartcarLinks = {
    "base_footprint",   "base_link", "left_front_wheel", "right_front_wheel", "left_back_wheel",
    "right_back_wheel", "head"};
const std::set<std::string> kSmartcarJoints = {"left_front_wheel_joint", "right_front_wheel_joint",
                                               "left_back_wheel_joint", "right_back_wheel_joint", "tobox"};

INSTANTIATE_TEST_SUITE_P(
    Robots, Description,
    ::testing::Values(
        RobotCase{"wheelchair",
                  "smartwheelchair_model",
                  "urdf/smartwheelchair_model.urdf.xacro",
                  "",
                  {"base_footprint", "base_link", "front_left_link", "front_right_link", "rear_left_link",
                   "wheel_rear_left_link", "rear_right_link", "wheel_rear_right_link", "laser_Link"},
                  {"front_left_joint", "front_right_joint", "rear_left_joint", "wheel_rear_left_joint",
                   "rear_right_joint", "wheel_rear_right_joint", "laser_joint"},
                  4,
                  1},
        RobotCase{"smartcar", "smartcar_description", "urdf/smartcar.urdf.xacro", "", kSmartcarLinks,
                  kSmartcarJoints, 4, 1},
        RobotCase{"smartcar_without_lidar", "smartcar_description", "urdf/smartcar.urdf.xacro",
                  "with_lidar:=false", kSmartcarLinks, kSmartcarJoints, 4, 0},
        RobotCase{"yahboomcar",
                  "yahboomcar_description",
                  "urdf/yahboomcar.urdf.xacro",
                  "",
                  {"base_footprint", "base_link", "zq_Link", "yq_Link", "yh_Link", "zh_Link", "imu_Link",
                   "radar_Link", "jq1_Link", "jq2_Link"},
                  {"zq_Joint", "yq_Joint", "yh_Joint", "zh_Joint", "imu_Joint", "radar_Joint", "jq1_Joint",
                   "jq2_Joint"},
                  4,
                  1},
        RobotCase{"tianracer",
                  "tianracer_description",
                  "urdf/tianracer.urdf.xacro",
                  "",
                  {"base_footprint", "base_link", "chassis", "left_steering_hinge", "right_steering_hinge",
                   "left_front_wheel", "right_front_wheel", "left_rear_wheel", "right_rear_wheel", "laser"},
                  {"base_link_joint", "left_steering_hinge_joint", "right_steering_hinge_joint",
                   "left_front_wheel_joint", "right_front_wheel_joint", "left_rear_wheel_joint",
                   "right_rear_wheel_joint", "laser_joint"},
                  4,
                  1}),
    [](const ::testing::TestParamInfo<RobotCase>& info) { return info.param.label; });

/// The XML of `text` without comments, in tinyxml2's compact form: what a URDF parser sees.
std::string withoutComments(const std::string& text) {
  tinyxml2::XMLDocument doc;
  EXPECT_EQ(doc.Parse(text.c_str()), tinyxml2::XML_SUCCESS) << doc.ErrorStr();
  std::vector<tinyxml2::XMLNode*> pending = {&doc};
  while (!pending.empty()) {
    tinyxml2::XMLNode* node = pending.back();
    pending.pop_back();
    for (tinyxml2::XMLNode* child = node->FirstChild(); child;) {
      tinyxml2::XMLNode* next = child->NextSibling();
      if (child->ToComment()) {
        node->DeleteChild(child);
      } else {
        pending.push_back(child);
      }
      child = next;
    }
  }
  tinyxml2::XMLPrinter printer(nullptr, /*compact=*/true);
  doc.Print(&printer);
  return printer.CStr();
}

// Seed 000's gazebo.launch spawns urdf/smartwheelchair_model.urdf: it must be the xacro's expansion.
TEST(WheelchairPlainUrdf, IsTheXacroExpandedRunScriptsGenerateUrdfWhenNot) {
  const std::string expanded =
      test::expandXacro("smartwheelchair_model", "urdf/smartwheelchair_model.urdf.xacro");
  const std::string plain =
      test::readFile(test::packageFile("smartwheelchair_model", "urdf/smartwheelchair_model.urdf"));
  EXPECT_EQ(withoutComments(plain), withoutComments(expanded))
      << "smartwheelchair_model.urdf is stale: run scripts/generate_urdf.py and commit it";
}

}  // namespace
}  // namespace bullet_sim
