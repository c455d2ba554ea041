// Scenario files, matrices, the clearance query, the xacro cache, and `scenario` run as a user runs it: a
// drive that reaches its region, one into a wall, a bad path, determinism, a matrix cell, the video, and a
// launch scenario that leaves no process behind. No roscore of the test's own.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <nlohmann/json.hpp>

extern "C" {
#include <libavformat/avformat.h>
}

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <thread>

#include "bullet_sim/physics/clearance.h"
#include "bullet_sim/scenario/scenario_file.h"
#include "bullet_sim/tools/xacro_cache.h"
#include "test_support.h"

namespace bullet_sim {
namespace {

namespace fs = std::filesystem;
using ::testing::AllOf;
using ::testing::HasSubstr;
using Json = nlohmann::json;
using test::TemporaryFolder;

std::string scenarioFile(const std::string& name) { return test::fixture("scenarios/" + name); }

test::CommandResult runScenario(const std::string& arguments) {
  return test::run(std::string(SCENARIO) + " " + arguments + " 2>&1");
}

Json resultOf(const std::string& folder) {
  std::ifstream in(folder + "/result.json");
  return Json::parse(in);
}

const Json& checkOf(const Json& result, const std::string& type) {
  for (const Json& check : result["checks"]) {
    if (check["type"] == type) return check;
  }
  throw std::runtime_error("no check " + type);
}

TEST(ScenarioSpec, ReadsEveryField) {
  const std::string yaml = R"(
name: every_field
robot: {description: reach_region.yaml, args: {with_lidar: false}, name: car, count: 2, wheel_model: contact}
world: test_room.world
spawn: [{x: 1, y: 2, yaw: 0.5}, {x: -1, y: 0, z: 0.2, joints: {pan: 0.3}}]
seed: 9
duration: 3
step: 0.002
record_period: 0.1
drive: {timeline: [{duration: 1, v: 0.2, w: 0.1, robot: car_2}, {duration: 2, vy: 0.3}]}
checks:
  - reach: {x: [1, 2], y: [-1, 1], by: 2, robot: car_1}
  - clearance: {min: 0.3, from: lidar}
  - upright: {max_tilt: 0.2}
  - final_pose: {x: 1, y: 2, position_tolerance: 0.1}
video: {fps: 10, size: 320x240}
)";
  const ScenarioSpec spec =
      parseScenario(yaml, scenarioFile("inline.yaml"), PackageResolver::fromEnvironment());
  EXPECT_EQ(spec.name, "every_field");
  EXPECT_EQ(spec.description, scenarioFile("reach_region.yaml"));
  EXPECT_THAT(spec.xacro_args, ::testing::ElementsAre("with_lidar:=false"));
  EXPECT_EQ(spec.robotNames("model"), (std::vector<std::string>{"car_1", "car_2"}));
  EXPECT_EQ(spec.wheel_model, "contact");
  EXPECT_THAT(spec.world, HasSubstr("bullet_sim/worlds/test_room.world"));
  ASSERT_EQ(spec.spawn.size(), 2u);
  EXPECT_DOUBLE_EQ(spec.spawn[0].yaw, 0.5);
  EXPECT_EQ(spec.spawn[1].z, 0.2);
  EXPECT_DOUBLE_EQ(spec.spawn[1].joints.at("pan"), 0.3);
  EXPECT_EQ(spec.seed, 9u);
  EXPECT_DOUBLE_EQ(spec.step, 0.002);
  ASSERT_EQ(spec.timeline.size(), 2u);
  EXPECT_EQ(spec.timeline[0].robot, "car_2");
  EXPECT_DOUBLE_EQ(spec.timeline[1].vy, 0.3);
  ASSERT_EQ(spec.checks.size(), 4u);
  EXPECT_TRUE(spec.checks[0].region.contains(1.5, 0));
  EXPECT_FALSE(spec.checks[0].region.contains(2.5, 0));
  EXPECT_DOUBLE_EQ(spec.checks[0].region.distance(2.5, 0), 0.5);
  EXPECT_TRUE(spec.checks[1].from_lidar);
  EXPECT_FALSE(spec.checks[3].check_yaw);
  EXPECT_EQ(spec.video_width, 320);
}

TEST(ScenarioSpec, ReportsEveryBadKeyAtOnce) {
  const std::string yaml = R"(
robot: {description: reach_region.yaml}
duraton: 3
step: -1
drive: {timeline: [{v: 0.5}]}
checks:
  - reach: {x: 1, y: 0, radius: 0.2}
  - clearence: {min: 1}
  - clearance: {min: 0.2, from: sonar}
)";
  try {
    parseScenario(yaml, scenarioFile("inline.yaml"), PackageResolver::fromEnvironment());
    FAIL() << "a bad scenario was read";
  } catch (const ScenarioError& error) {
    EXPECT_THAT(error.what(), AllOf(HasSubstr("duraton: unknown key (did you mean [duration]?)"),
                                    HasSubstr("step: [-1] is out of range"),
                                    HasSubstr("drive.timeline.0: missing duration"),
                                    HasSubstr("checks.0.reach: missing by"),
                                    HasSubstr("unknown check [clearence] (did you mean [clearance]?)"),
                                    HasSubstr("checks.2.clearance.from: [sonar]: choose geometry or lidar")));
  }
}

