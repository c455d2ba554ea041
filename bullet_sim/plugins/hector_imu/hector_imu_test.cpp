// hector's IMU against the ground truth, at rest and on the moving multi-sensor test robot
// (test/fixtures/robots/multi_sensor_robot.urdf.xacro): gravity, offsets, drift, calibration, seeds and load
// messages. Stepped in-process, no roscore.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "plugins/hector_imu/hector_imu.h"
#include "plugins/planar_move/planar_move.h"
#include "bullet_sim/simulation/simulation.h"
#include "test/multi_sensor_robot.h"
#include "test/test_support.h"

namespace bullet_sim {
namespace {

using test::loadErrors;
using test::loadWarnings;
using test::multiSensorRobot;
using test::multiSensorUrdf;
using test::parseExpecting;
using test::withoutPluginTags;

using ::testing::Contains;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

constexpr double kGravity = 9.81;
const std::string kImuPlugin = "libhector_gazebo_ros_imu.so";
const std::string kBiasTopic = "imu/data/bias";  // the multi-sensor robot's IMU publishes on imu/data

/// The multi-sensor robot's IMU with every error model off but the tags in `tags`.
std::string idealImu(const test::Tags& tags = {}) {
  test::Tags all = {{"accelDrift", "0 0 0"}, {"accelGaussianNoise", "0 0 0"}, {"rateDrift", "0 0 0"},
                    {"rateGaussianNoise", "0 0 0"}, {"yawDrift", "0"}, {"yawGaussianNoise", "0"}};
  all.insert(all.end(), tags.begin(), tags.end());
  return test::withPluginTags(multiSensorUrdf(), kImuPlugin, all);
}

/// The samples of `imu` over `seconds` of sim time.
std::vector<ImuSample> imuSamples(Simulation& simulation, const HectorImu& imu, double seconds) {
  std::vector<ImuSample> samples;
  const double end = simulation.time() + seconds;
  while (simulation.time() < end - 1e-9) {
    const uint64_t count = test::countOf<ImuSample>(imu);
    simulation.step();
    if (test::countOf<ImuSample>(imu) != count) samples.push_back(test::latestOf<ImuSample>(imu));
  }
  return samples;
}

TEST(HectorImu, AtRestReadsGravityUpAndNoRotationWithinItsNoise) {
  Simulation simulation(test::shippedWorld("empty.world"), {.seed = 3});
  Robot& robot = simulation.spawn("robot", multiSensorRobot(), {.x = 1, .yaw = 0.7});
  const HectorImu& imu = *test::pluginsOf<HectorImu>(robot).at(0);
  for (int i = 0; i < 500; ++i) simulation.step();  // settled
  const std::vector<ImuSample> samples = imuSamples(simulation, imu, 4.0);
  ASSERT_EQ(samples.size(), 200u) << "50 Hz";
  Eigen::Vector3d accel = Eigen::Vector3d::Zero(), rate = Eigen::Vector3d::Zero();
  for (const auto& sample : samples) {
    accel += sample.linear_acceleration / samples.size();
    rate += sample.angular_velocity / samples.size();
  }
  // The drift starts at N(0, 0.005^2) per axis: 4 sigma of it, and of the white noise's mean.
  const double bound = 4 * 0.005 + 4 * 0.005 / std::sqrt(200.0);
  EXPECT_NEAR(accel.x(), 0, bound);
  EXPECT_NEAR(accel.y(), 0, bound);
  EXPECT_NEAR(accel.z(), kGravity, bound);
  EXPECT_LT(rate.norm(), 2 * bound);
  EXPECT_GT((samples[0].angular_velocity - samples[1].angular_velocity).norm(), 0) << "the noise is on";
  const ImuSample& last = samples.back();
  EXPECT_EQ(last.frame_id, "imu_link");
  EXPECT_DOUBLE_EQ(last.angular_velocity_variance.x(), 0.005 * 0.005);
  EXPECT_DOUBLE_EQ(last.linear_acceleration_variance.z(), 0.005 * 0.005);
  EXPECT_NEAR(last.orientation_variance.x(), 0.005 * 0.005 / (kGravity * kGravity), 1e-15);
  EXPECT_DOUBLE_EQ(last.orientation_variance.z(), 0.005 * 0.005);
}

TEST(HectorImu, WithoutErrorsMatchesTheGroundTruth) {
  Simulation simulation(test::shippedWorld("empty.world"));
  Robot& robot = simulation.spawn("robot", parseExpecting(idealImu(), "ideal"), {.x = 1, .yaw = 0.7});
  const HectorImu& imu = *test::pluginsOf<HectorImu>(robot).at(0);
  for (int i = 0; i < 500; ++i) simulation.step();
  for (const ImuSample& sample : imuSamples(simulation, imu, 1.0)) {
    const Eigen::Quaterniond truth(robot.body().linkPose("imu_link").linear());
    EXPECT_LT(sample.orientation.angularDistance(truth), 1e-9);
    EXPECT_LT((sample.linear_acceleration - Eigen::Vector3d(0, 0, kGravity)).norm(), 1e-3);
    EXPECT_LT(sample.angular_velocity.norm(), 1e-3);
  }
  EXPECT_NEAR(Eigen::AngleAxisd(test::latestOf<ImuSample>(imu).orientation).angle(), 0.7, 1e-3)
      << "yaw 0.7 at spawn";
}

TEST(HectorImu, OffsetsShowInTheReadingAndTheBiasTopic) {
  Simulation simulation(test::shippedWorld("empty.world"));
  const std::string urdf = idealImu({{"rateOffset", "0.1 0 0"}, {"accelOffset", "0 0.2 0"}});
  Robot& robot = simulation.spawn("robot", parseExpecting(urdf, "offsets"), {});
  const HectorImu& imu = *test::pluginsOf<HectorImu>(robot).at(0);
  for (int i = 0; i < 500; ++i) simulation.step();
  const ImuSample& sample = test::latestOf<ImuSample>(imu);
  const ImuSample& bias = test::latestOf<ImuSample>(imu, kBiasTopic);
  EXPECT_NEAR(sample.angular_velocity.x(), 0.1, 1e-3);
  EXPECT_NEAR(sample.linear_acceleration.y(), 0.2, 1e-3);
  EXPECT_TRUE(bias.angular_velocity.isApprox(Eigen::Vector3d(0.1, 0, 0)));
  EXPECT_TRUE(bias.linear_acceleration.isApprox(Eigen::Vector3d(0, 0.2, 0)));
  // The accelerometer's bias tilts the orientation as hector's pseudo-AHRS does: 0.2 m/s^2 to the left rolls
  // it by about 0.2 / g.
  EXPECT_NEAR(Eigen::AngleAxisd(bias.orientation).angle(), 0.2 / kGravity, 1e-4);
}

TEST(HectorImu, CalibrateZeroesTheRateDrift) {
  Simulation simulation(test::shippedWorld("empty.world"), {.seed = 5});
  const std::string urdf = idealImu({{"rateDrift", "0.1 0.1 0.1"}});
  Robot& robot = simulation.spawn("robot", parseExpecting(urdf, "drift"), {});
  const HectorImu& imu = *test::pluginsOf<HectorImu>(robot).at(0);
  for (int i = 0; i < 100; ++i) simulation.step();
  EXPECT_GT(test::latestOf<ImuSample>(imu, kBiasTopic).angular_velocity.norm(), 0.01)
      << "drawn from N(0, 0.1^2) per axis";
  const auto& ports = imu.ports().services;
  ASSERT_EQ(ports.size(), 1u);
  EXPECT_EQ(ports[0].name, "imu/data/calibrate");
  EmptyRequest::Reply reply;
  EXPECT_EQ(std::get<ServiceHandler<EmptyRequest>>(ports[0].handler)(EmptyRequest{}, reply), "");
  simulation.step();
  for (int i = 0; i < 20; ++i) simulation.step();
  EXPECT_LT(test::latestOf<ImuSample>(imu, kBiasTopic).angular_velocity.norm(), 1e-3)
      << "the drift restarts from zero";
}

TEST(HectorImu, TheSameSeedGivesTheSameReadings) {
  const auto run = [](uint64_t seed) {
    Simulation simulation(test::shippedWorld("empty.world"), {.seed = seed});
    Robot& robot = simulation.spawn("robot", multiSensorRobot(), {});
    std::vector<double> readings;
    for (const ImuSample& sample : imuSamples(simulation, *test::pluginsOf<HectorImu>(robot).at(0), 0.5)) {
      readings.push_back(sample.linear_acceleration.x());
      readings.push_back(sample.orientation.z());
    }
    simulation.resetSimulation();
    const ImuSample after_reset =
        imuSamples(simulation, *test::pluginsOf<HectorImu>(robot).at(0), 0.5).back();
    EXPECT_EQ(after_reset.linear_acceleration.x(), readings[readings.size() - 2])
        << "a reset replays the run";
    return readings;
  };
  EXPECT_EQ(run(11), run(11));
  EXPECT_NE(run(11), run(12));
}

TEST(HectorImu, LoadMessages) {
  const std::string husky_style = test::withPluginTags(
      idealImu(), kImuPlugin, {{"headingDrift", "0.01"}, {"headingGaussianNoise", "0.02"}});
  const std::vector<std::string> warnings = loadWarnings(husky_style);
  EXPECT_THAT(warnings, Contains(HasSubstr("<headingDrift> is hector's old name of <yawDrift>, which today's "
                                           "hector ignores: ignored, since <yawDrift> is given")));
  const std::string without_yaw =
      withoutPluginTags(husky_style, kImuPlugin, {"yawDrift", "yawGaussianNoise"});
  EXPECT_THAT(loadWarnings(without_yaw),
              Contains(HasSubstr("<headingGaussianNoise> is hector's old name of <yawGaussianNoise>, which "
                                 "today's hector ignores: read as <yawGaussianNoise>")));
  const ModelSpec model = parseModel(without_yaw, "robot", PackageResolver::fromEnvironment());
  for (const auto& plugin : model.plugins) {
    if (const auto* config = plugin.configAs<HectorImuConfig>()) {
      EXPECT_DOUBLE_EQ(config->yaw.drift.x(), 0.01);
      EXPECT_DOUBLE_EQ(config->yaw.gaussian_noise.x(), 0.02);
    }
  }
  EXPECT_THAT(warnings, Contains(HasSubstr("hector's [imu/data/set_accel_bias] and [imu/data/set_rate_bias] "
                                           "services and its dynamic_reconfigure servers need hector's own "
                                           "types, which Debian lacks: left out")));
  const std::string bad =
      test::withPluginTags(idealImu(), kImuPlugin, {{"accelDrift", "0.1 0.1"}, {"bodyName", "imu_lnk"}});
  EXPECT_THAT(loadErrors(bad),
              ElementsAre(HasSubstr("<accelDrift> must be three numbers (x y z), not [0.1 0.1]")));
  EXPECT_THAT(
      loadWarnings(test::withPluginTags(idealImu(), kImuPlugin, {{"bodyName", "imu_lnk"}})),
      Contains(HasSubstr("<bodyName> [imu_lnk] is not a link of the robot (did you mean [imu_link]?): "
                         "messages carry it as their frame_id all the same, as Gazebo's do; link "
                         "[base_footprint] is measured instead")));
}

TEST(HectorImu, ANegativeGaussianNoiseIsReadAsItsAbsoluteValueWithAWarning) {
  // hector's kernel draws sigma * X + mu, as Gazebo does with any sign of sigma.
  const std::string urdf = idealImu({{"accelGaussianNoise", "-0.1 0.2 -0.3"},
                                     {"yawGaussianNoise", "-0.05"},
                                     {"gaussianNoise", "0"},
                                     {"updateRate", "-1"}});
  const std::vector<std::string> warnings = loadWarnings(urdf);
  EXPECT_THAT(warnings, Contains(HasSubstr("<accelGaussianNoise> -0.1 0.2 -0.3 has a negative component: "
                                           "read as 0.1 0.2 0.3, as Gazebo's Gaussian noise takes it")));
  EXPECT_THAT(warnings, Contains(HasSubstr("<yawGaussianNoise> -0.05 is negative: read as 0.05")));
  EXPECT_THAT(warnings, Contains(HasSubstr("<updateRate> -1 is below 0: read as 0, every update")));
  const ModelSpec model = parseModel(urdf, "robot", PackageResolver::fromEnvironment());
  for (const auto& plugin : model.plugins) {
    if (const auto* config = plugin.configAs<HectorImuConfig>()) {
      EXPECT_EQ(config->accel.gaussian_noise, Eigen::Vector3d(0.1, 0.2, 0.3));
      EXPECT_EQ(config->yaw.gaussian_noise.x(), 0.05);
      EXPECT_EQ(config->update_rate, 0.0);
    }
  }
  EXPECT_THAT(loadWarnings(idealImu({{"gaussianNoise", "-0.01"}})),
              Contains(HasSubstr("<gaussianNoise> -0.01 is negative: read as 0.01")));
}

TEST(HectorImu, ANegativeDriftOrDriftFrequencyIsReadAsItsAbsoluteValueWithAWarning) {
  // hector draws the drift with sigma sqrt(2 * frequency) * drift: any sign of drift, NaN below 0 frequency.
  const std::string urdf = idealImu({{"accelDrift", "-0.1 0 0"}, {"accelDriftFrequency", "-0.5 0.5 0.5"}});
  EXPECT_THAT(loadWarnings(urdf),
              testing::IsSupersetOf(
                  {HasSubstr("<accelDrift> -0.1 0 0 has a negative component: read as 0.1 0 0, as Gazebo's "
                             "Gaussian noise takes it"),
                   HasSubstr("<accelDriftFrequency> -0.5 0.5 0.5 has a negative component: read as 0.5 0.5 "
                             "0.5 (hector's drift would be NaN: it draws with sqrt(2 * frequency) * "
                             "drift)")}));
  Simulation simulation(test::shippedWorld("empty.world"), {.seed = 3});
  Robot& robot = simulation.spawn("robot", parseModel(urdf, "robot", PackageResolver::fromEnvironment()), {});
  const HectorImu& imu = *test::pluginsOf<HectorImu>(robot).at(0);
  EXPECT_EQ(imu.config().accel.drift, Eigen::Vector3d(0.1, 0, 0));
  EXPECT_EQ(imu.config().accel.drift_frequency, Eigen::Vector3d::Constant(0.5));
  const std::vector<ImuSample> samples = imuSamples(simulation, imu, 2.0);
  ASSERT_EQ(samples.size(), 100u);
  for (const ImuSample& sample : samples) ASSERT_TRUE(sample.linear_acceleration.allFinite());
}

TEST(HectorImu, ANegativeUpdatePeriodIsItsAbsoluteValueWithAWarning) {
  // hector's UpdateTimer::checkUpdate updates when fmod(time, period) is within a step: any sign of period.
  const std::string urdf = idealImu({{"updatePeriod", "-0.1"}});
  const std::string warning = "<updatePeriod> -0.1 s is below 0: read as 0.1 s, as hector's update timer "
                              "takes it (fmod of the time by the period ignores its sign)";
  EXPECT_THAT(loadWarnings(urdf), Contains(HasSubstr(warning)));
  Simulation simulation(test::shippedWorld("empty.world"));
  Robot& robot =
      simulation.spawn("robot", parseExpecting(urdf, "imu", {warning, test::kHectorWarnings[0]}), {});
  const HectorImu& imu = *test::pluginsOf<HectorImu>(robot).at(0);
  EXPECT_EQ(imu.config().update_rate, 10.0);
  EXPECT_EQ(imuSamples(simulation, imu, 1.0).size(), 10u) << "10 Hz";
}

// On the moving robot.

const SpawnPose kStart{.x = 0.5, .y = -0.3, .yaw = 0.4};

TEST(HectorImu, WithoutErrorsMatchesTheGroundTruthWhileTurning) {
  const std::string urdf = test::withPluginTags(
      multiSensorUrdf(), "libhector_gazebo_ros_imu.so",
      {{"accelDrift", "0 0 0"}, {"accelGaussianNoise", "0 0 0"}, {"rateDrift", "0 0 0"},
       {"rateGaussianNoise", "0 0 0"}, {"yawDrift", "0"}, {"yawGaussianNoise", "0"}});
  Simulation simulation(test::shippedWorld("empty.world"));
  Robot& robot = simulation.spawn("robot", parseExpecting(urdf, "ideal imu"), kStart);
  test::drivePlanar(simulation, *test::pluginsOf<PlanarMove>(robot).at(0), test::twist(0.3, 0.2, 0.5), 2.0);
  const ImuSample& sample = test::latestOf<ImuSample>(*test::pluginsOf<HectorImu>(robot).at(0));
  // On the turning axis, moving at v in its frame and turning at w: it feels w x v and gravity.
  EXPECT_LT((sample.angular_velocity - Eigen::Vector3d(0, 0, 0.5)).norm(), 1e-3);
  EXPECT_LT((sample.linear_acceleration - Eigen::Vector3d(-0.5 * 0.2, 0.5 * 0.3, 9.81)).norm(), 0.01);
  const Eigen::Quaterniond truth(robot.body().linkPose("imu_link").linear());
  EXPECT_LT(sample.orientation.angularDistance(truth), 1e-9);
}

}  // namespace
}  // namespace bullet_sim
