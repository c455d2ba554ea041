// Input that crashed, hung or exhausted the simulator (issue 17): every case of fixtures/bad_input/cases.yaml
// is refused by the loader and by urdf_doctor with the same message, while a robot already in the world
// drives on; spawn poses that are not finite or too far; SDF models to spawn and worlds held to the same
// limits; meshes that crash or hang their importer.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <malloc.h>
#include <signal.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <fstream>

#include "bullet_sim/common/diagnostics.h"
#include "bullet_sim/model/sdf_model.h"
#include "bullet_sim/plugins/registry.h"
#include "plugins/wheeled_drive/wheeled_drive.h"
#include "bullet_sim/tools/process_stats.h"
#include "assets/child_process.h"
#include "test_support.h"

namespace bullet_sim {
namespace {

using ::testing::HasSubstr;
namespace fs = std::filesystem;

struct Case {
  std::string file;      ///< in fixtures/bad_input, or "" for a generated one
  std::string generate;  ///< what to generate (cases.yaml says)
  int links = 0;
  bool loads = false;
  std::string message;
};

std::vector<Case> loadCases() {
  std::vector<Case> cases;
  for (const YAML::Node& node : YAML::LoadFile(test::fixture("bad_input/cases.yaml"))) {
    Case c;
    c.file = node["file"].as<std::string>("");
    c.generate = node["generate"].as<std::string>("");
    c.links = node["links"].as<int>(0);
    c.loads = node["loads"].as<bool>(false);
    c.message = node["message"].as<std::string>();
    cases.push_back(c);
  }
  return cases;
}

/// A temporary folder, removed with everything in it.
class TemporaryFolder {
 public:
  TemporaryFolder() {
    std::string pattern = (fs::temp_directory_path() / "bad_input_XXXXXX").string();
    path_ = mkdtemp(pattern.data());
  }
  ~TemporaryFolder() { fs::remove_all(path_); }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

std::string revoluteChain(int links) {
  const std::string inertial =
      "<inertial><mass value=\"0.1\"/><inertia ixx=\"1e-4\" iyy=\"1e-4\" izz=\"1e-4\" ixy=\"0\" ixz=\"0\" "
      "iyz=\"0\"/></inertial><collision><geometry><box size=\"0.05 0.05 0.05\"/></geometry></collision>";
  std::string urdf = "<robot name=\"chain\">\n";
  for (int i = 0; i < links; ++i)
    urdf += "<link name=\"l" + std::to_string(i) + "\">" + inertial + "</link>\n";
  for (int i = 1; i < links; ++i) {
    urdf += "<joint name=\"j" + std::to_string(i) + "\" type=\"revolute\"><parent link=\"l" +
            std::to_string(i - 1) + "\"/><child link=\"l" + std::to_string(i) +
            "\"/><origin xyz=\"0 0 0.06\"/><axis xyz=\"0 1 0\"/>" +
            "<limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/></joint>\n";
  }
  return urdf + "</robot>\n";
}

std::string meshRobot(const std::string& mesh) {
  return "<robot name=\"mesh\"><link name=\"base\"><inertial><mass value=\"1\"/><inertia ixx=\"0.01\" "
         "iyy=\"0.01\" izz=\"0.01\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial><visual><geometry><mesh "
         "filename=\"file://" +
         mesh + "\"/></geometry></visual></link></robot>\n";
}

/// The URDF of a case, its files written into `folder` when it is generated.
std::string urdfOf(const Case& c, const std::string& folder) {
  if (!c.file.empty()) return test::readFile(test::fixture("bad_input/" + c.file));
  if (c.generate == "revolute_chain") return revoluteChain(c.links);
  if (c.generate == "fifo_mesh") {
    EXPECT_EQ(mkfifo((folder + "/mesh.stl").c_str(), 0600), 0);
    return meshRobot(folder + "/mesh.stl");
  }
  if (c.generate == "obj_naming_fifo") {
    std::ofstream(folder + "/mesh.obj") << "mtllib mesh.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n";
    EXPECT_EQ(mkfifo((folder + "/mesh.mtl").c_str(), 0600), 0);
    return meshRobot(folder + "/mesh.obj");
  }
  if (c.generate == "sparse_mesh") {
    std::ofstream(folder + "/mesh.stl").close();
    fs::resize_file(folder + "/mesh.stl", 300u << 20);  // sparse: takes no disk space
    return meshRobot(folder + "/mesh.stl");
  }
  ADD_FAILURE() << "cases.yaml: unknown generate [" << c.generate << "]";
  return "";
}

std::string replaceAll(std::string text, const std::string& from, const std::string& to) {
  for (size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
    text.replace(at, from.size(), to);
  return text;
}

std::string describe(const Case& c) {
  return c.file.empty() ? c.generate + " " + std::to_string(c.links) : c.file;
}

/// Where the two-wheeler's base is, after driving it straight at 0.3 m/s for 1 s from where it stands.
double drivenDistance(Simulation& simulation, Robot& robot) {
  auto& drive = *test::pluginsOf<WheeledDrive>(robot).front();
  const Eigen::Vector3d start = robot.body().linkPose("base_link").translation();
  for (int i = 0; i < 1000; ++i) {
    if (i % 100 == 0) drive.setCommand(0.3, 0, simulation.time());
    simulation.step();
  }
  return (robot.body().linkPose("base_link").translation() - start).norm();
}

TEST(BadInput, TheLoaderAndUrdfDoctorGiveTheSameMessageAndTheRobotDrivesOn) {
  Simulation simulation(test::shippedWorld("empty.world"));
  const std::string driver_urdf = test::twoWheelerWithDiffDrive({{"robotBaseFrame", "base_footprint"}});
  Robot& driver = simulation.spawn("driver", test::parseQuietly(driver_urdf, "two_wheeler.urdf"), {});
  for (const Case& c : loadCases()) {
    SCOPED_TRACE(describe(c));
    TemporaryFolder folder;
    const std::string message = replaceAll(c.message, "TMP", folder.path());
    const std::string file = folder.path() + "/robot.urdf";
    std::ofstream(file) << urdfOf(c, folder.path());

    std::vector<std::string> warnings;
    try {
      ModelSpec model = parseModel(test::readFile(file), file, PackageResolver::fromEnvironment(), &warnings);
      simulation.spawn("bad", std::move(model), {}, &warnings);
      EXPECT_TRUE(c.loads) << "loaded";
      std::string all;
      for (const auto& warning : warnings) all += warning + "\n";
      EXPECT_THAT(all, HasSubstr(message));
      simulation.remove("bad");
    } catch (const SpecError& e) {
      EXPECT_FALSE(c.loads) << e.what();
      EXPECT_THAT(e.what(), HasSubstr(message));
    }
    const test::CommandResult doctor = test::run(std::string(URDF_DOCTOR) + " " + file);
    EXPECT_EQ(doctor.status, c.loads ? 0 : 1) << doctor.output;
    EXPECT_THAT(doctor.output, HasSubstr(message));
    EXPECT_GT(drivenDistance(simulation, driver), 0.25) << "the robot already in the world stopped driving";
  }
}

/// The message of the SpecError that spawning the minimal robot at `pose` throws, or "" when it spawns.
std::string spawnError(Simulation& simulation, const SpawnPose& pose) {
  try {
    const ModelSpec model =
        test::parseQuietly(test::readFile(test::fixture("robots/minimal.urdf")), "minimal");
    simulation.spawn("at_pose", model, pose);
    simulation.remove("at_pose");
  } catch (const SpecError& e) {
    return e.what();
  }
  return "";
}

TEST(BadInput, SpawnPosesThatAreNotFiniteOrTooFarAreRefused) {
  Simulation simulation(test::shippedWorld("empty.world"));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  SpawnPose pose;
  pose.x = nan;
  EXPECT_THAT(spawnError(simulation, pose), HasSubstr("spawn pose x [nan] is not a finite number"));
  pose = {};
  pose.z = 1e9;
  EXPECT_THAT(spawnError(simulation, pose),
              HasSubstr("spawn pose z [1e+09] m is beyond the limit of 10000 m (max_length)"));
  pose = {};
  pose.yaw = -inf;
  EXPECT_THAT(spawnError(simulation, pose), HasSubstr("spawn pose yaw [-inf] is not a finite number"));
  pose = {};
  pose.joints["no_such_joint"] = nan;
  EXPECT_THAT(spawnError(simulation, pose), HasSubstr("initial position for [no_such_joint]"));
  EXPECT_EQ(spawnError(simulation, {}), "");
  simulation.step();
}

TEST(BadInput, ServicePosesThatAreNotFiniteAreRefusedNamingTheValue) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Diagnostics position("spawn");
  spawnPoseFrom(Eigen::Vector3d(1, nan, 0), Eigen::Quaterniond::Identity(), true, position);
  EXPECT_THAT(::testing::PrintToString(position.errors()),
              HasSubstr("spawn position [  1 nan   0] is not finite"));
  Diagnostics orientation("spawn");
  spawnPoseFrom(Eigen::Vector3d::Zero(), Eigen::Quaterniond(nan, 0, 0, 1), true, orientation);
  EXPECT_THAT(::testing::PrintToString(orientation.errors()),
              HasSubstr("spawn orientation (x y z w) [0 0 1 nan] is not finite"));
  Diagnostics zero("spawn");
  const SpawnPose identity =
      spawnPoseFrom(Eigen::Vector3d(1, 2, 3), Eigen::Quaterniond(0, 0, 0, 0), false, zero);
  EXPECT_TRUE(zero.errors().empty());
  EXPECT_THAT(::testing::PrintToString(zero.warnings()), HasSubstr("is no rotation: the identity is used"));
  EXPECT_EQ(identity.yaw, 0);
  EXPECT_EQ(identity.z, 3);
  Diagnostics turned("spawn");
  const SpawnPose quarter =
      spawnPoseFrom(Eigen::Vector3d::Zero(), Eigen::Quaterniond(2, 0, 0, 2), true, turned);
  EXPECT_NEAR(quarter.yaw, M_PI / 2, 1e-12);  // normalised
  EXPECT_FALSE(quarter.z);
}

TEST(BadInput, AbsurdCommandsLeaveTheRobotFinite) {
  for (const std::string& wheel_model : test::kWheelModels) {
    SCOPED_TRACE(wheel_model);
    Simulation simulation(test::shippedWorld("empty.world"));
    Robot& robot = simulation.spawn("chair", test::wheelchair(wheel_model), {});
    auto& drive = *test::pluginsOf<WheeledDrive>(robot).front();
    for (const auto& [linear, angular] : {std::pair{1e308, 0.0}, {0.0, -1e308}, {1e30, 1e30}}) {
      for (int i = 0; i < 500; ++i) {
        if (i % 100 == 0) {
          EXPECT_TRUE(drive.setCommand(linear, angular, simulation.time()));
        }
        simulation.step();
      }
      EXPECT_TRUE(robot.body().linkPose("base_link").matrix().allFinite());
    }
  }
}

/// The message of the SpecError that parsing a world of `models` throws, or "" when it loads.
std::string worldError(const std::string& models, const Limits& limits = Limits()) {
  try {
    parseWorld("<sdf version=\"1.6\"><world name=\"w\">" + models + "</world></sdf>", "bad.world",
               PackageResolver::fromEnvironment(), nullptr, WorldOptions{false, limits});
  } catch (const SpecError& e) {
    return e.what();
  }
  return "";
}

std::string boxModel(const std::string& name, const std::string& pose, const std::string& size) {
  return "<model name=\"" + name + "\"><static>true</static><pose>" + pose + "</pose><link name=\"l\">" +
         "<collision name=\"c\"><geometry><box><size>" + size + "</size></box></geometry></collision>" +
         "</link></model>";
}

TEST(BadInput, WorldsOfAbsurdSizesPosesOrCountsAreRefused) {
  EXPECT_THAT(
      worldError(boxModel("wall", "0 0 0 0 0 0", "1e9 1 1")),
      HasSubstr("model [wall] link [l] collision [c]: size [1e+09] m is beyond the limit of 10000 m"));
  EXPECT_THAT(worldError(boxModel("far", "1e12 0 0 0 0 0", "1 1 1")),
              HasSubstr("model [far]: its position x [1e+12] m is beyond the limit of 10000 m (max_length)"));
  EXPECT_THAT(worldError(boxModel("flat", "0 0 0 0 0 0", "1 0 1")),
              HasSubstr("box size [1 0 1] must be positive"));
  Limits two_shapes;
  two_shapes.max_world_shapes = 2;
  const std::string three = boxModel("a", "0 0 0 0 0 0", "1 1 1") + boxModel("b", "2 0 0 0 0 0", "1 1 1") +
                            boxModel("c", "4 0 0 0 0 0", "1 1 1");
  const std::string distinct = boxModel("a", "0 0 0 0 0 0", "1 1 1") + boxModel("b", "2 0 0 0 0 0", "1 1 2") +
                               boxModel("c", "4 0 0 0 0 0", "1 1 3");
  for (const std::string& models : {three, distinct}) {  // copies of one model, and three kinds
    EXPECT_THAT(worldError(models, two_shapes),
                HasSubstr("the world has more than 2 collisions and visuals, the limit (max_world_shapes)"));
    EXPECT_EQ(worldError(models), "");
  }
}

/// The message of the SpecError that reading an SDF model to spawn of `links` throws, or "" when it loads.
std::string sdfModelError(const std::string& links, const Limits& limits = Limits()) {
  try {
    parseSdfModel("<sdf version=\"1.6\"><model name=\"m\">" + links + "</model></sdf>", "bad.sdf",
                  PackageResolver::fromEnvironment(), PluginRegistry::builtin(), nullptr, limits);
  } catch (const SpecError& e) {
    return e.what();
  }
  return "";
}

/// A link of an SDF model: a box of `size` at `pose`, of `mass` kg, with `extra` inside.
std::string sdfLink(const std::string& name, const std::string& pose = "0 0 0 0 0 0",
                    const std::string& size = "0.2 0.2 0.2", const std::string& mass = "1",
                    const std::string& extra = "") {
  return "<link name=\"" + name + "\"><pose>" + pose + "</pose><inertial><mass>" + mass +
         "</mass><inertia><ixx>0.01</ixx><iyy>0.01</iyy><izz>0.01</izz></inertia></inertial>" +
         "<collision name=\"c\"><geometry><box><size>" + size + "</size></box></geometry></collision>" +
         extra + "</link>";
}

TEST(BadInput, SdfModelsToSpawnAreBoundedAsUrdfsAre) {
  EXPECT_EQ(sdfModelError(sdfLink("base")), "");
  EXPECT_THAT(sdfModelError(sdfLink("base", "0 0 0 0 0 0", "0.2 0.2 0.2", "1e30")),
              HasSubstr("link [base] <inertial> mass [1e+30] kg is beyond the limit of 1e+06 kg (max_mass)"));
  EXPECT_THAT(sdfModelError(sdfLink("base", "0 0 0 0 0 0", "1e9 1 1")),
              HasSubstr("collision [c]: size [1e+09] m is beyond the limit of 10000 m (max_length)"));
  EXPECT_THAT(sdfModelError(sdfLink("base", "1e12 0 0 0 0 0")),
              HasSubstr("link [base]: its position x [1e+12] m is beyond the limit of 10000 m (max_length)"));
  EXPECT_THAT(sdfModelError(sdfLink("base", "0 0 0 0 0 0", "0.2 0 0.2")),
              HasSubstr("box size [0.2 0 0.2] must be positive"));
  const std::string lidar = R"(<sensor name="lidar" type="ray"><ray><scan><horizontal>
      <samples>2147483648</samples><min_angle>-1</min_angle><max_angle>1</max_angle></horizontal></scan>
      <range><min>0.1</min><max>10</max></range></ray>
      <plugin name="laser" filename="libgazebo_ros_laser.so"/></sensor>)";
  EXPECT_THAT(sdfModelError(sdfLink("base", "0 0 0 0 0 0", "0.2 0.2 0.2", "1", lidar)),
              HasSubstr("rays per scan, above the limit of 1048576 (max_rays)"));
  Limits two_links;
  two_links.max_links = 2;
  const std::string three = sdfLink("a") + sdfLink("b") + sdfLink("c") +
                            R"(<joint name="ab" type="fixed"><parent>a</parent><child>b</child></joint>
                               <joint name="bc" type="fixed"><parent>b</parent><child>c</child></joint>)";
  EXPECT_THAT(sdfModelError(three, two_links),
              HasSubstr("the robot has 3 links, above the limit of 2 (max_links)"));
  EXPECT_EQ(sdfModelError(three), "");
  // Counted in the text, before libsdformat reads it: with no time left to read it, the count still refuses.
  Limits two_links_no_time = two_links;
  two_links_no_time.world_load_seconds = 1e-6;
  EXPECT_THAT(sdfModelError(three, two_links_no_time),
              HasSubstr("the robot has 3 links, above the limit of 2 (max_links)"));
  Limits no_time;
  no_time.world_load_seconds = 1e-6;
  EXPECT_THAT(sdfModelError(three, no_time), HasSubstr("(world_load_seconds)"));  // what reading it gives
}

/// A robot of `boxes` visible boxes in a row on one link, the first ten colliding, with a 1000-beam lidar:
/// the issue's robot of 800,000 visuals, within the limits.
std::string heavyRobot(int boxes) {
  std::string shapes;
  for (int i = 0; i < boxes; ++i) {
    const std::string origin = "<origin xyz=\"" + std::to_string(0.01 * i) + " 0 0.05\"/>";
    const std::string box = "<geometry><box size=\"0.01 0.1 0.1\"/></geometry>";
    if (i < 10) shapes += "<collision>" + origin + box + "</collision>";
    shapes += "<visual>" + origin + box + "</visual>";
  }
  return R"(<robot name="heavy"><link name="base"><inertial><mass value="10"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>)" +
         shapes +
         R"(</link><gazebo reference="base"><sensor type="ray" name="lidar"><update_rate>100</update_rate>
    <pose>0 0 1 0 0 0</pose><ray><scan><horizontal><samples>1000</samples><min_angle>-3</min_angle>
    <max_angle>3</max_angle></horizontal></scan><range><min>0.1</min><max>10</max></range></ray>
    <plugin name="lidar_controller" filename="libgazebo_ros_laser.so"/></sensor></gazebo></robot>)";
}

