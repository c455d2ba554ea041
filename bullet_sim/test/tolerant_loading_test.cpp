// What Gazebo accepts, accepted with one warning each (issue 19, section 1): each tolerated form, written
// into a small diff-drive robot that loads clean, loads with exactly one warning and the robot drives. A
// file's errors, of whatever kind, come out together; an unreadable world falls back on the empty one.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <array>
#include <filesystem>
#include <fstream>

#include "bullet_sim/model/sdf_model.h"
#include "bullet_sim/model/world.h"
#include "plugins/ground_truth/ground_truth.h"
#include "plugins/joint_states/joint_states.h"
#include "plugins/ray_lidar/ray_lidar.h"
#include "bullet_sim/plugins/registry.h"
#include "plugins/wheeled_drive/wheeled_drive.h"
#include "bullet_sim/simulation/simulation.h"
#include "multi_sensor_robot.h"
#include "test_support.h"

namespace bullet_sim {
namespace {

using ::testing::AllOf;
using ::testing::ElementsAre;
using ::testing::HasSubstr;
using ::testing::IsEmpty;
using ::testing::Not;

/// The two-wheeler with a diff drive: it loads without a warning.
std::string driveable() {
  return test::twoWheelerWithDiffDrive({{"robotBaseFrame", "base_footprint"}, {"odometryFrame", "odom"}});
}

/// `urdf` with `xml` (elements) appended to its <robot>.
std::string withElements(const std::string& urdf, const std::string& xml) {
  const auto end = urdf.rfind("</robot>");
  return urdf.substr(0, end) + xml + "\n</robot>\n";
}

/// `urdf` with the inertia of link `link` replaced by `moments` (ixx iyy izz), or its <inertial> removed.
std::string withInertia(const std::string& urdf, const std::string& link, const char* moments[3]) {
  return test::editUrdf(urdf, [&](tinyxml2::XMLElement& robot) {
    for (auto* l = robot.FirstChildElement("link"); l; l = l->NextSiblingElement("link")) {
      if (link != l->Attribute("name")) continue;
      if (!moments) {
        l->DeleteChild(l->FirstChildElement("inertial"));
        continue;
      }
      auto* inertia = l->FirstChildElement("inertial")->FirstChildElement("inertia");
      inertia->SetAttribute("ixx", moments[0]);
      inertia->SetAttribute("iyy", moments[1]);
      inertia->SetAttribute("izz", moments[2]);
    }
  });
}

/// `urdf` with <dynamics `term`="`value`"/> on each of its wheel joints.
std::string withWheelDynamics(const std::string& urdf, const char* term, const char* value) {
  return test::editUrdf(urdf, [&](tinyxml2::XMLElement& robot) {
    for (auto* joint = robot.FirstChildElement("joint"); joint; joint = joint->NextSiblingElement("joint")) {
      if (std::string(joint->Attribute("type")) != "continuous") continue;
      tinyxml2::XMLElement* dynamics = joint->InsertNewChildElement("dynamics");
      dynamics->SetAttribute(term, value);
    }
  });
}

/// How far the robot's base goes in 1 s of a 0.3 m/s cmd_vel.
double drivenDistance(const std::string& urdf) {
  Simulation simulation(test::shippedWorld("empty.world"));
  std::vector<std::string> warnings;
  Robot& robot =
      simulation.spawn("robot", parseModel(urdf, "robot", PackageResolver::fromEnvironment()), {}, &warnings);
  auto& drive = *test::pluginsOf<WheeledDrive>(robot).front();
  const Eigen::Vector3d start = robot.body().linkPose("base_link").translation();
  for (int i = 0; i < 1000; ++i) {
    if (i % 100 == 0) drive.setCommand(0.3, 0, simulation.time());
    simulation.step();
  }
  return (robot.body().linkPose("base_link").translation() - start).x();
}

/// A 90-ray lidar on base_link scanning at `rate` [Hz], with `noise` (a <noise> element, or "") in its <ray>.
std::string lidarOnBase(const std::string& rate, const std::string& noise = "") {
  return "<gazebo reference='base_link'><sensor type='ray' name='lidar'><update_rate>" + rate +
         "</update_rate><ray><scan><horizontal><samples>90</samples><resolution>1</resolution>"
         "<min_angle>-3.14</min_angle><max_angle>3.14</max_angle></horizontal></scan><range><min>0.12</min>"
         "<max>3.5</max></range>" +
         noise +
         "</ray><plugin name='laser' filename='libgazebo_ros_laser.so'><topicName>scan</topicName>"
         "<frameName>base_link</frameName></plugin></sensor></gazebo>";
}

/// `urdf` with a joint_state_publisher publishing at `rate` [Hz].
std::string withJointStates(const std::string& urdf, const std::string& rate) {
  return test::withPlugin(urdf, "joint_states", "libgazebo_ros_joint_state_publisher.so",
                          {{"updateRate", rate}});
}

/// A lidar <noise> of standard deviation `stddev` [m].
std::string lidarNoise(const std::string& stddev) {
  return "<noise><type>gaussian</type><mean>0</mean><stddev>" + stddev + "</stddev></noise>";
}

/// `urdf` with a p3d on base_link whose noise has standard deviation `stddev`.
std::string withP3d(const std::string& urdf, const std::string& stddev) {
  return test::withPlugin(
      urdf, "p3d", "libgazebo_ros_p3d.so",
      {{"bodyName", "base_link"}, {"topicName", "ground_truth"}, {"gaussianNoise", stddev}});
}

struct Tolerated {
  const char* name;
  std::string urdf;
  const char* warning;  ///< the one warning's telling part; nullptr: none, as in Gazebo
};

const char* kZero[3] = {"0", "0", "0"};
const char* kNotPositiveDefinite[3] = {"-1.4e-4", "2.5e-4", "1.4e-4"};

std::vector<Tolerated> toleratedForms() {
  const std::string robot = driveable();
  const std::string lidar =
      "<gazebo reference='base_link'><sensor type='ray' name='lidar'><update_rate>10</update_rate><ray><scan>"
      "<horizontal><samples>90</samples><resolution>1</resolution><min_angle>-3.14</min_angle>"
      "<max_angle>3.14</max_angle></horizontal></scan><range><min>0.12</min><max>3.5</max></range></ray>"
      "<plugin name='laser' filename='libgazebo_ros_laser.so'><topicName>scan</topicName>"
      "<frameName>/laser_frame</frameName></plugin></sensor></gazebo>";
  const std::string ode_tags = "<mu1>1</mu1><fdir1>1 0 0</fdir1><minDepth>0.001</minDepth><maxVel>0</maxVel>";
  const std::string missing_visual =
      "<link name='logo'><visual><geometry><mesh "
      "filename='model://no_such_model/meshes/logo.dae'/></geometry>"
      "</visual></link><joint name='logo_joint' type='fixed'><parent link='base_link'/><child link='logo'/>"
      "</joint>";
  return {
      {"LeadingSlashOnFrames",
       test::withPluginTags(robot, "diff_drive.so",
                            {{"robotBaseFrame", "/base_footprint"}, {"odometryFrame", "/odom"}}),
       nullptr},
      {"BaseFrameNamingNoLink", test::withPluginTags(robot, "diff_drive.so", {{"robotBaseFrame", "chassis"}}),
       "<robotBaseFrame> [chassis] is not a link of the robot: messages carry it as their frame_id all the "
       "same, as Gazebo's do; link [base_footprint] is measured instead"},
      {"LidarFrameNamingNoLink", withElements(robot, lidar),
       "<frameName> [laser_frame] is not a link of the robot"},
      {"ZeroInertia", withInertia(robot, "left_wheel", kZero),
       "link [left_wheel]: inertia is not positive definite (principal moments 0 0 0 kg m^2); it is "
       "simulated "
       "as a solid box of 0.2 kg"},
      {"InertiaNotPositiveDefinite", withInertia(robot, "left_wheel", kNotPositiveDefinite),
       "link [left_wheel]: inertia is not positive definite"},
      {"MovingLinkWithoutMass", withInertia(robot, "right_wheel", nullptr),
       "link [right_wheel]: it has no mass; it is simulated as a solid box of 0.022 kg"},
      {"MissingVisualMesh", withElements(robot, missing_visual),
       "link [logo] <visual>: unknown model [no_such_model]"},
      {"TransmissionWithoutRosControl",
       withElements(robot,
                    "<transmission name='left_tran'><type>transmission_interface/SimpleTransmission</type>"
                    "<joint name='left_wheel_joint'><hardwareInterface>hardware_interface/"
                    "VelocityJointInterface</hardwareInterface></joint><actuator name='left_motor'>"
                    "<mechanicalReduction>1</mechanicalReduction></actuator></transmission>"),
       "<transmission> [left_tran] is not used: only libgazebo_ros_control.so reads transmissions"},
      {"OdeOnlyTagsOnEveryWheel",
       withElements(robot, "<gazebo reference='left_wheel'>" + ode_tags +
                               "</gazebo><gazebo reference='right_wheel'>" + ode_tags + "</gazebo>"),
       "Gazebo tags that bullet_sim does not model (ODE's) are ignored: <fdir1> on [left_wheel] and "
       "[right_wheel]; <maxVel> on [left_wheel] and [right_wheel]; <minDepth> on [left_wheel] and "
       "[right_wheel]"},
      {"ZeroWheelSeparation", test::withPluginTags(robot, "diff_drive.so", {{"wheelSeparation", "0"}}),
       "<wheelSeparation> 0 m disagrees with the joints [left_wheel_joint] and [right_wheel_joint], which "
       "are 0.35 m apart: the robot cannot turn, as in Gazebo"},
      {"NegativeWheelSeparation",
       test::withPluginTags(robot, "diff_drive.so", {{"wheelSeparation", "-0.35"}}),
       "<wheelSeparation> -0.35 m is below 0: the robot turns the other way from its commands, as in Gazebo, "
       "whose wheels get v -/+ w * separation / 2"},
      {"ZeroWheelDiameter", test::withPluginTags(robot, "diff_drive.so", {{"wheelDiameter", "0"}}),
       "<wheelDiameter> 0 m is not above 0: 0.1 m, the collision diameter of joint [left_wheel_joint]'s "
       "wheel, is used (Gazebo would set its wheels' speeds to the command divided by it)"},
      {"NegativeWheelDiameter", test::withPluginTags(robot, "diff_drive.so", {{"wheelDiameter", "-0.1"}}),
       "<wheelDiameter> -0.1 m is not above 0: 0.1 m, the collision diameter"},
      {"NegativeWheelAcceleration",
       test::withPluginTags(robot, "diff_drive.so", {{"wheelAcceleration", "-2"}}),
       "<wheelAcceleration> -2 m/s^2 is below 0: read as 2 m/s^2 (Gazebo's ramp would step the wheels' "
       "speeds away from the command)"},
      {"NegativeFrictionCoefficient",
       withElements(robot, "<gazebo reference='base_link'><mu1>-1</mu1></gazebo>"),
       "<gazebo reference=\"base_link\"> <mu1> [-1] is negative: read as unlimited friction, so the other "
       "surface's mu decides, as Gazebo reads it"},
      {"NegativeJointDamping", withWheelDynamics(robot, "damping", "-0.01"),
       "joints [left_wheel_joint], [right_wheel_joint] <dynamics damping> are negative: read as 0"},
      {"NegativeJointFriction", withWheelDynamics(robot, "friction", "-0.01"),
       "joints [left_wheel_joint], [right_wheel_joint] <dynamics friction> are negative: read as 0, as "
       "Gazebo's ODE reads it"},
      {"NegativeSensorUpdateRate", withElements(robot, lidarOnBase("-1")),
       "<sensor name=\"lidar\"> <update_rate> -1 is below 0: read as 0, every step, as Gazebo does"},
      {"NegativeDriveUpdateRate", test::withPluginTags(robot, "diff_drive.so", {{"updateRate", "-1"}}),
       "plugin [drive] <updateRate> -1 is below 0: read as 0, every update, as Gazebo's plugin reads it"},
      {"NegativeJointStatesUpdateRate", withJointStates(robot, "-2.5"),
       "plugin [joint_states] <updateRate> -2.5 is below 0: read as 0, every update, as Gazebo's plugin "
       "reads it"},
      {"NegativeLidarNoiseStddev", withElements(robot, lidarOnBase("10", lidarNoise("-0.01"))),
       "<noise> <stddev> -0.01 is negative: read as 0.01, as Gazebo's Gaussian noise takes it"},
      {"NegativeP3dGaussianNoise", withP3d(robot, "-0.01"),
       "plugin [p3d] <gaussianNoise> -0.01 is negative: read as 0.01, as Gazebo's Gaussian noise takes it"},
      {"NegativeImuGaussianNoise",
       test::withPlugin(robot, "imu", "libgazebo_ros_imu.so",
                        {{"bodyName", "base_link"}, {"gaussianNoise", "-0.002"}}),
       "plugin [imu] <gaussianNoise> -0.002 is negative: read as 0.002, as Gazebo's Gaussian noise takes it"},
  };
}

TEST(TolerantLoading, TheRobotLoadsClean) { EXPECT_THAT(test::loadWarnings(driveable()), IsEmpty()); }

TEST(TolerantLoading, EachFormGazeboAcceptsLoadsWithOneWarningAndDrives) {
  for (const Tolerated& form : toleratedForms()) {
    SCOPED_TRACE(form.name);
    const std::vector<std::string> warnings = test::loadWarnings(form.urdf);
    if (form.warning) {
      EXPECT_THAT(warnings, ElementsAre(HasSubstr(form.warning)));
    } else {
      EXPECT_THAT(warnings, IsEmpty());
    }
    EXPECT_GT(drivenDistance(form.urdf), 0.25) << "drives forward";
  }
}

TEST(TolerantLoading, FramesLoseTheirLeadingSlashAndKeepTheirNames) {
  const std::vector<Tolerated> forms = toleratedForms();
  const auto config = [&](int i) {
    const ModelSpec model = parseModel(forms[i].urdf, "robot", PackageResolver::fromEnvironment());
    return *model.plugins.front().configAs<DriveConfig>();
  };
  EXPECT_EQ(config(0).robot_base_frame, "base_footprint");
  EXPECT_EQ(config(0).odometry_frame, "odom");
  EXPECT_EQ(config(1).robot_base_frame, "chassis") << "the odometry's child_frame_id, as Gazebo's";
  EXPECT_EQ(config(1).base_link, "base_footprint");
  const ModelSpec lidar = parseModel(forms[2].urdf, "robot", PackageResolver::fromEnvironment(), nullptr);
  const auto* scan = lidar.plugins.back().configAs<RayLidarConfig>();
  ASSERT_TRUE(scan);
  EXPECT_EQ(scan->frame, "laser_frame");
  EXPECT_EQ(scan->link, "base_link");
}

TEST(TolerantLoading, NegativeDampingAndJointFrictionAreReadAsZeroANegativeMuAsUnlimited) {
  const auto parsed = [](const std::string& urdf) {
    return parseModel(urdf, "robot", PackageResolver::fromEnvironment(), nullptr);
  };
  const std::string robot = driveable();
  EXPECT_EQ(parsed(withElements(robot, "<gazebo reference='base_link'><mu1>-1</mu1></gazebo>"))
                .link("base_link")->surface.mu1, SurfaceSpec::kUnlimitedMu);
  EXPECT_EQ(parsed(withWheelDynamics(robot, "damping", "-0.01")).joint("left_wheel_joint")->damping, 0.0);
  EXPECT_EQ(parsed(withWheelDynamics(robot, "friction", "-0.01")).joint("left_wheel_joint")->friction, 0.0);
  EXPECT_EQ(parsed(withWheelDynamics(robot, "damping", "0.01")).joint("left_wheel_joint")->damping, 0.01);
}

/// How many scans, odometries and joint states the robot of `urdf` publishes in 20 steps (1 ms each).
std::array<uint64_t, 3> publishedIn20Steps(const std::string& urdf) {
  Simulation simulation(test::shippedWorld("empty.world"));
  std::vector<std::string> warnings;
  Robot& robot =
      simulation.spawn("robot", parseModel(urdf, "robot", PackageResolver::fromEnvironment()), {}, &warnings);
  for (int i = 0; i < 20; ++i) simulation.step();
  return {test::countOf<LaserScan>(*test::pluginsOf<RayLidar>(robot).front()),
          test::countOf<Odometry>(*test::pluginsOf<WheeledDrive>(robot).front()),
          test::countOf<JointStateSample>(*test::pluginsOf<JointStates>(robot).front())};
}

TEST(TolerantLoading, ANegativeUpdateRateIsEveryStepAsGazebosZero) {
  const auto rates = [](const std::string& sensor, const std::string& plugins) {
    const std::string urdf =
        withJointStates(test::withPluginTags(withElements(driveable(), lidarOnBase(sensor)), "diff_drive.so",
                                             {{"updateRate", plugins}}),
                        plugins);
    return publishedIn20Steps(urdf);
  };
  EXPECT_THAT(rates("-1", "-1"), ElementsAre(20, 20, 20)) << "every step, as a rate of 0";
  EXPECT_THAT(rates("0", "0"), ElementsAre(20, 20, 20));
  EXPECT_THAT(rates("100", "100"), ElementsAre(2, 2, 2)) << "a rate above 0 still paces them";
  const ModelSpec model = parseModel(withElements(driveable(), lidarOnBase("-1")), "robot",
                                     PackageResolver::fromEnvironment(), nullptr);
  EXPECT_EQ(model.plugins.back().sensor->update_rate, 0.0);
  EXPECT_EQ(model.plugins.back().configAs<RayLidarConfig>()->update_rate, 0.0);
}

TEST(TolerantLoading, AnUpdateRateThatIsNoNumberStaysAnError) {
  EXPECT_THAT(test::loadErrors(withElements(driveable(), lidarOnBase("fast"))),
              ElementsAre(HasSubstr("<update_rate> must be a number [Hz], not [fast]")));
  EXPECT_THAT(test::loadErrors(test::withPluginTags(driveable(), "diff_drive.so", {{"updateRate", "x"}})),
              ElementsAre(HasSubstr("<updateRate> must be a number, not [x]")));
}

/// The ranges of the first scan of the lidar, and the first pose p3d gives, of `urdf`'s robot in the test
/// room (walls 2 and 3 m away), whose lidar scans and p3d publishes every step.
std::pair<std::vector<float>, Eigen::Vector3d> firstReadings(const std::string& urdf) {
  Simulation simulation(test::shippedWorld("test_room.world"));
  std::vector<std::string> warnings;
  Robot& robot =
      simulation.spawn("robot", parseModel(urdf, "robot", PackageResolver::fromEnvironment()), {}, &warnings);
  simulation.step();
  return {test::latestOf<LaserScan>(*test::pluginsOf<RayLidar>(robot).front()).ranges,
          test::latestOf<Odometry>(*test::pluginsOf<GroundTruth>(robot).front()).pose.translation()};
}

TEST(TolerantLoading, ANegativeNoiseStddevDrawsAsItsAbsoluteValue) {
  const auto readings = [](const std::string& stddev) {
    return firstReadings(withP3d(withElements(driveable(), lidarOnBase("0", lidarNoise(stddev))), stddev));
  };
  const auto negative = readings("-0.01"), positive = readings("0.01"), exact = readings("0");
  EXPECT_EQ(negative.first, positive.first) << "the same seeded draws, scaled by 0.01";
  EXPECT_EQ(negative.second, positive.second);
  EXPECT_NE(negative.first, exact.first) << "noisy";
  EXPECT_NE(negative.second, exact.second);
  const ModelSpec model = parseModel(withElements(driveable(), lidarOnBase("10", lidarNoise("-0.01"))),
                                     "robot", PackageResolver::fromEnvironment(), nullptr);
  EXPECT_EQ(model.plugins.back().configAs<RayLidarConfig>()->noise_stddev, 0.01);
}

TEST(TolerantLoading, AWheelTorqueNotAboveZeroLoadsAndTheRobotDoesNotDrive) {
  for (const std::string& wheel_model : test::kWheelModels) {
    for (const char* torque : {"0", "-30"}) {
      SCOPED_TRACE(wheel_model + ", wheelTorque " + torque);
      const std::string urdf = test::withWheelModel(
          test::withPluginTags(driveable(), "diff_drive.so", {{"wheelTorque", torque}}), wheel_model);
      EXPECT_THAT(test::loadWarnings(urdf),
                  ElementsAre(HasSubstr("<wheelTorque> " + std::string(torque) +
                                        " N m is not above 0: its motors give none, as in Gazebo")));
      EXPECT_LT(std::abs(drivenDistance(urdf)), 0.005) << "the wheels give no torque";
    }
  }
}

TEST(TolerantLoading, ANegativeWheelAccelerationRampsByItsAbsoluteValue) {
  const auto accelerated = [](const char* acceleration) {
    return test::withPluginTags(driveable(), "diff_drive.so", {{"wheelAcceleration", acceleration}});
  };
  const double negative = drivenDistance(accelerated("-0.5"));
  EXPECT_EQ(negative, drivenDistance(accelerated("0.5"))) << "the same ramp";
  EXPECT_GT(drivenDistance(accelerated("0")) - negative, 0.06)
      << "it lags the unramped robot, by up to v^2 / (2 a) = 0.09 m";
}

/// The drive's config, read from `urdf`.
DriveConfig driveConfig(const std::string& urdf) {
  const ModelSpec model = parseModel(urdf, "robot", PackageResolver::fromEnvironment(), nullptr);
  return *model.plugins.front().configAs<DriveConfig>();
}

TEST(TolerantLoading, AWheelDiameterNotAboveZeroIsTheWheelsCollisions) {
  for (const char* diameter : {"0", "-0.1"}) {
    EXPECT_DOUBLE_EQ(driveConfig(test::withPluginTags(driveable(), "diff_drive.so",
                                                      {{"wheelDiameter", diameter}})).wheel_diameter, 0.1);
  }
  const std::string box_wheels = test::editUrdf(
      test::withPluginTags(driveable(), "diff_drive.so", {{"wheelDiameter", "0"}}),
      [](tinyxml2::XMLElement& robot) {
        for (auto* link = robot.FirstChildElement("link"); link; link = link->NextSiblingElement("link")) {
          if (std::string(link->Attribute("name")).find("wheel") == std::string::npos) continue;
          auto* geometry = link->FirstChildElement("collision")->FirstChildElement("geometry");
          geometry->DeleteChildren();
          geometry->InsertNewChildElement("box")->SetAttribute("size", "0.1 0.03 0.1");
        }
      });
  EXPECT_THAT(test::loadErrors(box_wheels),
              ElementsAre(HasSubstr("<wheelDiameter> 0 m is not above 0, and no wheel has a collision "
                                    "cylinder or sphere to measure it by")));
}

/// Where the base is and where its encoder odometry says it is, after 1 s of 0.3 m/s and 1 rad/s under a
/// diff drive's `separation`.
struct EncoderRun {
  Eigen::Isometry3d base, odometry;
};
EncoderRun driveWithEncoders(const std::string& separation) {
  const std::string urdf = test::withPluginTags(
      driveable(), "diff_drive.so", {{"wheelSeparation", separation}, {"odometrySource", "encoder"}});
  Simulation simulation(test::shippedWorld("empty.world"));
  std::vector<std::string> warnings;
  Robot& robot =
      simulation.spawn("robot", parseModel(urdf, "robot", PackageResolver::fromEnvironment()), {}, &warnings);
  auto& drive = *test::pluginsOf<WheeledDrive>(robot).front();
  test::stepSending(simulation, 1.0, [&] { return drive.setCommand(0.3, 1.0, simulation.time()); });
  return {robot.body().linkPose("base_link"), test::latestOf<Odometry>(drive).pose};
}

TEST(TolerantLoading, AZeroWheelSeparationWithEncoderOdometryDividesByTheJointsSeparation) {
  const std::string urdf = test::withPluginTags(driveable(), "diff_drive.so",
                                                {{"wheelSeparation", "0"}, {"odometrySource", "encoder"}});
  EXPECT_THAT(test::loadWarnings(urdf),
              ElementsAre(HasSubstr("<wheelSeparation> 0 m disagrees with the joints [left_wheel_joint] "
                                    "and [right_wheel_joint], which are 0.35 m apart: the robot cannot turn, "
                                    "as in Gazebo; the encoder odometry divides by their 0.35 m instead "
                                    "(Gazebo's would be NaN)")));
  EXPECT_NEAR(driveConfig(urdf).encoder_separation, 0.35, 1e-12);
  const Eigen::Isometry3d odometry = driveWithEncoders("0").odometry;
  EXPECT_GT(odometry.translation().x(), 0.2) << "it drives";
  EXPECT_NEAR(Eigen::AngleAxisd(odometry.rotation()).angle(), 0, 0.05)
      << "straight on, as it cannot turn, and its odometry, not NaN, says so";
}

/// The yaw [rad] of `rotation`, a turn about z.
double yawOf(const Eigen::Matrix3d& rotation) { return std::atan2(rotation(1, 0), rotation(0, 0)); }

/// The base's yaw and its encoder odometry's [rad] after 1 s of 0.3 m/s and 1 rad/s, under `separation`.
std::pair<double, double> yawsTurning(const std::string& separation) {
  const EncoderRun run = driveWithEncoders(separation);
  return {yawOf(run.base.linear()), yawOf(run.odometry.linear())};
}

TEST(TolerantLoading, ANegativeWheelSeparationTurnsTheOtherWayAndEncoderOdometryFollows) {
  const std::string urdf = test::withPluginTags(
      driveable(), "diff_drive.so", {{"wheelSeparation", "-0.35"}, {"odometrySource", "encoder"}});
  EXPECT_THAT(test::loadWarnings(urdf),
              ElementsAre(HasSubstr("<wheelSeparation> -0.35 m is below 0: the robot turns the other way "
                                    "from its commands, as in Gazebo, whose wheels get v -/+ w * separation "
                                    "/ 2; the encoder odometry divides by 0.35 m, so it follows the robot "
                                    "(Gazebo's turns the other way from it)")));
  EXPECT_EQ(driveConfig(urdf).encoder_separation, 0.35);
  const auto [yaw, odometry_yaw] = yawsTurning("-0.35");
  const auto [mirror_yaw, mirror_odometry_yaw] = yawsTurning("0.35");
  EXPECT_GT(mirror_yaw, 0.5) << "0.35 turns left, as commanded";
  EXPECT_NEAR(yaw, -mirror_yaw, 0.02) << "-0.35 turns right as far";
  EXPECT_NEAR(odometry_yaw, -mirror_odometry_yaw, 0.02) << "and its odometry says so, as 0.35's says left";
}

/// driveable() with the left wheel's <axis xyz> `xyz`.
std::string withLeftWheelAxis(const std::string& xyz) {
  return test::editUrdf(driveable(), [&](tinyxml2::XMLElement& robot) {
    for (auto* joint = robot.FirstChildElement("joint"); joint; joint = joint->NextSiblingElement("joint")) {
      if (std::string(joint->Attribute("name")) == "left_wheel_joint")
        joint->FirstChildElement("axis")->SetAttribute("xyz", xyz.c_str());
    }
  });
}

TEST(TolerantLoading, ATinyAxisIsItsDirectionAZeroOneIsNamedWithItsValue) {
  EXPECT_THAT(test::loadWarnings(withLeftWheelAxis("0 1e-12 0")),
              ElementsAre(HasSubstr("joint [left_wheel_joint] <axis xyz=\"0 1e-12 0\"> is 1e-12 long: read "
                                    "as its direction, 0 1 0, as Gazebo's ODE normalizes it")));
  const ModelSpec model =
      parseModel(withLeftWheelAxis("0 1e-12 0"), "robot", PackageResolver::fromEnvironment(), nullptr);
  EXPECT_EQ(model.joint("left_wheel_joint")->axis, Eigen::Vector3d::UnitY());
  EXPECT_GT(drivenDistance(withLeftWheelAxis("0 1e-12 0")), 0.25) << "drives forward";
  EXPECT_THAT(test::loadErrors(withLeftWheelAxis("0 0 0")),
              ElementsAre(HasSubstr("joint [left_wheel_joint] <axis xyz=\"0 0 0\"> is zero")));
}

TEST(TolerantLoading, FixedChildrenAreLumpedBeforeTheInertiaIsJudged) {
  // A zero inertia on a link fixed to a sound one is no problem once lumped, as in Gazebo.
  const char* zero[3] = {"0", "0", "0"};
  const std::string urdf = withElements(
      withInertia(driveable(), "left_wheel", nullptr),
      "<link name='hub'><inertial><mass value='0.2'/><inertia ixx='1.4e-4' ixy='0' ixz='0' iyy='2.5e-4' "
      "iyz='0' izz='1.4e-4'/></inertial></link><joint name='hub_joint' type='fixed'><parent "
      "link='left_wheel'/><child link='hub'/></joint>");
  EXPECT_THAT(test::loadWarnings(urdf), IsEmpty()) << "the wheel's mass is its hub's";
  EXPECT_THAT(test::loadWarnings(withInertia(urdf, "hub", zero)),
              ElementsAre(HasSubstr("link [left_wheel] with the links fixed to it, lumped as Gazebo does,")));
}

TEST(TolerantLoading, AnSdfModelsPoorInertiaIsMendedToo) {
  const std::string sdf =
      "<sdf version='1.6'><model name='crate'><link name='body'><inertial><mass>4</mass><inertia><ixx>0</ixx>"
      "<iyy>0</iyy><izz>0</izz></inertia></inertial><collision name='c'><geometry><box><size>0.5 0.5 "
      "0.5</size>"
      "</box></geometry></collision></link></model></sdf>";
  std::vector<std::string> warnings;
  const ModelSpec crate = parseSdfModel(sdf, "crate.sdf", PackageResolver::fromEnvironment(),
                                        PluginRegistry::builtin(), &warnings);
  EXPECT_THAT(warnings,
              ElementsAre(HasSubstr("link [body]: inertia is not positive definite (principal moments "
                                    "0 0 0 kg m^2); it is simulated as a solid box of 4 kg")));
  const Eigen::Vector3d moments = crate.link("body")->inertial->inertia.diagonal();
  EXPECT_TRUE(moments.isApprox(Eigen::Vector3d::Constant(4.0 / 12 * 0.5), 1e-12)) << moments.transpose();
}

TEST(TolerantLoading, AnSdfModelsNegativeDampingIsReadAsZero) {
  const std::string sdf =
      "<sdf version='1.6'><model name='cart'><link name='body'><collision name='c'><geometry><box><size>0.5 "
      "0.5 0.5</size></box></geometry></collision></link><link name='wheel'/><joint name='axle' "
      "type='revolute'><parent>body</parent>"
      "<child>wheel</child><axis><xyz>0 1 0</xyz><dynamics><damping>-2</damping></dynamics></axis></joint>"
      "</model></sdf>";
  std::vector<std::string> warnings;
  const ModelSpec cart = parseSdfModel(sdf, "cart.sdf", PackageResolver::fromEnvironment(),
                                       PluginRegistry::builtin(), &warnings);
  EXPECT_THAT(warnings,
              testing::Contains(HasSubstr("joint [axle]: <dynamics><damping> [-2] is negative: read as 0")));
  EXPECT_EQ(cart.joint("axle")->damping, 0.0);
}

TEST(TolerantLoading, AFilesErrorsOfEveryKindComeOutTogether) {
  const std::string urdf = withElements(
      test::withPluginTags(withInertia(driveable(), "right_wheel", nullptr), "diff_drive.so",
                           {{"wheelSeparation", "wide"}}),
      "<link name='bumper'><inertial><mass value='-1'/><inertia ixx='1' ixy='0' ixz='0' iyy='1' iyz='0' "
      "izz='1'/></inertial><collision><geometry><mesh filename='package://bullet_sim/no_such.stl'/>"
      "</geometry></collision><collision><geometry><box size='0.1 -0.1 0.1'/></geometry></collision></link>"
      "<joint name='bumper_joint' type='fixed'><parent link='base_link'/><child link='bumper'/></joint>"
      "<gazebo reference='bumpr'><mu1>1</mu1></gazebo>");
  EXPECT_THAT(test::loadErrors(urdf),
              testing::UnorderedElementsAre(
                  HasSubstr("link [bumper] <collision> <box size=\"0.1 -0.1 0.1\">: [-0.1] must be positive"),
                  HasSubstr("link [bumper] <inertial>: mass -1 kg is not positive"),
                  HasSubstr("link [bumper] <collision>: cannot load mesh"),
                  HasSubstr("<wheelSeparation> must be a number, not [wide]")));
}

/// `driveable()` with a box link whose size starts with `word`.
std::string withBoxOf(const std::string& word) {
  return withElements(driveable(),
                      "<link name='box'><collision><geometry><box size='" + word +
                          " 0.1 0.1'/></geometry></collision></link><joint name='box_joint' type='fixed'>"
                          "<parent link='base_link'/><child link='box'/></joint>");
}

TEST(TolerantLoading, NumbersAreDecimalAsUrdfdomReadsThem) {
  for (const std::string word : {"0.5", "+0.5", ".5", "5.", "5e-1", "0.05E+1", "50e-2"}) {
    EXPECT_THAT(test::loadErrors(withBoxOf(word)), IsEmpty()) << word;
  }
  for (const std::string word :
       {"0x1", "inf", "nan", "1e", "+-1", "--1", ".", "1.5.2", "e5", "1e+", "0.5f", "1,5"}) {
    EXPECT_THAT(test::loadErrors(withBoxOf(word)), ElementsAre(HasSubstr("[" + word + "] is not a number")))
        << word;
  }
}

TEST(TolerantLoading, AnUnknownModelUriNamesTheModel) {
  const std::string visual =
      "<link name='logo'><visual><geometry><mesh filename='MESH'/></geometry></visual>"
      "</link><joint name='logo_joint' type='fixed'><parent link='base_link'/>"
      "<child link='logo'/></joint>";
  const auto warningFor = [&](const std::string& uri) {
    const auto warnings =
        test::loadWarnings(withElements(driveable(), test::replaceAfter(visual, "", "MESH", uri)));
    return warnings.empty() ? std::string() : warnings.front();
  };
  EXPECT_THAT(warningFor("model://no_such_model/meshes/logo.dae"),
              AllOf(HasSubstr("unknown model [no_such_model]"), Not(HasSubstr("meshes/logo.dae"))));
  EXPECT_THAT(warningFor("model://cafe_table/meshes/no_such.dae"),
              HasSubstr("model [cafe_table] has no file [meshes/no_such.dae]"));
}

TEST(TolerantLoading, AWorldThatCannotBeReadFallsBackOnTheEmptyWorld) {
  const PackageResolver resolver = PackageResolver::fromEnvironment();
  const std::string broken = (std::filesystem::temp_directory_path() / "tolerant_broken.world").string();
  std::ofstream(broken) << "<sdf version='1.6'><world name='w'><model name='m'></world></sdf>\n";
  for (const std::string& name : {std::string("no_such.world"), broken}) {
    SCOPED_TRACE(name);
    std::vector<std::string> warnings;
    std::string path;
    const WorldSpec world = loadWorldOrFallback(name, "empty.world", resolver, &warnings, {}, &path);
    EXPECT_THAT(path, HasSubstr("empty.world"));
    EXPECT_THAT(warnings, ElementsAre(AllOf(HasSubstr("falling back on empty.world, as gzserver does"),
                                            HasSubstr(name))));
    EXPECT_THROW(loadWorldOrFallback(name, "", resolver, &warnings), std::runtime_error) << "no fallback";
  }
  WorldOptions strict;
  strict.strict_models = true;
  EXPECT_THROW(loadWorldOrFallback(broken, "empty.world", resolver, nullptr, strict), std::runtime_error)
      << "strict: refused";
  std::filesystem::remove(broken);
}

}  // namespace
}  // namespace bullet_sim