TEST(ScenarioMatrix, CrossesItsAxesTheLastFastest) {
  const Matrix matrix = loadMatrix(scenarioFile("drive_matrix.yaml"));
  EXPECT_EQ(matrix.name, "drive_matrix");
  EXPECT_EQ(matrix.count, 8);
  const MatrixCell cell = matrix.cell(5);
  EXPECT_THAT(cell.values,
              ::testing::ElementsAre(std::make_pair(std::string("drive.timeline.1.v"), std::string("0.5")),
                                     std::make_pair(std::string("seed"), std::string("2"))));
  const ScenarioSpec spec = cellScenario(matrix, 5, PackageResolver::fromEnvironment());
  EXPECT_EQ(spec.name, "reach_region_5");
  EXPECT_EQ(spec.seed, 2u);
  EXPECT_DOUBLE_EQ(spec.timeline.at(1).v, 0.5);
  EXPECT_DOUBLE_EQ(cellScenario(matrix, 2, PackageResolver::fromEnvironment()).timeline.at(1).v, 0.4);
  EXPECT_THROW(
      try { matrix.cell(8); } catch (const ScenarioError& error) {
        EXPECT_THAT(error.what(), HasSubstr("no cell [8]: it has 8, numbered 0 to 7"));
        throw;
      },
      ScenarioError);
}

TEST(ScenarioMatrix, RefusesAnAxisOutsideTheScenario) {
  TemporaryFolder folder;
  std::ofstream(folder / "m.yaml") << "scenario: " << scenarioFile("reach_region.yaml")
                                   << "\naxes: {drive.timeline.5.v: [1, 2]}\n";
  const Matrix matrix = loadMatrix(folder / "m.yaml");
  EXPECT_THROW(
      try { matrix.cell(0); } catch (const ScenarioError& error) {
        EXPECT_THAT(error.what(), HasSubstr("[5] is not an index of the list at [drive.timeline.5.v]"));
        throw;
      },
      ScenarioError);
}

TEST(ScenarioMatrix, RefusesARangePastTheLargestWholeNumber) {
  TemporaryFolder folder;
  const auto matrixWithSeeds = [&](const std::string& range) {
    std::ofstream(folder / "m.yaml") << "scenario: " << scenarioFile("reach_region.yaml")
                                     << "\naxes: {seed: " << range << "}\n";
    return loadMatrix(folder / "m.yaml");
  };
  EXPECT_THAT(matrixWithSeeds("{from: 9223372036854775806, count: 2}").values.back(),
              ::testing::ElementsAre("9223372036854775806", "9223372036854775807"));
  EXPECT_THROW(
      try { matrixWithSeeds("{from: 9223372036854775806, count: 3}"); } catch (const ScenarioError& error) {
        EXPECT_THAT(error.what(),
                    HasSubstr("{from: 9223372036854775806, count: 3} goes past the largest whole number"));
        throw;
      },
      ScenarioError);
}

/// A 0.4 x 0.4 x 0.2 m box robot.
ModelSpec boxRobot() {
  const std::string urdf = R"(<robot name="box"><link name="base"><inertial><mass value="1"/>
    <inertia ixx="0.02" iyy="0.02" izz="0.03" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><geometry><box size="0.4 0.4 0.2"/></geometry></collision></link></robot>)";
  return test::parseQuietly(urdf, "box.urdf");
}

