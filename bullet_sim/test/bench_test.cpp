// The bench tool as a user runs it: its JSON parses and holds numbers, its options reach the robot, and bad
// input gives the usage and exit status 2. A smoke test: timings are printed, never asserted.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "test_support.h"

namespace bullet_sim {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

/// The bench scenario's robot.
std::string robot() { return "--robot '" + test::packageFile("bullet_sim", "bench/bench_robot.urdf") + "'"; }

/// The bench scenario's robot and world.
std::string scenario() {
  return robot() + " --world '" + test::packageFile("bullet_sim", "bench/bench_home.world") + "'";
}

/// The numbers under `keys` of the JSON object `json`, read by Python's strict json module; a key that is
/// missing or holds anything but a number fails the test.
std::map<std::string, double> numbersIn(const std::string& json, const std::vector<std::string>& keys) {
  char path[] = "/tmp/bullet_sim_bench_test_XXXXXX";
  const int fd = mkstemp(path);
  close(fd);
  std::ofstream(path) << json;
  std::string command =
      "python3 -c 'import json, sys\n"
      "values = json.load(open(sys.argv[1]))\n"
      "for key in sys.argv[2:]:\n"
      "    value = values.get(key)\n"
      "    if isinstance(value, bool) or not isinstance(value, (int, float)):\n"
      "        sys.exit(\"%s is %r, not a number\" % (key, value))\n"
      "    print(key, repr(float(value)))' ";
  command += path;
  for (const auto& key : keys) command += " " + key;
  const test::CommandResult result = test::run(command);
  std::remove(path);
  EXPECT_EQ(result.status, 0) << result.errors << "\nin\n" << json;
  std::map<std::string, double> numbers;
  std::istringstream lines(result.output);
  std::string key;
  for (double value; lines >> key >> value;) numbers[key] = value;
  return numbers;
}

std::string bench(const std::string& args) { return std::string(BENCH) + " " + args; }

TEST(Bench, PrintsOneJsonObjectOfNumbersAndFollowsTheCommand) {
  const test::CommandResult result = test::run(bench(scenario() + " --cmd 0.5,0 --duration 2 --repeat 1"));
  ASSERT_EQ(result.status, 0) << result.errors;
  EXPECT_EQ(result.errors, "") << "the bench robot and world load without a warning";
  const auto numbers =
      numbersIn(result.output, {"rtf_physics", "rtf_lidar", "rays_per_s", "render_ms", "png_ms", "startup_s",
                                "peak_rss_mb", "pose_error_m", "pose_error_steady_m", "lidar_rays_per_scan",
                                "lidar_rate_hz", "duration_s", "repeat"});
  for (const auto& [key, value] : numbers) EXPECT_GT(value, 0) << key;
  EXPECT_EQ(numbers.at("lidar_rays_per_scan"), 360);
  EXPECT_EQ(numbers.at("lidar_rate_hz"), 10);
  // simulation_test holds the physics to its accuracy; these catch a bench that measures the wrong thing (a
  // wrong frame or sign is off by about the 1 m driven). From rest, the wheels slip for a few centimetres.
  EXPECT_LT(numbers.at("pose_error_m"), 0.1);
  EXPECT_LT(numbers.at("pose_error_steady_m"), 0.01);
}

TEST(Bench, AppliesTheWheelModelAndLidarOptionsToTheRobot) {
  const test::CommandResult result = test::run(
      bench(scenario() + " --wheel-model raycast --lidar 1800x16 --lidar-rate 5 --duration 0.2 --repeat 1"));
  ASSERT_EQ(result.status, 0) << result.errors;
  const auto numbers = numbersIn(result.output, {"lidar_rays_per_scan", "lidar_rate_hz", "rays_per_s"});
  EXPECT_EQ(numbers.at("lidar_rays_per_scan"), 1800 * 16);
  EXPECT_EQ(numbers.at("lidar_rate_hz"), 5);
  EXPECT_THAT(result.output, HasSubstr("\"wheel_model_requested\": \"raycast\""));
  EXPECT_THAT(result.output, HasSubstr("\"pose_error_steady_m\": null"));
}

TEST(Bench, ACameraRendersAtItsRateAndAnUnwantedOneRendersNothing) {
  const test::CommandResult result =
      test::run(bench(scenario() + " --camera 64x48@20 --depth --duration 0.5 --repeat 1"));
  ASSERT_EQ(result.status, 0) << result.errors;
  const auto numbers = numbersIn(result.output, {"rtf_camera", "rtf_camera_idle", "camera_frames_per_run",
                                                 "camera_ms_per_frame", "camera_idle_cost_pct"});
  // 0.5 s of settling and 0.5 s of driving at 20 Hz.
  EXPECT_EQ(numbers.at("camera_frames_per_run"), 20);
  EXPECT_THAT(result.output, HasSubstr("\"camera_idle_frames_per_run\": 0"));
}

TEST(Bench, AWatchedRunHasItsPageTakeInFrames) {
  const test::CommandResult result = test::run(bench(scenario() + " --web-viewer --duration 0.5 --repeat 1"));
  ASSERT_EQ(result.status, 0) << result.errors;
  const auto numbers = numbersIn(result.output, {"rtf_web_viewer", "web_viewer_cost_pct",
                                                 "web_viewer_cpu_cost_pct", "web_viewer_frames_per_run"});
  EXPECT_GT(numbers.at("rtf_web_viewer"), 0);
  EXPECT_GE(numbers.at("web_viewer_frames_per_run"), 1);
}

/// `arguments` ending in a folder under a plain file: bench ends with status 1 and names it after `option`.
void expectNamesAFolderItCannotMake(const std::string& scratch, const std::string& arguments,
                                    const std::string& option) {
  const std::string file = scratch + "/a_file";
  std::ofstream(file) << "not a folder";
  const test::CommandResult result = test::run(bench(arguments + file + "/pictures"));
  EXPECT_EQ(result.status, 1);
  EXPECT_THAT(result.errors, HasSubstr(option + ": cannot make [" + file + "/pictures]"));
}

// --snapshot makes its folder, as scenario --out does, and names one it cannot make.
TEST(Bench, AFleetSnapshotMakesItsFolder) {
  char scratch[] = "/tmp/bullet_sim_bench_snapshot_XXXXXX";
  ASSERT_NE(mkdtemp(scratch), nullptr);
  const std::string folder = std::string(scratch) + "/pictures/fleet";
  const std::string fleet = robot() + " --robots 1 --duration 0.1 --repeat 1 --snapshot ";
  const test::CommandResult result = test::run(bench(fleet + folder));
  EXPECT_EQ(result.status, 0) << result.errors;
  for (const char* moment : {"settled", "end"}) {
    for (const char* view : {"top", "corner"}) {
      const std::string picture = folder + "/fleet_1_" + moment + "_" + view + ".png";
      EXPECT_TRUE(std::ifstream(picture).good()) << picture;
    }
  }
  expectNamesAFolderItCannotMake(scratch, fleet, "--snapshot");
  test::run("rm -rf " + std::string(scratch));
}

// --strike-render makes its folder too, and names one it cannot make before any cell runs.
TEST(Bench, StrikePicturesMakeTheirFolder) {
  char scratch[] = "/tmp/bullet_sim_bench_strikes_XXXXXX";
  ASSERT_NE(mkdtemp(scratch), nullptr);
  const std::string folder = std::string(scratch) + "/pictures/strikes";
  const std::string cell =
      "--strikes --strike-filter caster_two_wheeler --strike-filter raycast --strike-filter 10ms "
      "--strike-filter 2m/s --strike-filter panel --strike-render ";
  const test::CommandResult result = test::run(bench(cell + folder));
  EXPECT_EQ(result.status, 0) << result.errors;
  const std::string stem = folder + "/caster_two_wheeler_raycast_10ms_2m_s_0deg_panel";
  for (const char* written : {"_end_side.png", "_end_chase.png", "_trail.csv"})
    EXPECT_TRUE(std::ifstream(stem + written).good()) << stem + written;
  expectNamesAFolderItCannotMake(scratch, cell, "--strike-render");
  test::run("rm -rf " + std::string(scratch));
}

// --strike-steps runs the matrix's cells at the world step sizes given instead of 1 and 10 ms.
TEST(Bench, StrikeStepsRunTheCellsAtTheStepsGiven) {
  const test::CommandResult result =
      test::run(bench("--strikes --strike-steps 0.004,0.0005 --strike-filter caster_two_wheeler "
                      "--strike-filter raycast --strike-filter 2m/s --strike-filter panel"));
  EXPECT_EQ(result.status, 0) << result.errors;
  EXPECT_THAT(result.errors, HasSubstr("caster_two_wheeler raycast 4ms 2m/s 0deg panel"));
  EXPECT_THAT(result.errors, HasSubstr("caster_two_wheeler raycast 0.5ms 2m/s 0deg panel"));
  EXPECT_THAT(result.errors, Not(HasSubstr(" 1ms ")));
  EXPECT_THAT(result.errors, Not(HasSubstr(" 10ms ")));
  const auto numbers = numbersIn(result.output, {"cells", "passed", "rtf_4ms", "rtf_0.5ms"});
  EXPECT_EQ(numbers.at("cells"), 2);
  EXPECT_EQ(numbers.at("passed"), 2);
}

TEST(Bench, BadArgumentsPrintTheUsageAndExitWith2) {
  for (const std::string args :
       {"", "--world home.world", "--robot x.urdf --bogus 1", "--robot x.urdf --cmd 0.5",
        "--robot x.urdf --lidar 1800x", "--robot x.urdf --repeat 0", "--robot x.urdf --wheel-model tank",
        "--robot x.urdf --step -1", "--robot x.urdf --render 640", "--robot x.urdf --depth",
        "--robot x.urdf --camera 640x480", "--robot x.urdf --camera 640x480@0",
        "--strikes --strike-steps 0", "--strikes --strike-steps 0.001,", "--strikes --strike-steps 0.2"}) {
    SCOPED_TRACE(args);
    const test::CommandResult result = test::run(bench(args));
    EXPECT_EQ(result.status, 2);
    EXPECT_THAT(result.errors, HasSubstr("usage: bench"));
  }
}

TEST(Bench, ALoadErrorSaysWhatAndExitsWith1) {
  test::CommandResult result = test::run(bench("--robot /nonexistent/robot.urdf"));
  EXPECT_EQ(result.status, 1);
  EXPECT_THAT(result.errors, HasSubstr("cannot read URDF [/nonexistent/robot.urdf]"));

  result = test::run(bench("--robot '" + test::packageFile("bullet_sim", "bench/bench_robot.urdf") +
                           "' --world no_such.world"));
  EXPECT_EQ(result.status, 1);
  EXPECT_THAT(result.errors, HasSubstr("no_such.world"));
}

}  // namespace
}  // namespace bullet_sim
