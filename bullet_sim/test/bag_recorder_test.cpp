// The bag recorder in-process (src/ros/bag_recorder.h): what a bag of the wheelchair's run holds, checked
// against the simulation it recorded, and how the recorder meets a path it cannot write, a full disk and a
// reset.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <rosbag/view.h>
#include <sys/resource.h>
#include <tf2_eigen/tf2_eigen.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "src/ros/bag_recorder.h"
#include "test/test_support.h"

namespace bullet_sim {
namespace {

namespace fs = std::filesystem;

constexpr double kStep = 0.001;  // [s]

/// A fresh folder for a test's bags.
/// This process's folder under the system's temporary folder, removed when the tests end.
const fs::path& scratchRoot() {
  struct Root {
    fs::path path = fs::temp_directory_path() / ("bag_recorder_test_" + std::to_string(getpid()));
    ~Root() {
      std::error_code ignored;
      fs::remove_all(path, ignored);
    }
  };
  static const Root root;
  return root.path;
}

/// A fresh folder for a test's bags.
fs::path scratch(const std::string& name) {
  const fs::path dir = scratchRoot() / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

/// What the simulation said at every step of a recorded run: each link's pose and the root's velocities, and
/// how many samples each of the chair's outputs published.
struct Truth {
  std::vector<std::map<std::string, Eigen::Isometry3d>> links;  ///< per step, from step 1
  std::vector<Eigen::Vector3d> linear, angular;                 ///< of the root link, world axes
  std::map<std::string, uint64_t> samples;                      ///< by topic ("" for the tf output)
};

/// The wheelchair in the test room, driven on an arc (cmd_vel re-sent every 0.1 s, and recorded), recorded
/// for `seconds` of sim time into `settings.path`.
Truth recordChair(const BagSettings& settings, double seconds, std::vector<std::string>* errors = nullptr,
                  uint64_t seed = 3) {
  SimulationOptions options;
  options.seed = seed;
  Simulation simulation(test::shippedWorld("test_room.world"), options);
  Robot& chair = simulation.spawn("chair", test::wheelchair(), {.x = 0.5, .y = -0.3, .yaw = 0.3});
  std::vector<std::string> reported;
  BagRecorder recorder(settings, [&](const std::string& error) { reported.push_back(error); });
  recorder.addRobot(chair, "", "");
  Truth truth;
  std::map<std::string, uint64_t> first;
  const auto count = [&](std::map<std::string, uint64_t>& into) {
    for (const auto& output : chair.outputs<LaserScan>()) into[output.topic] = output.stream->count();
    for (const auto& output : chair.outputs<Odometry>()) into[output.topic] = output.stream->count();
    for (const auto& output : chair.outputs<JointStateSample>()) into[output.topic] = output.stream->count();
    for (const auto& output : chair.outputs<TransformSample>()) into[output.topic] = output.stream->count();
  };
  count(first);
  const long steps = std::lround(seconds / kStep);
  for (long i = 0; i < steps; ++i) {
    if (i % 100 == 0) {
      Twist command;
      command.linear.x() = 0.4;
      command.angular.z() = 0.5;
      for (const auto& input : chair.inputs<Twist>()) {
        (*input.handler)(command, simulation.time());
        recorder.command(chair, input, command, simulation.time());
      }
    }
    simulation.step();
    recorder.afterStep(simulation);
    auto& links = truth.links.emplace_back();
    for (const auto& link : chair.body().spec().links) links[link.name] = chair.body().linkPose(link.name);
    const std::string& root = chair.body().spec().root;
    truth.linear.push_back(chair.body().linkLinearVelocity(root));
    truth.angular.push_back(chair.body().linkAngularVelocity(root));
  }
  count(truth.samples);
  for (auto& [topic, samples] : truth.samples) samples -= first[topic];
  recorder.close();
  if (errors) *errors = reported;
  else EXPECT_THAT(reported, ::testing::IsEmpty());
  return truth;
}

/// Every message of `topic` in a bag, in bag order, with its bag time.
template <class Message>
std::vector<std::pair<double, Message>> messages(const std::string& path, const std::string& topic) {
  rosbag::Bag bag(path, rosbag::bagmode::Read);
  std::vector<std::pair<double, Message>> found;
  for (const rosbag::MessageInstance& m : rosbag::View(bag, rosbag::TopicQuery(topic))) {
    const auto message = m.instantiate<Message>();
    EXPECT_NE(message, nullptr) << topic << " holds " << m.getDataType();
    if (message) found.emplace_back(m.getTime().toSec(), *message);
  }
  return found;
}

std::set<std::string> topicsOf(const std::string& path) {
  rosbag::Bag bag(path, rosbag::bagmode::Read);
  std::set<std::string> topics;
  for (const auto* connection : rosbag::View(bag).getConnections()) topics.insert(connection->topic);
  return topics;
}

/// The step a sim time ends.
size_t stepAt(double time) { return static_cast<size_t>(std::lround(time / kStep)); }

void expectSameTransform(const Eigen::Isometry3d& actual, const Eigen::Isometry3d& expected, double tolerance,
                         const std::string& what) {
  EXPECT_LT((actual.translation() - expected.translation()).norm(), tolerance) << what;
  EXPECT_LT(Eigen::AngleAxisd(actual.linear().transpose() * expected.linear()).angle(), tolerance) << what;
}

std::string bytesOf(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

class ChairBag : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    settings_ = new BagSettings;
    settings_->path = (scratch("chair") / "chair.bag").string();
    truth_ = new Truth(recordChair(*settings_, 2.0));
  }
  static void TearDownTestSuite() {
    delete truth_;
    delete settings_;
  }
  static BagSettings* settings_;
  static Truth* truth_;
};
BagSettings* ChairBag::settings_ = nullptr;
Truth* ChairBag::truth_ = nullptr;

TEST_F(ChairBag, HoldsTheRobotsTopicsButNotTheClock) {
  EXPECT_THAT(topicsOf(settings_->path),
              ::testing::UnorderedElementsAre("/ground_truth", "/tf", "/tf_static", "/odom", "/joint_states",
                                              "/scan", "/cmd_vel"));
}

TEST_F(ChairBag, GroundTruthIsTheRootLinkInTheWorldAt50Hz) {
  const auto truth = messages<nav_msgs::Odometry>(settings_->path, "/ground_truth");
  ASSERT_EQ(truth.size(), 100u);  // 2 s at 50 Hz
  for (size_t i = 0; i < truth.size(); ++i) {
    const auto& [time, message] = truth[i];
    EXPECT_NEAR(time, 0.02 * (i + 1), 1e-9);
    EXPECT_EQ(message.header.stamp.toSec(), time);
    EXPECT_EQ(message.header.frame_id, "world");
    EXPECT_EQ(message.child_frame_id, "base_footprint");
    const size_t step = stepAt(time) - 1;
    Eigen::Isometry3d pose;
    tf2::fromMsg(message.pose.pose, pose);
    expectSameTransform(pose, truth_->links[step].at("base_footprint"), 1e-9,
                        "ground truth at " + std::to_string(time));
    Eigen::Vector3d linear, angular;
    tf2::fromMsg(message.twist.twist.linear, linear);
    tf2::fromMsg(message.twist.twist.angular, angular);
    EXPECT_LT((pose.linear() * linear - truth_->linear[step]).norm(), 1e-9) << "in the child frame";
    EXPECT_LT((pose.linear() * angular - truth_->angular[step]).norm(), 1e-9);
  }
  EXPECT_GT(truth.back().second.pose.pose.position.x, 0.5 + 0.3) << "the chair drove";
}

TEST_F(ChairBag, FixedLinksAreOnALatchedTfStaticAsRobotStatePublisherPutsThem) {
  rosbag::Bag bag(settings_->path, rosbag::bagmode::Read);
  rosbag::View view(bag, rosbag::TopicQuery("/tf_static"));
  ASSERT_EQ(view.getConnections().size(), 1u);
  const auto& header = *view.getConnections()[0]->header;
  EXPECT_EQ(header.at("latching"), "1");
  EXPECT_EQ(header.count("callerid"), 0u) << "no caller id: nothing in the bag depends on the host";
  const auto statics = messages<tf2_msgs::TFMessage>(settings_->path, "/tf_static");
  ASSERT_EQ(statics.size(), 1u);
  const ModelSpec model = test::wheelchair();
  std::set<std::string> children;
  for (const auto& transform : statics[0].second.transforms) {
    children.insert(transform.child_frame_id);
    const JointSpec* joint = model.parentJoint(transform.child_frame_id);
    ASSERT_NE(joint, nullptr) << transform.child_frame_id;
    EXPECT_FALSE(joint->moves());
    EXPECT_EQ(transform.header.frame_id, joint->parent);
    const auto& links = truth_->links.front();  // a rigid joint: the simulated links agree
    expectSameTransform(tf2::transformToEigen(transform),
                        links.at(joint->parent).inverse() * links.at(joint->child), 1e-6,
                        transform.child_frame_id);
  }
  size_t fixed = 0;
  for (const auto& joint : model.joints) fixed += !joint.moves();
  EXPECT_EQ(children.size(), fixed);
  EXPECT_TRUE(children.count("laser_Link"));
}

TEST_F(ChairBag, MovingLinksComeWithEveryJointStatesAtItsStamp) {
  const auto states = messages<sensor_msgs::JointState>(settings_->path, "/joint_states");
  EXPECT_EQ(states.size(), truth_->samples.at("joint_states"));
  EXPECT_EQ(states.size(), 100u);  // 50 Hz
  // robot_state_publisher's, by stamp
  std::map<double, std::vector<geometry_msgs::TransformStamped>> links_at;
  size_t odometry = 0;
  for (const auto& [time, message] : messages<tf2_msgs::TFMessage>(settings_->path, "/tf")) {
    for (const auto& transform : message.transforms) {
      EXPECT_EQ(transform.header.stamp.toSec(), time);
      if (transform.header.frame_id == "odom") ++odometry;
      else links_at[time].push_back(transform);
    }
  }
  EXPECT_EQ(odometry, truth_->samples.at("")) << "odom -> base_footprint, each once";
  const ModelSpec model = test::wheelchair();
  for (const auto& [time, message] : states) {
    ASSERT_EQ(message.header.stamp.toSec(), time);
    const auto& links = links_at[time];
    ASSERT_EQ(links.size(), message.name.size()) << "at " << time;
    for (size_t i = 0; i < links.size(); ++i) {
      const JointSpec* joint = model.joint(message.name[i]);
      ASSERT_NE(joint, nullptr);
      EXPECT_EQ(links[i].header.frame_id, joint->parent);
      EXPECT_EQ(links[i].child_frame_id, joint->child);
      const auto& pose = truth_->links[stepAt(time) - 1];
      expectSameTransform(tf2::transformToEigen(links[i]),
                          pose.at(joint->parent).inverse() * pose.at(joint->child), 1e-6,
                          message.name[i] + " at " + std::to_string(time));
    }
  }
}

TEST_F(ChairBag, EverySensorSampleOnceAtItsOwnRateInStepOrder) {
  const auto scans = messages<sensor_msgs::LaserScan>(settings_->path, "/scan");
  EXPECT_EQ(scans.size(), truth_->samples.at("scan"));
  EXPECT_EQ(scans.size(), 11u);  // 5.5 Hz for 2 s
  const auto odometry = messages<nav_msgs::Odometry>(settings_->path, "/odom");
  EXPECT_EQ(odometry.size(), truth_->samples.at("odom"));
  EXPECT_EQ(odometry.size(), 200u);  // 100 Hz
  for (const auto& [time, scan] : scans) {
    EXPECT_EQ(scan.header.stamp.toSec(), time) << "recorded at the step that produced it";
    EXPECT_EQ(scan.header.frame_id, "laser_Link");
    EXPECT_EQ(scan.ranges.size(), 360u);
  }
  rosbag::Bag bag(settings_->path, rosbag::bagmode::Read);
  double last = 0;
  for (const rosbag::MessageInstance& m : rosbag::View(bag)) {
    EXPECT_GE(m.getTime().toSec(), last) << m.getTopic();
    last = m.getTime().toSec();
  }
}

TEST_F(ChairBag, CommandsAtTheTimesTheyWereGiven) {
  const auto commands = messages<geometry_msgs::Twist>(settings_->path, "/cmd_vel");
  ASSERT_EQ(commands.size(), 20u);
  EXPECT_NEAR(commands[0].first, 1e-9, 1e-12) << "the first, at t = 0, at the bag's earliest time";
  EXPECT_NEAR(commands[5].first, 0.5, 1e-9);
  EXPECT_EQ(commands[5].second.linear.x, 0.4);
  EXPECT_EQ(commands[5].second.angular.z, 0.5);
}

TEST(BagRecorder, TheSameRunGivesTheSameBytesWhateverTheCompression) {
  const fs::path dir = scratch("same_bytes");
  for (const std::string compression : {"none", "lz4", "bz2"}) {
    BagSettings settings;
    settings.compression = compression;
    settings.chunk_size = 16 * 1024;  // several chunks
    settings.path = (dir / (compression + "_a.bag")).string();
    recordChair(settings, 0.5);
    settings.path = (dir / (compression + "_b.bag")).string();
    recordChair(settings, 0.5);
    const std::string first = bytesOf(dir / (compression + "_a.bag"));
    EXPECT_GT(first.size(), 20000u);
    EXPECT_TRUE(first == bytesOf(dir / (compression + "_b.bag"))) << compression;
    settings.path = (dir / (compression + "_c.bag")).string();
    recordChair(settings, 0.5, nullptr, 4);
    EXPECT_FALSE(first == bytesOf(dir / (compression + "_c.bag"))) << "another seed, other scans";
  }
}

TEST(BagRecorder, TopicPatternsChooseWhatIsRecorded) {
  BagSettings settings;
  settings.path = (scratch("patterns") / "some").string();  // .bag is added
  settings.topics = {"/scan", "/tf.*"};
  recordChair(settings, 0.5);
  EXPECT_THAT(topicsOf(settings.path + ".bag"),
              ::testing::UnorderedElementsAre("/scan", "/tf", "/tf_static"));
}

TEST(BagRecorder, TheDefaultLeavesOutImagesAndPointClouds) {
  const TopicFilter all({});
  EXPECT_TRUE(all.records("/scan", "sensor_msgs/LaserScan"));
  EXPECT_TRUE(all.records("/camera/camera_info", "sensor_msgs/CameraInfo"));
  EXPECT_FALSE(all.records("/camera/image_raw", "sensor_msgs/Image"));
  EXPECT_FALSE(all.records("/velodyne_points", "sensor_msgs/PointCloud2"));
  EXPECT_FALSE(all.records("/block_laser", "sensor_msgs/PointCloud"));
  EXPECT_TRUE(TopicFilter({"/camera/.*"}).records("/camera/image_raw", "sensor_msgs/Image"));
  EXPECT_FALSE(TopicFilter({"/camera"}).records("/camera/image_raw", "sensor_msgs/Image"))
      << "the whole name";
}

TEST(BagRecorder, BadSettingsAreNamed) {
  const auto refused = [](BagSettings settings) {
    settings.path = (scratch("refused") / "x.bag").string();
    try {
      BagRecorder recorder(settings, [](const std::string&) {});
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_THAT(refused({.topics = {"/scan("}}), ::testing::HasSubstr("[/scan(]"));
  EXPECT_THAT(refused({.compression = "zip"}),
              ::testing::HasSubstr("compression [zip]: use none, lz4 or bz2"));
  EXPECT_THAT(refused({.chunk_size = 0}), ::testing::HasSubstr("chunk size 0"));
  EXPECT_THAT(refused({.ground_truth_rate = -1}), ::testing::HasSubstr("ground truth rate [-1"));
}

TEST(BagRecorder, TheBagIsActiveUntilClosedThenRenamed) {
  const fs::path dir = scratch("active");
  Simulation simulation(test::shippedWorld("empty.world"));
  Robot& chair = simulation.spawn("chair", test::wheelchair(), {});
  BagRecorder recorder({.path = (dir / "run.bag").string()},
                       [](const std::string& e) { ADD_FAILURE() << e; });
  recorder.addRobot(chair, "", "");
  for (int i = 0; i < 100; ++i) {
    simulation.step();
    recorder.afterStep(simulation);
  }
  EXPECT_TRUE(fs::exists(dir / "run.bag.active"));
  EXPECT_FALSE(fs::exists(dir / "run.bag"));
  EXPECT_THAT(recorder.close(), ::testing::ElementsAre((dir / "run.bag").string()));
  EXPECT_FALSE(fs::exists(dir / "run.bag.active"));
  EXPECT_EQ(messages<nav_msgs::Odometry>((dir / "run.bag").string(), "/odom").size(), 10u);
}

TEST(BagRecorder, AResetClosesTheBagAndGoesOnInTheNext) {
  const fs::path dir = scratch("reset");
  Simulation simulation(test::shippedWorld("empty.world"));
  Robot& chair = simulation.spawn("chair", test::wheelchair(), {});
  BagRecorder recorder({.path = (dir / "run.bag").string()},
                       [](const std::string& e) { ADD_FAILURE() << e; });
  recorder.addRobot(chair, "", "");
  const auto run = [&](int steps) {
    for (int i = 0; i < steps; ++i) {
      simulation.step();
      recorder.afterStep(simulation);
    }
  };
  run(300);
  simulation.resetSimulation();
  recorder.restart();
  EXPECT_TRUE(fs::exists(dir / "run.bag")) << "closed at the reset";
  EXPECT_EQ(recorder.path(), (dir / "run_1.bag").string());
  run(100);
  EXPECT_THAT(recorder.close(),
              ::testing::ElementsAre((dir / "run.bag").string(), (dir / "run_1.bag").string()));
  const auto before = messages<nav_msgs::Odometry>((dir / "run.bag").string(), "/ground_truth");
  const auto after = messages<nav_msgs::Odometry>((dir / "run_1.bag").string(), "/ground_truth");
  ASSERT_EQ(before.size(), 15u);
  ASSERT_EQ(after.size(), 5u);
  EXPECT_NEAR(after.front().first, 0.02, 1e-9) << "sim time restarted";
  EXPECT_EQ(messages<tf2_msgs::TFMessage>((dir / "run_1.bag").string(), "/tf_static").size(), 1u)
      << "the fixed links again, for a player of this bag alone";
}

TEST(BagRecorder, AnUnwritablePathIsOneErrorNamingItAndTheRunGoesOn) {
  std::vector<std::string> errors;
  Simulation simulation(test::shippedWorld("empty.world"));
  Robot& chair = simulation.spawn("chair", test::wheelchair(), {});
  BagRecorder recorder({.path = "/etc/passwd/run.bag"}, [&](const std::string& e) { errors.push_back(e); });
  recorder.addRobot(chair, "", "");
  for (int i = 0; i < 200; ++i) {
    simulation.step();
    recorder.afterStep(simulation);
  }
  recorder.restart();  // recording stays stopped
  EXPECT_THAT(recorder.close(), ::testing::IsEmpty());
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_THAT(errors[0], ::testing::HasSubstr("[/etc/passwd/run.bag.active]"));
  EXPECT_THAT(errors[0], ::testing::HasSubstr("Not a directory"));
  EXPECT_NEAR(simulation.time(), 0.2, 1e-9);
}

TEST(BagRecorder, AFullDiskIsOneErrorNamingThePathAndTheRunGoesOn) {
  // The file size limit stands in for a full disk: the bag's writes fail once it is reached, mid-run.
  const fs::path dir = scratch("full");
  rlimit saved{};
  getrlimit(RLIMIT_FSIZE, &saved);
  const auto previous = std::signal(SIGXFSZ, SIG_IGN);
  rlimit limit = saved;
  limit.rlim_cur = 200 * 1024;
  setrlimit(RLIMIT_FSIZE, &limit);
  std::vector<std::string> errors;
  std::vector<std::string> closed;
  {
    BagSettings settings{.path = (dir / "run.bag").string()};
    settings.chunk_size = 16 * 1024;
    SimulationOptions options;
    Simulation simulation(test::shippedWorld("test_room.world"), options);
    Robot& chair = simulation.spawn("chair", test::wheelchair(), {});
    BagRecorder recorder(settings, [&](const std::string& e) { errors.push_back(e); });
    recorder.addRobot(chair, "", "");
    for (int i = 0; i < 20000; ++i) {  // 20 s: well over 200 KiB of bag
      simulation.step();
      recorder.afterStep(simulation);
    }
    closed = recorder.close();
    EXPECT_NEAR(simulation.time(), 20, 1e-9);
  }
  setrlimit(RLIMIT_FSIZE, &saved);
  std::signal(SIGXFSZ, previous);
  EXPECT_THAT(closed, ::testing::IsEmpty());
  ASSERT_EQ(errors.size(), 1u) << ::testing::PrintToString(errors);
  EXPECT_THAT(errors[0], ::testing::HasSubstr("[" + (dir / "run.bag.active").string() + "]"));
  EXPECT_THAT(errors[0], ::testing::HasSubstr("File too large"));
  EXPECT_TRUE(fs::exists(dir / "run.bag.active")) << "left for rosbag reindex";
}

TEST(BagWriter, NeverDropsAMessageWhenTheWriterFallsBehind) {
  const fs::path dir = scratch("behind");
  BagWriter::Options options;
  options.max_queued_bytes = 1;  // the caller waits for every message
  {
    BagWriter writer((dir / "queue.bag").string(), options, [](const std::string& e) { ADD_FAILURE() << e; });
    for (int i = 0; i < 5000; ++i) {
      nav_msgs::Odometry message;
      message.pose.pose.position.x = i;
      writer.write("/odom", 0.001 * (i + 1), message);
    }
    EXPECT_TRUE(writer.close());
  }
  const auto written = messages<nav_msgs::Odometry>((dir / "queue.bag").string(), "/odom");
  ASSERT_EQ(written.size(), 5000u);
  for (int i = 0; i < 5000; ++i) EXPECT_EQ(written[i].second.pose.pose.position.x, i);
}

TEST(BagRecorder, SeveralRobotsEachInTheirNamespaceAndPrefix) {
  const fs::path dir = scratch("several");
  Simulation simulation(test::shippedWorld("empty.world"));
  BagRecorder recorder({.path = (dir / "run.bag").string()},
                       [](const std::string& e) { ADD_FAILURE() << e; });
  for (const std::string name : {"chair_1", "chair_2"}) {
    recorder.addRobot(simulation.spawn(name, test::wheelchair(), {.x = name == "chair_1" ? 0.0 : 3.0}), name,
                      name);
  }
  for (int i = 0; i < 300; ++i) {
    simulation.step();
    recorder.afterStep(simulation);
  }
  recorder.close();
  const std::string bag = (dir / "run.bag").string();
  EXPECT_THAT(topicsOf(bag),
              ::testing::IsSupersetOf({"/chair_1/ground_truth", "/chair_2/ground_truth", "/chair_1/scan",
                                       "/chair_2/odom", "/tf", "/tf_static"}));
  const auto truth = messages<nav_msgs::Odometry>(bag, "/chair_2/ground_truth");
  ASSERT_FALSE(truth.empty());
  EXPECT_EQ(truth[0].second.child_frame_id, "chair_2/base_footprint");
  EXPECT_NEAR(truth[0].second.pose.pose.position.x, 3.0, 0.01);
  EXPECT_EQ(messages<nav_msgs::Odometry>(bag, "/chair_1/odom")[0].second.header.frame_id, "chair_1/odom");
  const auto statics = messages<tf2_msgs::TFMessage>(bag, "/tf_static");
  ASSERT_EQ(statics.size(), 1u) << "one message holds both robots' fixed links";
  std::set<std::string> children;
  for (const auto& transform : statics[0].second.transforms) children.insert(transform.child_frame_id);
  EXPECT_TRUE(children.count("chair_1/laser_Link") && children.count("chair_2/laser_Link"));
}

}  // namespace
}  // namespace bullet_sim