TEST(Clearance, IsTheDistanceToTheNearestWall) {
  const WorldSpec room = test::shippedWorld("test_room.world");
  Simulation simulation(room);
  // test_room's inner faces: x = +-3, y = +-2. The box's faces are 0.2 m from its centre.
  const Robot& near_east = simulation.spawn("east", boxRobot(), {.x = 2.3, .y = 0.5});
  const Robot& middle = simulation.spawn("middle", boxRobot(), {.x = -0.5, .y = 0});
  const Robot& corner = simulation.spawn("corner", boxRobot(), {.x = -2.5, .y = 1.6});
  ClearanceQuery query(room);
  const Clearance east = query.nearest(near_east.body(), 1.0);
  EXPECT_NEAR(east.distance, 3.0 - 2.5, 1e-4);
  EXPECT_EQ(east.obstacle, "room");
  const Clearance far = query.nearest(middle.body(), 1.0);
  EXPECT_DOUBLE_EQ(far.distance, 1.0);  // the nearest wall is 1.5 m away: beyond the cap
  EXPECT_EQ(far.obstacle, "");
  EXPECT_NEAR(query.nearest(corner.body(), 1.0).distance, 2.0 - 1.8, 1e-4);
}

TEST(XacroCache, ServesItsEntryUntilAnIncludedFileChanges) {
  TemporaryFolder folder;
  const auto write = [&](const std::string& link) {
    std::ofstream(folder / "part.xacro")
        << "<robot xmlns:xacro=\"http://www.ros.org/wiki/xacro\"><link name=\"" << link << "\"/></robot>\n";
  };
  write("first");
  std::ofstream(folder / "top.urdf.xacro")
      << "<robot name=\"r\" xmlns:xacro=\"http://www.ros.org/wiki/xacro\">"
         "<xacro:include filename=\"part.xacro\"/></robot>\n";
  const std::string cache = folder / "cache";
  EXPECT_THAT(cachedXacro(folder / "top.urdf.xacro", {}, cache), HasSubstr("first"));
  // The entry is what the next call returns: mark it, and the mark comes back.
  ASSERT_EQ(std::distance(fs::directory_iterator(cache), fs::directory_iterator()), 1);
  const fs::path entry = fs::directory_iterator(cache)->path();
  std::string text = test::readFile(entry.string());
  text = text.substr(0, text.find("\n\n") + 2) + "<robot name=\"from_the_cache\"/>";
  std::ofstream(entry) << text;
  EXPECT_THAT(cachedXacro(folder / "top.urdf.xacro", {}, cache), HasSubstr("from_the_cache"));
  // Another argument is another entry; a changed included file is expanded again.
  EXPECT_THAT(cachedXacro(folder / "top.urdf.xacro", {"unused:=1"}, cache), HasSubstr("first"));
  write("second");
  fs::last_write_time(folder / "part.xacro",
                      fs::last_write_time(folder / "part.xacro") + std::chrono::seconds(2));
  EXPECT_THAT(cachedXacro(folder / "top.urdf.xacro", {}, cache), HasSubstr("second"));
}

