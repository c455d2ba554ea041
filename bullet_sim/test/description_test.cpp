// Checks every robot description the workspace ships: it expands, parses, loads its meshes, has valid
// inertia, rests on its wheels at the zero pose, and its drive plugin agrees with its joint geometry.
#include <gtest/gtest.h>
#include <tinyxml2.h>
#include <urdf_parser/urdf_parser.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "bullet_sim/spec/mesh.h"
#include "bullet_sim/spec/model_geometry.h"
#include "bullet_sim/spec/package_resolver.h"

namespace bullet_sim {
namespace {

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

struct CommandResult {
  int status;
  std::string output;  // stdout
  std::string errors;  // stderr
};

CommandResult run(const std::string& command) {
  char error_file[] = "/tmp/description_test_XXXXXX";
  const int fd = mkstemp(error_file);
  close(fd);
  CommandResult result{-1, "", ""};
  if (FILE* pipe = popen((command + " 2>" + error_file).c_str(), "r")) {
    std::array<char, 4096> buffer;
    for (size_t n; (n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0;)
      result.output.append(buffer.data(), n);
    result.status = pclose(pipe);
  }
  std::ifstream errors(error_file);
  result.errors.assign(std::istreambuf_iterator<char>(errors), {});
  std::remove(error_file);
  return result;
}

std::string packageFile(const std::string& package, const std::string& relative) {
  std::string error;
  const auto path =
      PackageResolver::fromEnvironment().resolve("package://" + package + "/" + relative, &error);
  return path ? *path : "<" + error + ">";
}

class Description : public ::testing::TestWithParam<RobotCase> {
 protected:
  void SetUp() override {
    const RobotCase& robot = GetParam();
    xacro_file_ = packageFile(robot.package, robot.xacro);
    static std::map<std::string, CommandResult> expanded;  // xacro takes ~0.3 s; expand each case once
    const std::string command = "xacro '" + xacro_file_ + "' " + robot.xacro_args;
    if (!expanded.count(command)) expanded[command] = run(command);
    expansion_ = expanded[command];
    ASSERT_EQ(expansion_.status, 0) << command << " failed:\n" << expansion_.errors;
    model_ = urdf::parseURDF(expansion_.output);
    ASSERT_TRUE(model_) << "urdfdom cannot parse the expansion of " << xacro_file_;
    ASSERT_EQ(gazebo_.Parse(expansion_.output.c_str()), tinyxml2::XML_SUCCESS);
  }

  /// Texts of the children of the <plugin> whose filename is `filename`, or empty when there is none.
  std::map<std::string, std::string> pluginTags(const std::string& filename) {
    std::map<std::string, std::string> tags;
    for (auto* g = gazebo_.RootElement()->FirstChildElement("gazebo"); g;
         g = g->NextSiblingElement("gazebo")) {
      for (auto* p = g->FirstChildElement("plugin"); p; p = p->NextSiblingElement("plugin")) {
        if (p->Attribute("filename", filename.c_str()) == nullptr) continue;
        for (auto* tag = p->FirstChildElement(); tag; tag = tag->NextSiblingElement()) {
          tags[tag->Name()] = tag->GetText() ? tag->GetText() : "";
        }
      }
    }
    return tags;
  }

  std::string xacro_file_;
  CommandResult expansion_;
  urdf::ModelInterfaceSharedPtr model_;
  tinyxml2::XMLDocument gazebo_;
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
  EXPECT_NE(check.output.find("Successfully Parsed XML"), std::string::npos) << check.output;
}

TEST_P(Description, HasTheSeedsLinkAndJointNames) {
  std::set<std::string> links;
  for (const auto& [name, link] : model_->links_) links.insert(name);
  EXPECT_EQ(links, GetParam().links);
  for (const auto& joint : GetParam().joints)
    EXPECT_TRUE(model_->getJoint(joint)) << "no joint [" << joint << "]";
  EXPECT_EQ(model_->getRoot()->name, "base_footprint");
}

TEST_P(Description, EveryMeshResolvesAndLoadsWithTriangles) {
  const auto resolver = PackageResolver::fromEnvironment();
  int meshes = 0;
  for (const auto& [name, link] : model_->links_) {
    std::vector<urdf::GeometrySharedPtr> geometries;
    for (const auto& visual : link->visual_array) geometries.push_back(visual->geometry);
    for (const auto& collision : link->collision_array) geometries.push_back(collision->geometry);
    for (const auto& geometry : geometries) {
      if (geometry->type != urdf::Geometry::MESH) continue;
      const auto& mesh = static_cast<const urdf::Mesh&>(*geometry);
      std::string error;
      const auto path = resolver.resolve(mesh.filename, &error);
      ASSERT_TRUE(path) << "link [" << name << "]: " << error;
      const auto loaded = loadMesh(*path, {mesh.scale.x, mesh.scale.y, mesh.scale.z}, &error);
      ASSERT_TRUE(loaded) << "link [" << name << "]: " << error;
      EXPECT_GT(loaded->triangles.size(), 0u);
      ++meshes;
    }
  }
  EXPECT_GT(meshes, 0) << "every robot has visual meshes";
}

TEST_P(Description, EveryLinkWithCollisionHasValidInertia) {
  for (const auto& [name, link] : model_->links_) {
    if (link->collision_array.empty() && !link->inertial) continue;
    ASSERT_TRUE(link->inertial) << "link [" << name << "] collides but has no <inertial>";
    const auto problem = inertiaProblem(*link->inertial);
    EXPECT_FALSE(problem) << "link [" << name << "]: " << problem.value_or("");
  }
}

TEST_P(Description, WheelsTouchTheGroundAndNothingSinks) {
  const auto poses = linkPosesAtZero(*model_);
  const MeshSource no_meshes = [](const urdf::Mesh&) { return std::nullopt; };
  size_t wheels = 0;
  for (const auto& [name, link] : model_->links_) {
    const bool rolls = link->parent_joint && link->parent_joint->type == urdf::Joint::CONTINUOUS;
    for (const auto& collision : link->collision_array) {
      const auto lowest =
          lowestPoint(*collision->geometry, poses.at(name) * toIsometry(collision->origin), no_meshes);
      ASSERT_TRUE(lowest) << "link [" << name << "]: descriptions collide with primitives only";
      EXPECT_GT(*lowest, -kGroundTolerance) << "link [" << name << "] sinks into the ground";
      const bool round = collision->geometry->type == urdf::Geometry::CYLINDER ||
                         collision->geometry->type == urdf::Geometry::SPHERE;
      if (rolls && round) {
        EXPECT_NEAR(*lowest, 0.0, kGroundTolerance) << "wheel [" << name << "] does not touch z = 0";
        ++wheels;
      }
    }
  }
  EXPECT_EQ(wheels, GetParam().wheels);
}

TEST_P(Description, DrivePluginAgreesWithJointGeometry) {
  std::vector<std::array<std::string, 2>> axles;  // left joint, right joint
  auto tags = pluginTags("libgazebo_ros_diff_drive.so");
  if (!tags.empty()) {
    axles.push_back({tags["leftJoint"], tags["rightJoint"]});
  } else {
    tags = pluginTags("libgazebo_ros_skid_steer_drive.so");
    ASSERT_FALSE(tags.empty()) << "no diff-drive or skid-steer plugin";
    axles.push_back({tags["leftFrontJoint"], tags["rightFrontJoint"]});
    axles.push_back({tags["leftRearJoint"], tags["rightRearJoint"]});
  }
  const double separation = std::stod(tags.at("wheelSeparation"));
  const double diameter = std::stod(tags.at("wheelDiameter"));
  const auto poses = linkPosesAtZero(*model_);

  Eigen::Vector3d first_axis = Eigen::Vector3d::Zero();
  for (const auto& [left_name, right_name] : axles) {
    const auto left = model_->getJoint(left_name);
    const auto right = model_->getJoint(right_name);
    ASSERT_TRUE(left && right) << "plugin names joints [" << left_name << "], [" << right_name << "]";
    const Eigen::Isometry3d left_pose = poses.at(left->child_link_name);
    const Eigen::Isometry3d right_pose = poses.at(right->child_link_name);
    const Eigen::Vector3d left_axis =
        left_pose.linear() * Eigen::Vector3d(left->axis.x, left->axis.y, left->axis.z);
    const Eigen::Vector3d right_axis =
        right_pose.linear() * Eigen::Vector3d(right->axis.x, right->axis.y, right->axis.z);
    if (first_axis.isZero()) first_axis = left_axis;
    EXPECT_GT(left_axis.dot(first_axis), 0.99) << "[" << left_name << "] turns the other way";
    EXPECT_GT(right_axis.dot(first_axis), 0.99) << "[" << right_name << "] turns the other way";
    EXPECT_NEAR(std::abs((left_pose.translation() - right_pose.translation()).dot(left_axis.normalized())),
                separation, kGeometryTolerance)
        << left_name << " / " << right_name;
    for (const auto& joint : {left, right}) {
      const auto wheel = model_->getLink(joint->child_link_name);
      ASSERT_FALSE(wheel->collision_array.empty());
      const auto& shape = *wheel->collision_array.front()->geometry;
      ASSERT_EQ(shape.type, urdf::Geometry::CYLINDER) << "wheel [" << wheel->name << "]";
      EXPECT_NEAR(2 * static_cast<const urdf::Cylinder&>(shape).radius, diameter, kGeometryTolerance);
    }
  }
}

TEST_P(Description, GazeboReferencesAndFrameNamesExist) {
  std::set<std::string> frames;
  for (const auto& [name, link] : model_->links_) frames.insert(name);
  std::set<std::string> references = frames;
  for (const auto& [name, joint] : model_->joints_) references.insert(name);
  for (auto* g = gazebo_.RootElement()->FirstChildElement("gazebo"); g; g = g->NextSiblingElement("gazebo")) {
    if (const char* reference = g->Attribute("reference")) {
      EXPECT_TRUE(references.count(reference)) << "<gazebo reference=\"" << reference << "\">";
    }
    std::function<void(const tinyxml2::XMLElement*)> visit = [&](const tinyxml2::XMLElement* e) {
      if (std::string(e->Name()) == "frameName") {
        EXPECT_TRUE(frames.count(e->GetText() ? e->GetText() : "")) << "<frameName>" << e->GetText();
      }
      for (auto* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) visit(c);
    };
    visit(g);
  }
}

TEST_P(Description, RevoluteJointsHaveRealLimits) {
  for (const auto& [name, joint] : model_->joints_) {
    if (joint->type != urdf::Joint::REVOLUTE) continue;
    ASSERT_TRUE(joint->limits) << "joint [" << name << "]";
    EXPECT_GT(joint->limits->effort, 0) << "joint [" << name << "]";
    EXPECT_GT(joint->limits->velocity, 0) << "joint [" << name << "]";
    EXPECT_LE(std::abs(joint->limits->lower), 2 * M_PI) << "joint [" << name << "] limits look like degrees";
    EXPECT_LE(std::abs(joint->limits->upper), 2 * M_PI) << "joint [" << name << "] limits look like degrees";
  }
}

TEST_P(Description, LidarsCastNoBeamTwice) {
  size_t sensors = 0;
  for (auto* g = gazebo_.RootElement()->FirstChildElement("gazebo"); g; g = g->NextSiblingElement("gazebo")) {
    for (auto* sensor = g->FirstChildElement("sensor"); sensor;
         sensor = sensor->NextSiblingElement("sensor")) {
      if (sensor->Attribute("type", "ray") == nullptr) continue;
      ++sensors;
      const auto* horizontal =
          sensor->FirstChildElement("ray")->FirstChildElement("scan")->FirstChildElement("horizontal");
      const double samples = horizontal->FirstChildElement("samples")->DoubleText();
      const double min_angle = horizontal->FirstChildElement("min_angle")->DoubleText();
      const double max_angle = horizontal->FirstChildElement("max_angle")->DoubleText();
      // Gazebo spaces N beams (max - min) / (N - 1) apart; the beam after the last must not wrap onto the
      // first.
      const double increment = (max_angle - min_angle) / (samples - 1);
      EXPECT_LE(max_angle - min_angle + increment, 2 * M_PI + 1e-9)
          << "sensor [" << sensor->Attribute("name") << "]";
    }
  }
  EXPECT_EQ(sensors, GetParam().ray_sensors);
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
                  1}),
    [](const ::testing::TestParamInfo<RobotCase>& info) { return info.param.label; });

}  // namespace
}  // namespace bullet_sim
