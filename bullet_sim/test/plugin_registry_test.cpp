// The plugin registry is open: a plugin defined here, in a test, is registered on a copy of the built-in
// registry and then parsed, checked, built, stepped and heard through its ports with no edit elsewhere.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "bullet_sim/plugins/registry.h"
#include "bullet_sim/simulation/simulation.h"
#include "test_support.h"

namespace bullet_sim {
namespace {

/// libtest_altimeter.so: publishes a link's pose as odometry at updateRate [Hz]; a Twist's linear.z sets an
/// offset [m] added to the height it reports, and its calibrate service takes the offset away.
struct AltimeterConfig : PluginConfig {
  std::string topic;
};

const TagTable kAltimeterTags = {
    {"linkName", TagType::kText, "", "", "", "the link whose height it reports"},
    {"topicName", TagType::kTopic, "altitude", "", "", "where it publishes"},
};

void parseAltimeter(const DeclarationSource& source, AltimeterConfig& config) {
  config.link = source.tags.text("linkName");
  if (!source.model.link(config.link)) {
    source.diagnostics.error(source.tags.where() + " <linkName> [" + config.link + "] is not a link" +
                             didYouMean(config.link, source.model.linkNames()));
  }
  config.topic = source.tags.text("topicName");
}

class Altimeter : public Plugin {
 public:
  Altimeter(const PluginDeclaration& declaration, const AltimeterConfig& config, const PluginSetup& setup)
      : Plugin(declaration, setup), config_(config) {
    addOutput(config_.topic, heights_);
    addInput<Twist>("set_offset", [this](const Twist& twist, double) -> std::string {
      if (!std::isfinite(twist.linear.z())) return "an offset that is not finite";
      offset_ = twist.linear.z();
      return "";
    });
    addService<EmptyRequest>("calibrate", [this](const EmptyRequest&) -> std::string {
      offset_ = 0;
      return "";
    });
  }

  void sense(const StepTime& time, const RobotBody& body, const RayCaster&) override {
    if (!timer().due(time)) return;
    Odometry& sample = heights_.next();
    sample.stamp = time.sim_time;
    sample.pose = body.linkPose(config_.link);
    sample.pose.translation().z() += offset_;
    heights_.publish();
  }