TEST(Footprint, TheMemoryOfADeletedRobotIsGivenBack) {
  Simulation simulation(test::shippedWorld("empty.world"));
  simulation.step();
  Limits limits;
  limits.max_shapes = 100000;
  const ModelSpec heavy =
      parseModel(heavyRobot(60000), "heavy", PackageResolver::fromEnvironment(), nullptr, limits);
  malloc_trim(0);
  const double before = currentRssMb();
  double spawned = 0;
  for (int cycle = 0; cycle < 3; ++cycle) {
    simulation.spawn("heavy", heavy, {});
    for (int i = 0; i < 50; ++i) simulation.step();  // its lidar scans
    spawned = std::max(spawned, currentRssMb());
    ASSERT_TRUE(simulation.remove("heavy"));
    malloc_trim(0);  // as the node does
  }
  ASSERT_GT(spawned, before + 10) << "the robot took too little memory for the test to tell";
  EXPECT_LT(currentRssMb(), 1.1 * before)
      << "before the first spawn: " << before << " MB, with the robot " << spawned << " MB";
}

/// Inputs the fuzzers found that crash, hang or exhaust a library we cannot patch, in
/// bullet_sim/fuzz/crashes/<target>/library: the simulator's own readers, which run those libraries in a
/// child process, report each as a load error naming the file.
/// The files in `folder`; none when there is no such folder.
std::vector<fs::path> filesIn(const fs::path& folder) {
  std::vector<fs::path> files;
  std::error_code ec;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec))
    files.push_back(it->path());
  return files;
}