TEST(ScenarioTool, ADriveReachesItsRegion) {
  TemporaryFolder out;
  const auto run = runScenario(scenarioFile("reach_region.yaml") + " --out " + out.path().string());
  EXPECT_EQ(run.status, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("scenario reach_region: pass: 7 checks passed"));
  const Json result = resultOf(out.path());
  EXPECT_EQ(result["verdict"], "pass");
  EXPECT_EQ(result["mode"], "timeline");
  EXPECT_EQ(result["deterministic"], true);
  // x >= -0.3 after 1.7 m: 0.5 s at rest, the 0.278 s ramp to 0.5 m/s (0.069 m), then 1.631 m at 0.5 m/s.
  EXPECT_NEAR(checkOf(result, "reach")["value"].get<double>(), 0.5 + 0.5 / 1.8 + (1.7 - 0.0694) / 0.5, 0.02);
  EXPECT_NEAR(result["metrics"]["chair"]["final_x_m"].get<double>(), 0.0, 0.005);
  EXPECT_GT(result["timing"]["rtf"].get<double>(), 1.0);
  // A row every record_period (0.05 s) of the 6 s, from the first step.
  std::ifstream csv(out / "trajectory.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header, "time,robot,x,y,z,roll,pitch,yaw,v,w");
  size_t rows = 0;
  for (std::string line; std::getline(csv, line);) ++rows;
  EXPECT_EQ(rows, 121u);
  EXPECT_EQ(test::readFile(out / "top.png").substr(1, 3), "PNG");
}

TEST(ScenarioTool, ADriveIntoAWallFails) {
  TemporaryFolder out;
  const auto run = runScenario(scenarioFile("hit_wall.yaml") + " --out " + out.path().string());
  EXPECT_EQ(run.status, 1) << run.output;
  EXPECT_THAT(run.output, HasSubstr("fail: no_collision [chair]: first touched at t = "));
  const Json result = resultOf(out.path());
  EXPECT_EQ(result["verdict"], "fail");
  EXPECT_EQ(checkOf(result, "no_collision")["passed"], false);
  EXPECT_THAT(checkOf(result, "no_collision")["detail"].get<std::string>(),
              HasSubstr("[room::wall_east::collision]"));
  EXPECT_EQ(checkOf(result, "clearance")["value"], 0.0);
  EXPECT_EQ(checkOf(result, "upright")["passed"], true);
  // Stopped by the wall's inner face at x = 3: the root link stays behind it.
  EXPECT_LT(result["metrics"]["chair"]["final_x_m"].get<double>(), 3.0);
}

TEST(ScenarioTool, ABadPathCannotRun) {
  TemporaryFolder out;
  const auto run = runScenario(scenarioFile("bad_path.yaml") + " --out " + out.path().string());
  EXPECT_EQ(run.status, 2) << run.output;
  EXPECT_THAT(run.output, AllOf(HasSubstr("could not run"),
                                HasSubstr("robot.description: [no_such_robot.urdf.xacro] is not a file")));
  EXPECT_EQ(resultOf(out.path())["verdict"], "error");
  EXPECT_EQ(runScenario("").status, 2);
  EXPECT_EQ(runScenario(scenarioFile("reach_region.yaml") + " --seed x").status, 2);
}

/// One line on stderr naming the value, nothing on stdout, exit code 2: a row per bad argument or file.
TEST(ScenarioTool, AnswersEveryBadArgumentInOneLine) {
  TemporaryFolder folder;
  std::ofstream(folder / "a_file") << "x\n";
  std::ofstream(folder / "two_problems.yaml") << "seed: -1\nduration: -2\nrobot: {description: nope.xacro}\n";
  const auto matrixFile = [&](const std::string& name, const std::string& axes) {
    std::ofstream(folder / name) << "scenario: " << scenarioFile("reach_region.yaml") << "\naxes: " << axes
                                 << "\n";
    return folder / name;
  };
  const std::string scenario = scenarioFile("reach_region.yaml"), matrix = scenarioFile("drive_matrix.yaml");
  const std::vector<std::pair<std::string, std::string>> rows = {
      {"", "give a scenario FILE, or --matrix M.yaml --index N"},
      {folder / "nope.yaml", "scenario [" + (folder / "nope.yaml") + "] is not a file"},
      {folder.path().string(), "scenario [" + folder.path().string() + "] is not a file"},
      {folder / "two_problems.yaml",
       "seed: [-1] is out of range: give a number from 0 to 9.0072e+15; duration: [-2] is out of range"},
      {scenario + " --bogus", "The following argument was not expected: --bogus"},
      {scenario + " " + scenario, "give one scenario FILE"},
      {scenario + " --seed x", "--seed: [x] is not a number"},
      {scenario + " --seed -1", "--seed [-1]: give a whole number from 0"},
      {scenario + " --seed 1e300", "--seed [1e300]: give a whole number from 0"},
      {scenario + " --seed nan", "--seed: [nan] is not a number"},
      {scenario + " --out " + (folder / "a_file"),
       "--out [" + (folder / "a_file") + "] is a file, not a folder"},
      {scenario + " --out " + (folder / "a_file/sub"),
       "cannot make the run's folder [" + (folder / "a_file/sub")},
      {scenario + " --bag-chunk-size 0.5", "--bag-chunk-size [0.5]: give a whole number from 0"},
      {scenario + " --index 1", "--index goes with --matrix"},
      {"--matrix " + matrix, "--matrix needs --index N (the cell to run), or --list"},
      {"--matrix " + matrix + " --index 1 " + scenario, "give a scenario FILE, or --matrix M.yaml --index N"},
      {"--matrix " + matrix + " --index 8", "no cell [8]: it has 8, numbered 0 to 7"},
      {"--matrix " + matrix + " --index -1", "--index [-1]: give a whole number from 0"},
      {"--matrix " + (folder / "nope.yaml") + " --list",
       "matrix [" + (folder / "nope.yaml") + "] is not a file"},
      {"--matrix " + matrixFile("wraps.yaml", "{seed: {from: 9223372036854775807, count: 2}}") + " --list",
       "{from: 9223372036854775807, count: 2} goes past the largest whole number"},
      {"--matrix " + matrixFile("huge.yaml", "{seed: {from: 1, count: 1e400}}") + " --list",
       "count 1 to 100000"},
      {"--matrix " + matrixFile("outside.yaml", "{drive.timeline.5.v: [1, 2]}") + " --list",
       "[5] is not an index of the list at [drive.timeline.5.v]"},
      {"--matrix " + matrixFile("negative.yaml", "{seed: {from: -5, count: 2}}") + " --list",
       "reach_region.yaml: seed: [-5] is out of range: give a number from 0 to 9.0072e+15"},
      {"--list", "give a scenario FILE, or --matrix M.yaml --index N"},
  };
  for (const auto& [arguments, expected] : rows) {
    SCOPED_TRACE(arguments);
    const auto run = test::run("cd " + folder.path().string() + " && " + SCENARIO + " " + arguments);
    EXPECT_EQ(run.status, 2);
    EXPECT_EQ(run.output, "");
    EXPECT_THAT(run.errors, AllOf(::testing::StartsWith("scenario: "), HasSubstr(expected)));
    EXPECT_EQ(std::count(run.errors.begin(), run.errors.end(), '\n'), 1) << run.errors;
  }
}

/// --list gives each cell's values without building each cell's scenario (100000 cells took 10 s, a million
/// 100 s); the scenario is built for the first and the last.
TEST(ScenarioTool, ListsCellsWithoutBuildingEach) {
  TemporaryFolder folder;
  std::ofstream(folder / "m.yaml")
      << "scenario: " << scenarioFile("reach_region.yaml")
      << "\naxes: {seed: {from: 1, count: 1000}, drive.timeline.0.v: {from: 1, count: 100}}\n";
  const auto listing = test::run(std::string(SCENARIO) + " --matrix " + (folder / "m.yaml") + " --list");
  ASSERT_EQ(listing.status, 0) << listing.errors;
  const Json json = Json::parse(listing.output);
  EXPECT_EQ(json["count"], 100000);
  EXPECT_EQ(json["cells"][101]["values"], Json({{"seed", "2"}, {"drive.timeline.0.v", "2"}}));
  EXPECT_EQ(json["cells"].back()["values"], Json({{"seed", "1000"}, {"drive.timeline.0.v", "100"}}));
}

TEST(ScenarioTool, TheSameFileAndSeedGiveTheSameResult) {
  TemporaryFolder out;
  for (const char* run : {"a", "b"})
    ASSERT_EQ(runScenario(scenarioFile("reach_region.yaml") + " --seed 11 --out " + (out / run)).status, 0);
  Json first = resultOf(out / "a"), second = resultOf(out / "b");
  EXPECT_EQ(first["seed"], 11);
  first.erase("timing");
  second.erase("timing");
  EXPECT_EQ(first, second);
  EXPECT_EQ(test::readFile(out / "a/trajectory.csv"), test::readFile(out / "b/trajectory.csv"));
}

TEST(ScenarioTool, RunsAMatrixCell) {
  TemporaryFolder out;
  const auto listing =
      test::run(std::string(SCENARIO) + " --matrix " + scenarioFile("drive_matrix.yaml") + " --list");
  ASSERT_EQ(listing.status, 0) << listing.errors;
  EXPECT_EQ(Json::parse(listing.output)["count"], 8);
  const auto run = runScenario("--matrix " + scenarioFile("drive_matrix.yaml") + " --index 6 --out " +
                               out.path().string());
  EXPECT_EQ(run.status, 0) << run.output;
  const Json result = resultOf(out.path());
  EXPECT_EQ(result["scenario"], "reach_region_6");
  EXPECT_EQ(result["matrix"]["index"], 6);
  EXPECT_EQ(result["matrix"]["values"]["seed"], "3");
  EXPECT_EQ(result["seed"], 3);
  const auto outside =
      runScenario("--matrix " + scenarioFile("drive_matrix.yaml") + " --index 8 --out " + (out / "8"));
  EXPECT_EQ(outside.status, 2);
  EXPECT_THAT(outside.output, HasSubstr("no cell [8]: it has 8, numbered 0 to 7"));
  EXPECT_EQ(resultOf(out / "8")["verdict"], "error");
}

/// The video frames of an MP4 file, as libavformat reads them.
int videoFrames(const std::string& path) {
  AVFormatContext* format = nullptr;
  if (avformat_open_input(&format, path.c_str(), nullptr, nullptr) < 0) return -1;
  int frames = 0;
  if (avformat_find_stream_info(format, nullptr) >= 0) {
    const int stream = av_find_best_stream(format, AVMEDIA_TYPE_VIDEO, -1, -1, nullptr, 0);
    AVPacket* packet = av_packet_alloc();
    while (stream >= 0 && av_read_frame(format, packet) >= 0) {
      frames += packet->stream_index == stream;
      av_packet_unref(packet);
    }
    av_packet_free(&packet);
  }
  avformat_close_input(&format);
  return frames;
}

TEST(ScenarioTool, WritesTheChaseViewAsAVideo) {
  TemporaryFolder out;
  const auto run = runScenario(scenarioFile("hit_wall.yaml") + " --video --out " + out.path().string());
  EXPECT_EQ(run.status, 1) << run.output;
  EXPECT_EQ(videoFrames(out / "video.mp4"), 8 * 25);  // 8 s of sim time at 25 frames a second
  EXPECT_EQ(resultOf(out.path())["outputs"]["video"], "video.mp4");
}

/// The processes that belong to a launch run writing into `folder`: each has the folder in its command line
/// or in its environment (ROS_LOG_DIR).
std::vector<std::string> processesOf(const fs::path& folder) {
  std::vector<std::string> found;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator("/proc", ec)) {
    const std::string pid = entry.path().filename();
    if (pid.find_first_not_of("0123456789") != std::string::npos) continue;
    // A process may end between the listing and the reading: then there is nothing to read, and nothing left.
    std::ifstream cmdline_file(entry.path() / "cmdline", std::ios::binary);
    std::string cmdline((std::istreambuf_iterator<char>(cmdline_file)), {});
    std::ifstream environ_file(entry.path() / "environ", std::ios::binary);
    const std::string environment((std::istreambuf_iterator<char>(environ_file)), {});
    if (cmdline.find(folder.string()) != std::string::npos ||
        environment.find(folder.string()) != std::string::npos) {
      std::replace(cmdline.begin(), cmdline.end(), '\0', ' ');
      found.push_back(pid + ": " + cmdline);
    }
  }
  return found;
}

TEST(ScenarioTool, ALaunchScenarioLeavesNoProcessBehind) {
  TemporaryFolder out;
  const fs::path run_folder = out.path() / "run";
  EXPECT_THAT(processesOf(run_folder), ::testing::IsEmpty());
  const auto run = runScenario(scenarioFile("teleop_launch.yaml") + " --out " + run_folder.string());
  EXPECT_EQ(run.status, 0) << run.output << test::readFile((run_folder / "launch.log").string());
  EXPECT_THAT(processesOf(run_folder), ::testing::IsEmpty());
  int status = 0;
  EXPECT_EQ(waitpid(-1, &status, WNOHANG), -1);  // nothing of ours left to reap either
  const Json result = resultOf(run_folder);
  EXPECT_EQ(result["mode"], "launch");
  EXPECT_EQ(result["deterministic"], false);
  // The user's node drove it at 0.3 m/s for 2 s of sim time, from t = 1 s.
  EXPECT_NEAR(result["metrics"]["smartwheelchair_model"]["distance_m"].get<double>(), 0.6, 0.3);
}

}  // namespace
}  // namespace bullet_sim