 private:
  AltimeterConfig config_;
  Stream<Odometry> heights_;
  double offset_ = 0;
};

PluginRegistry withAltimeter() {
  PluginRegistry registry = PluginRegistry::builtin();
  PluginType type = pluginType<Altimeter>("libtest_altimeter.so", parseAltimeter, kAltimeterTags);
  type.rate = {RateRule::From::kTags, {"updateRate"}, 0};
  registry.add(std::move(type));
  return registry;
}

/// The minimal robot with an altimeter block whose tags are `tags`.
std::string robotWithAltimeter(const test::Tags& tags) {
  return test::withPlugin(test::readFile(test::fixture("robots/minimal.urdf")), "altimeter",
                          "libtest_altimeter.so", tags);
}

const PluginRegistry& registry() {
  static const PluginRegistry registry = withAltimeter();
  return registry;
}

TEST(PluginRegistry, ARegisteredPluginIsParsedIntoItsTypedConfig) {
  std::vector<std::string> warnings;
  const ModelSpec model =
      parseModel(robotWithAltimeter({{"linkName", "base_link"}, {"updateRate", "50"}}), "altimeter robot",
                 PackageResolver::fromEnvironment(), registry(), &warnings);
  EXPECT_EQ(warnings, std::vector<std::string>{});
  ASSERT_EQ(model.plugins.size(), 1u);
  const auto* config = model.plugins.front().configAs<AltimeterConfig>();
  ASSERT_NE(config, nullptr);
  EXPECT_EQ(config->link, "base_link");
  EXPECT_DOUBLE_EQ(config->update_rate, 50);
}

TEST(PluginRegistry, WithoutTheRegistrationThePluginIsOneWarning) {
  std::vector<std::string> warnings;
  const ModelSpec model =
      parseModel(robotWithAltimeter({{"linkName", "base_link"}}), "altimeter robot",
                 PackageResolver::fromEnvironment(), PluginRegistry::builtin(), &warnings);
  EXPECT_TRUE(model.plugins.empty());
  EXPECT_EQ(warnings, std::vector<std::string>{"plugin [altimeter] filename [libtest_altimeter.so] is not a "
                                               "plugin bullet_sim simulates: ignored"});
}

TEST(PluginRegistry, ItsTagProblemsAreReportedWithTheFilesOthers) {
  try {
    parseModel(robotWithAltimeter({{"linkName", "base_lnik"}, {"updateRate", "fast"}, {"colour", "red"}}),
               "altimeter robot", PackageResolver::fromEnvironment(), registry());
    FAIL() << "a plugin naming a missing link was accepted";
  } catch (const SpecError& error) {
    EXPECT_EQ(error.problems(),
              (std::vector<std::string>{  // the registry's head first, then the plugin's own tags
                  "plugin [altimeter] <updateRate> must be a number, not [fast]",
                  "plugin [altimeter] <linkName> [base_lnik] is not a link (did you mean [base_link]?)"}));
  }
}

TEST(PluginRegistry, ARateTagIsARateWhoseNegativeIsZeroAsInGazebo) {
  std::vector<std::string> warnings;
  const ModelSpec model =
      parseModel(robotWithAltimeter({{"linkName", "base_link"}, {"updateRate", "-1"}}), "altimeter robot",
                 PackageResolver::fromEnvironment(), registry(), &warnings);
  EXPECT_EQ(warnings, std::vector<std::string>{"plugin [altimeter] <updateRate> -1 is below 0: read as 0, "
                                               "every update, as Gazebo's plugin reads it"});
  EXPECT_EQ(model.plugins.front().config->update_rate, 0.0);
  // A plugin documenting its rate tag as another type would show a rule the head does not follow.
  PluginType type = pluginType<Altimeter>("libtest_altimeter.so", parseAltimeter, kAltimeterTags);
  type.tags.add({"updateRate", TagType::kPositive, "0", "Hz", "", ""});
  type.rate = {RateRule::From::kTags, {"updateRate"}, 0};
  PluginRegistry other;
  EXPECT_THROW(other.add(std::move(type)), std::logic_error);
}

TEST(PluginRegistry, TheSimulationBuildsItAndItsOutputFollowsFreeFall) {
  SimulationOptions options;
  options.plugins = &registry();
  Simulation simulation(test::shippedWorld("empty.world"), options);
  ModelSpec model = parseModel(robotWithAltimeter({{"linkName", "base_link"}, {"updateRate", "100"}}),
                               "altimeter robot", PackageResolver::fromEnvironment(), registry());
  SpawnPose pose;
  pose.z = 10.0;  // [m] high enough to fall freely for the whole test
  Robot& robot = simulation.spawn("dropped", std::move(model), pose);
  ASSERT_EQ(test::pluginsOf<Altimeter>(robot).size(), 1u);
  const Plugin& altimeter = *robot.plugins().front();
  ASSERT_EQ(altimeter.ports().outputs.size(), 1u);
  EXPECT_EQ(altimeter.ports().outputs.front().topic, "altitude");
  const auto* heights = std::get<const Stream<Odometry>*>(altimeter.ports().outputs.front().stream);

  for (int i = 0; i < 500; ++i) simulation.step();  // 0.5 s at 1 ms
  EXPECT_EQ(heights->count(), 50u);                 // 100 Hz
  const double t = heights->latest().stamp;
  EXPECT_DOUBLE_EQ(t, 0.5);
  EXPECT_NEAR(heights->latest().pose.translation().z(), 10.0 - 9.81 * t * t / 2, 0.01);

  const auto& set_offset = std::get<InputHandler<Twist>>(altimeter.ports().inputs.front().sink);
  Twist up;
  up.linear.z() = 100;
  EXPECT_EQ(set_offset(up, simulation.time()), "");
  up.linear.z() = NAN;
  // The ports drop it before the plugin sees it (input_checks.h).
  EXPECT_EQ(set_offset(up, simulation.time()), "a message whose linear.z [nan] is not finite");
  for (int i = 0; i < 10; ++i) simulation.step();
  const double later = heights->latest().stamp;
  EXPECT_NEAR(heights->latest().pose.translation().z(), 110.0 - 9.81 * later * later / 2, 0.01);

  ASSERT_EQ(altimeter.ports().services.size(), 1u);
  EXPECT_EQ(altimeter.ports().services.front().name, "calibrate");
  const auto& calibrate = std::get<ServiceHandler<EmptyRequest>>(altimeter.ports().services.front().handler);
  EmptyRequest::Reply reply;
  EXPECT_EQ(calibrate(EmptyRequest{}, reply), "");
  for (int i = 0; i < 10; ++i) simulation.step();
  const double calibrated = heights->latest().stamp;
  EXPECT_NEAR(heights->latest().pose.translation().z(), 10.0 - 9.81 * calibrated * calibrated / 2, 0.01);
}

}  // namespace
}  // namespace bullet_sim