TEST(BadInput, FilesThatBreakALibraryAreLoadErrorsNamingTheFile) {
  const fs::path crashes = test::packageFile("bullet_sim", "fuzz/crashes");
  int replayed = 0;
  for (const fs::path& found : filesIn(crashes / "fuzz_mesh" / "library")) {
    const std::string bytes = test::readFile(found.string());
    ASSERT_FALSE(bytes.empty()) << found;
    // As fuzz_mesh takes it: the first byte chooses the format.
    static const char* const kExtensions[] = {".stl", ".obj", ".dae"};
    TemporaryFolder folder;
    const std::string path = folder.path() + "/mesh" + kExtensions[static_cast<unsigned char>(bytes[0]) % 3];
    std::ofstream(path, std::ios::binary) << bytes.substr(1);
    std::string error;
    EXPECT_FALSE(loadMesh(path, Eigen::Vector3d::Ones(), &error)) << found;
    EXPECT_THAT(error, HasSubstr("cannot load mesh [" + path + "]: ")) << found;
    if (found.filename().string().rfind("oom-", 0) == 0) {
      EXPECT_THAT(error, HasSubstr("the importer (assimp) ran out of the memory it may use on it")) << found;
    }
    ++replayed;
  }
  for (const fs::path& found : filesIn(crashes / "fuzz_world" / "library")) {
    EXPECT_THROW(parseWorld(test::readFile(found.string()), found.string(),
                            PackageResolver::fromEnvironment(), nullptr),
                 SpecError)
        << found;
    ++replayed;
  }
  EXPECT_GT(replayed, 0) << "no input in " << crashes << "/*/library";
}

TEST(BadInput, WorkThatCrashesHangsOrExhaustsItsChildEndsOnlyTheChild) {
  const auto crashed = runInChild(
      []() -> std::string {
        raise(SIGSEGV);
        return "";
      },
      1 << 30, 10);
  EXPECT_EQ(crashed.ending, ChildOutcome::Ending::kCrashed);
  EXPECT_THAT(crashed.why, HasSubstr("signal 11"));
  const auto hung = runInChild(
      []() -> std::string {
        for (;;) pause();
      },
      1 << 30, 0.2);
  EXPECT_EQ(hung.ending, ChildOutcome::Ending::kTimedOut);
  const auto greedy = runInChild([]() { return std::string(size_t{8} << 30, 'x'); }, 1 << 30, 10);
  EXPECT_EQ(greedy.ending, ChildOutcome::Ending::kThrew);
  EXPECT_THAT(greedy.why, HasSubstr("more memory than its limit"));
  const auto fine = runInChild([]() { return std::string("answer"); }, 1 << 30, 10);
  EXPECT_EQ(fine.ending, ChildOutcome::Ending::kReturned);
  EXPECT_EQ(fine.output, "answer");
}

}  // namespace
}  // namespace bullet_sim
