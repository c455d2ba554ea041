// bench: how fast and how exact bullet_sim is for one robot in one world, printed as one JSON object.
// ROS-free: it needs ROS_PACKAGE_PATH for package:// URIs and the xacro executable for .xacro robots only.
// Speed is measured here, never in tests; figures other than timings are deterministic.
#include <sys/resource.h>
#include <unistd.h>

#include <tinyxml2.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "bullet_sim/render/image.h"
#include "bullet_sim/render/offscreen_renderer.h"
#include "bullet_sim/scene/robot_snapshot.h"
#include "bullet_sim/scene/scene_builder.h"
#include "bullet_sim/scene/simulation_images.h"
#include "bullet_sim/simulation/simulation.h"
#include "bullet_sim/tools/process_stats.h"
#include "bullet_sim/tools/urdf_edits.h"
#include "bullet_sim/web/web_viewer.h"
#include "bench/bench_drive.h"
#include "bench/bench_fleet.h"
#include "common/work_pool.h"
#include "bench/bench_strikes.h"
#include "bench/bench_viewer.h"
#include "bench/bench_world.h"
#include "tools/command_line.h"

namespace bullet_sim {
namespace {

constexpr char kUsage[] =
    "usage: bench --robot FILE.urdf|FILE.xacro [--world FILE] [--pose x,y,yaw]\n"
    "             [--wheel-model contact|raycast] [--step S] [--duration S] [--cmd v,w]\n"
    "             [--lidar SAMPLES|SAMPLESxCHANNELS] [--lidar-rate HZ] [--render WxH]\n"
    "             [--obstacles N] [--boxes N] [--delete-cycles K] [--repeat K]\n"
    "             [--camera WxH@HZ [--depth]] [--web-viewer] [--limit NAME=VALUE]... [--lockstep]\n"
    "       bench --robots N[,N]... [--robot FILE] [--world FILE] [--pose x,y,yaw] [--wheel-model M]\n"
    "             [--step S] [--duration S] [--cmd v,w] [--lidar ...] [--lidar-rate HZ] [--repeat K]\n"
    "             [--threads T] [--spacing M] [--snapshot DIR] [--lockstep]\n"
    "       bench --strikes [--strike-filter WORD]... [--strike-cells] [--strike-render DIR]\n"
    "             [--strike-steps S[,S]...]\n"
    "\n"
    "Spawns the robot resting on the ground at the pose (x [m], y [m], yaw [rad]), lets it settle\n"
    "for 0.5 s, then drives it at v [m/s] and w [rad/s] for the duration [s], K times without its\n"
    "lidars and K times with them; casts its lidar rays on their own; renders it; and prints one\n"
    "JSON object on stdout:\n"
    "  rtf_physics, rtf_lidar  sim seconds per wall second while driving, without and with lidars\n"
    "  rays_per_s              the lidars' rays cast from the settled pose on one thread, alone\n"
    "  render_ms, png_ms       a chase view of the settled robot at WxH; writing it as a PNG file\n"
    "  startup_s               from the process start to the end of the first step, xacro and\n"
    "                          loading included; startup_cpu_s: the CPU time this process used\n"
    "  peak_rss_mb             peak resident memory\n"
    "  world_load_s            reading the world file, as the simulator node does (libsdformat in a\n"
    "                          child process); world_first_step_s: and then building a simulation of\n"
    "                          it and stepping it once; world_rss_mb: resident memory then\n"
    "  rss_before_spawn_mb     resident memory of a simulation of the world before the robot is first\n"
    "                          spawned; rss_after_delete_mb: after K spawns, 0.5 s runs and deletions\n"
    "                          (malloc_trim, as the node does); rss_delete_growth_pct: the difference\n"
    "  pose_error_m            where the drive axle ends, against the unicycle that follows the\n"
    "                          command exactly from the settled axle; pose_error_steady_m: that\n"
    "                          unicycle started after the first second of driving\n"
    "  rtf_camera              with --camera: with its lidars and a camera that renders at HZ;\n"
    "                          camera_ms_per_frame: the wall time each frame adds to the lidar run\n"
    "  rtf_camera_idle         without lidars, with a camera nobody wants (it renders nothing);\n"
    "                          camera_idle_cost_pct: the CPU time it adds to the physics-only\n"
    "                          run before it (the median of those pairs)\n"
    "  rtf_web_viewer          with --web-viewer: with its lidars and one page open on the live\n"
    "                          viewer (a client on its own thread that takes in every frame, as\n"
    "                          a browser does); web_viewer_cost_pct: the wall time it adds to the\n"
    "                          lidar run before it (the median of those pairs); web_viewer_cpu_cost_pct:\n"
    "                          the CPU time it adds to the simulation's thread\n"
    "with the inputs, every run's figures (medians are reported) and the load warnings.\n"
    "\n"
    "--wheel-model sets <wheelModel> in the robot's drive plugin. --lidar replaces the scan of the\n"
    "robot's ray sensors: SAMPLES beams over their horizontal field (the full circle when they have\n"
    "none) and, with CHANNELS > 1, that many channels from -15 to +15 degrees, published as a\n"
    "velodyne plugin would. --lidar-rate sets their update rate [Hz]. --obstacles adds N static\n"
    "0.1 x 0.1 x 1 m posts at random (seeded) places at least 1.5 m from the commanded path.\n"
    "--boxes N drives in a world of N x N static boxes of 0.3 x 0.3 x 0.5 m, 1 m apart, the grid's\n"
    "nearest row 2.5 m to the right of the start (instead of --world). --delete-cycles sets K.\n"
    "--lockstep casts the lidars' rays within the step they measure (gzserver's --lockstep); without it,\n"
    "they are cast behind the next steps' physics on a thread of their own, as the simulator node does.\n"
    "--limit sets one of the simulator's limits (its ~limits/NAME), e.g. max_links=2000.\n"
    "--camera adds a 60 degree camera of WxH pixels at HZ on the robot's root link, 0.3 m ahead and\n"
    "1 m up, looking ahead (libgazebo_ros_camera.so); with --depth, a depth camera with its depth\n"
    "image and organized cloud (libgazebo_ros_openni_kinect.so).\n"
    "--robots runs fleets instead (issue 32): for each N, N copies of the robot (the wheelchair's xacro\n"
    "without --robot) named robot1 to robotN, each in its own namespace, on a square grid 1.5 m apart\n"
    "centred on --pose's x, y, all facing its yaw; they settle for 0.5 s, then every one drives --cmd\n"
    "(default 0.3,0.3), re-sent at 10 Hz of sim time, its lidars scanning at their own rate. It prints\n"
    "the inputs and, per N (median of K runs, in increasing N):\n"
    "  rtf                          sim seconds per wall second while driving\n"
    "  wall_ms_per_sim_s_per_robot  wall time per sim second per robot; cpu_ms_per_sim_s_per_robot:\n"
    "                               the same in the simulation thread's CPU time;\n"
    "                               process_cpu_ms_per_sim_s_per_robot: in every thread's CPU time\n"
    "                               (--threads T share each step's per-robot work; default: the\n"
    "                               cores it may run on, at most 4)\n"
    "  shared_solves_pct            the share of the drive's physics substeps whose islands (bodies\n"
    "                               in contact) the pool's threads solved side by side\n"
    "  robot_rtf                    N x rtf\n"
    "  spawn_s                      parsing the URDF and spawning, for every robot (as the node's\n"
    "                               spawn service does); xacro runs once\n"
    "  peak_rss_mb, rss_mb          the process's peak so far; resident at the end of the drive\n"
    "  lidar_scans_per_robot_per_s  the scans each robot published while driving, per sim second\n"
    "  pose_error_max_m             the farthest any robot's drive axle ends from its unicycle\n"
    "  robot_rise_max_m, robot_sink_max_m, robot_tilt_max_deg  the most any robot's root link rose,\n"
    "                               sank and leaned, from the spawn to the end of the drive (every step\n"
    "                               sampled)\n"
    "  loose_bodies                 the world's non-static models (walled_boxes.world's boxes), and of\n"
    "                               them: loose_pushed, moved more than 1 cm; loose_rise_max_m and\n"
    "                               loose_sink_max_m, the most a centre rose above or sank below its\n"
    "                               start; loose_escaped, those whose centre was once outside the walls\n"
    "                               (the x-y bounds of the static bodies), inside a static body or below\n"
    "                               the ground: a bug; spawn_clearance_m, the nearest a robot started to\n"
    "                               a loose body's centre; loose_asleep_at_end, those Bullet had put\n"
    "                               to sleep at the end (Gazebo's auto-disable), in the run with fewest\n"
    "                               of them\n"
    "--spacing sets the grid's spacing [m] (default 1.5). The walled 20 x 20 m world of 200 boxes,\n"
    "issue 32's: --robots 20 --world walled_boxes.world --spacing 4 (its boxes leave those places free).\n"
    "--snapshot writes DIR/fleet_<N>_<settled|end>_<top|corner>.png (DIR made if missing): the first run\n"
    "of each fleet after settling and at the end of the drive, from above and from a corner, at --render's\n"
    "size.\n"
    "--strikes runs the strike matrix instead (issue 28): every shipped robot and the contact tests'\n"
    "look-alikes driven into a wall, a door frame's edge and a 2 cm panel at 0.1 to 2 m/s, head-on, at\n"
    "30 and 60 degrees, on both wheel models, at 1 and 10 ms steps (--strike-steps S[,S]...: at those\n"
    "world step sizes [s] instead), and coasting in with the motors off;\n"
    "each cell is judged against bounds from the robot's mass, inertia and geometry. It prints the cells\n"
    "run and passed, the largest tilt, rise and energy gain, the RTF at each step and the failed cells\n"
    "(--strike-cells: every cell). --strike-filter runs the cells whose name (robot model 1ms 0.5m/s\n"
    "30deg wall [coast]) holds every WORD. --strike-render writes a side and a chase view of each cell,\n"
    "0.3 s after the first contact and at the end, and its trail (the root link every 50 ms, CSV),\n"
    "into DIR.\n"
    "A relative --world is looked up in bullet_sim/worlds, then bullet_sim_bringup/worlds, then\n"
    "the working directory.\n"
    "Defaults: --world empty.world --pose 0,0,0 --step 0.001 --duration 10 --cmd 0.5,0.3 --delete-cycles 3\n"
    "          --render 640x480 --repeat 3; the robot's own wheel model and lidars;\n"
    "          --lidar-rate 10 with --lidar\n";

constexpr double kSpinUpTime = 1.0;       ///< [s] of driving that pose_error_steady_m leaves out
constexpr double kRayTimingSlice = 0.25;  ///< [s] of wall time per ray-casting measurement
constexpr int kMinRenders = 5;            ///< timed renders and PNG writes, at least
constexpr double kDefaultLidarRate = 10;  ///< [Hz] for --lidar
constexpr double kChannelSpread = 15 * M_PI / 180;  ///< [rad] of a --lidar with channels, each side of level
constexpr double kPostSide = 0.1;                   ///< [m] of an --obstacles post's square base
constexpr double kPostHeight = 1.0;                 ///< [m]: lidars up to this height see the posts
constexpr double kPostClearance = 1.5;              ///< [m] kept free around the commanded path
constexpr uint64_t kPostSeed = 1;
constexpr double kBoxClearance = 2.5;  ///< [m] from the start to --boxes' nearest row, on the right
constexpr double kFirstFrameWait = 5;  ///< [wall s] --web-viewer's page gets for its first frame
constexpr int kMaxFleet = 1000;        ///< robots in one --robots fleet, at most
constexpr char kFleetRobot[] = "urdf/smartwheelchair_model.urdf.xacro";  ///< of smartwheelchair_model

struct Options {
  std::string robot;
  std::string world;
  SpawnPose pose;
  std::optional<std::string> wheel_model;  ///< nullopt: the robot's own
  double step = 0.001;                     ///< [s]
  double duration = 10;                    ///< [s]
  double v = 0.5;                          ///< [m/s]
  double w = 0.3;                          ///< [rad/s]
  int lidar_samples = 0;                   ///< 0: the robot's own lidars
  int lidar_channels = 1;
  std::optional<double> lidar_rate;  ///< [Hz]
  int render_width = 640, render_height = 480;
  int obstacles = 0;
  int boxes = 0;  ///< a world of boxes x boxes boxes instead of `world`
  int delete_cycles = 3;
  Limits limits;
  int repeat = 3;
  struct Camera {
    int width = 640, height = 480;
    double rate = 30;  ///< [Hz]
    bool depth = false;
  };
  std::optional<Camera> camera;
  bool web_viewer = false;
  bool lockstep = false;    ///< the lidars cast within their step, not behind physics
  std::vector<int> robots;  ///< --robots: the fleets' sizes
  int threads = 0;          ///< --robots: the simulation's pool; 0 = its default
  double spacing = 1.5;     ///< [m] --robots: between neighbours on the grid
  std::string snapshot_dir;  ///< --robots: where the fleets' pictures go; "" = none
  bool cmd_given = false;
  bool strikes = false;
  StrikeMatrixOptions strike_options;
  bool help = false;
};

/// A whole number in [low, high] that is the whole of `text`.
int parseCount(const std::string& text, const std::string& option, int low, int high) {
  const double value = parseNumber(text, option);
  if (value != std::floor(value) || value < low || value > high) {
    throw UsageError(option + " [" + text + "]: give a whole number from " + std::to_string(low) + " to " +
                     std::to_string(high));
  }
  return static_cast<int>(value);
}

/// Two numbers written "a<separator>b".
std::pair<std::string, std::string> pairOf(const std::string& text, char separator, const std::string& option,
                                           const std::string& form) {
  const auto parts = split(text, separator);
  if (parts.size() != 2) throw UsageError(option + " [" + text + "]: write " + form);
  return {parts[0], parts[1]};
}

/// A number in (low, high] [unit] that is the whole of `text`.
double parseBounded(const std::string& text, const std::string& option, double low, double high,
                    const std::string& unit) {
  const double number = parseNumber(text, option);
  if (number <= low || number > high) {
    std::ostringstream message;
    message << option << " [" << text << "]: give more than " << low << " and at most " << high << " "
            << unit;
    throw UsageError(message.str());
  }
  return number;
}

void parseLidar(const std::string& value, Options& options) {
  const bool channels = value.find('x') != std::string::npos;
  const auto [samples, count] =
      channels ? pairOf(value, 'x', "--lidar", "SAMPLES or SAMPLESxCHANNELS, e.g. 360 or 1800x16")
               : std::pair<std::string, std::string>{value, "1"};
  options.lidar_samples = parseCount(samples, "--lidar", 1, 100000);
  options.lidar_channels = parseCount(count, "--lidar", 1, 1024);
}

Options::Camera parseCamera(const std::string& value) {
  const auto [size, rate] = pairOf(value, '@', "--camera", "WxH@HZ, e.g. 640x480@30");
  Options::Camera camera;
  std::tie(camera.width, camera.height) = parseSize(size, "--camera", 16384);
  camera.rate = parseBounded(rate, "--camera", 0, 1000, "Hz");
  return camera;
}

/// --robots' list of fleet sizes, each from 1 to kMaxFleet.
std::vector<int> parseRobotCounts(const std::string& value) {
  std::vector<int> counts;
  for (const std::string& count : split(value, ','))
    counts.push_back(parseCount(count, "--robots", 1, kMaxFleet));
  return counts;
}

/// --strike-steps' list of world step sizes [s], each above 0 and at most 0.1 s, as --step's.
std::vector<double> parseStrikeSteps(const std::string& value) {
  std::vector<double> steps;
  for (const std::string& step : split(value, ','))
    steps.push_back(parseBounded(step, "--strike-steps", 0, 0.1, "s"));
  return steps;
}

/// --robots drives fleets in a plain world: the options of the single robot's extras are refused.
void checkFleetOptions(const Options& options) {
  if (options.camera || options.web_viewer || options.obstacles > 0 || options.boxes > 0)
    throw UsageError("--robots: leave out --camera, --web-viewer, --obstacles and --boxes");
}

Options parseArguments(int argc, char** argv) {
  Options options;
  using Value = const std::string&;
  parseCommandLine(
      argc, argv,
      {{"--robot", [&](Value value) { options.robot = value; }},
       {"--world", [&](Value value) { options.world = value; }},
       {"--pose",
        [&](Value value) {
          parsePlanarPose(value, "--pose", &options.pose.x, &options.pose.y, &options.pose.yaw);
        }},
       {"--wheel-model",
        [&](Value value) {
          if (value != "contact" && value != "raycast")
            throw UsageError("--wheel-model [" + value + "]: choose contact or raycast");
          options.wheel_model = value;
        }},
       {"--step", [&](Value value) { options.step = parseBounded(value, "--step", 0, 0.1, "s"); }},
       {"--duration",
        [&](Value value) { options.duration = parseBounded(value, "--duration", 0, 3600, "s"); }},
       {"--cmd",
        [&](Value value) {
          const auto [v, w] = pairOf(value, ',', "--cmd", "v,w in m/s, rad/s, e.g. 0.5,0.3");
          options.v = parseNumber(v, "--cmd");
          options.w = parseNumber(w, "--cmd");
          options.cmd_given = true;
        }},
       {"--lidar", [&](Value value) { parseLidar(value, options); }},
       {"--lidar-rate",
        [&](Value value) { options.lidar_rate = parseBounded(value, "--lidar-rate", 0, 10000, "Hz"); }},
       {"--render",
        [&](Value value) {
          std::tie(options.render_width, options.render_height) = parseSize(value, "--render", 4096);
        }},
       {"--obstacles", [&](Value value) { options.obstacles = parseCount(value, "--obstacles", 0, 100000); }},
       {"--boxes", [&](Value value) { options.boxes = parseCount(value, "--boxes", 1, 1000); }},
       {"--delete-cycles",
        [&](Value value) { options.delete_cycles = parseCount(value, "--delete-cycles", 0, 1000); }},
       limitOption(options.limits),
       {"--repeat", [&](Value value) { options.repeat = parseCount(value, "--repeat", 1, 1000); }},
       {"--threads", [&](Value value) { options.threads = parseCount(value, "--threads", 1, 64); }},
       {"--spacing", [&](Value value) { options.spacing = parseBounded(value, "--spacing", 0, 100, "m"); }},
       {"--snapshot", [&](Value value) { options.snapshot_dir = value; }},
       {"--camera", [&](Value value) { options.camera = parseCamera(value); }},
       // Taken after --camera, whatever their order on the command line.
       {"--depth",
        [&](Value) {
          if (!options.camera) throw UsageError("--depth needs --camera WxH@HZ");
          options.camera->depth = true;
        },
        false, /*flag=*/true},
       {"--web-viewer", [&](Value) { options.web_viewer = true; }, false, /*flag=*/true},
       {"--lockstep", [&](Value) { options.lockstep = true; }, false, /*flag=*/true},
       {"--robots", [&](Value value) { options.robots = parseRobotCounts(value); }},
       {"--strikes", [&](Value) { options.strikes = true; }, false, /*flag=*/true},
       {"--strike-filter", [&](Value value) { options.strike_options.filter.push_back(value); }, true},
       {"--strike-cells", [&](Value) { options.strike_options.list_cells = true; }, false, /*flag=*/true},
       {"--strike-render", [&](Value value) { options.strike_options.render_dir = value; }},
       {"--strike-steps", [&](Value value) { options.strike_options.steps = parseStrikeSteps(value); }}},
      &options.help);
  if (options.help || options.strikes) return options;
  if (!options.robots.empty()) {
    checkFleetOptions(options);
    return options;
  }
  if (options.robot.empty()) throw UsageError("--robot FILE.urdf or FILE.xacro is missing");
  if (options.boxes > 0 && !options.world.empty())
    throw UsageError("--boxes makes a world: leave --world out");
  return options;
}

bool endsWith(const std::string& text, const std::string& end) {
  return text.size() >= end.size() && text.compare(text.size() - end.size(), end.size(), end) == 0;
}

bool isRaySensor(const std::string& type) { return type == "ray" || type == "gpu_ray"; }

/// The first child of `parent` named `name`, created when there is none.
tinyxml2::XMLElement* child(tinyxml2::XMLElement* parent, const char* name) {
  tinyxml2::XMLElement* found = parent->FirstChildElement(name);
  return found ? found : parent->InsertNewChildElement(name);
}

void setChildText(tinyxml2::XMLElement* parent, const char* name, double value) {
  std::ostringstream text;
  text.precision(17);
  text << value;
  child(parent, name)->SetText(text.str().c_str());
}

/// Replaces a ray sensor's <scan> with `samples` beams over its horizontal field (the full circle, no beam
/// twice, when it has none) and, for several channels, that many from -15 to +15 degrees. Several channels
/// are a 3D lidar, so a 2D laser plugin becomes the velodyne one, which publishes every channel.
void overrideScan(tinyxml2::XMLElement* sensor, int samples, int channels) {
  tinyxml2::XMLElement* ray = child(sensor, "ray");
  double min_angle = -M_PI, max_angle = M_PI - 2 * M_PI / samples;
  if (auto* old_scan = ray->FirstChildElement("scan")) {
    const auto* horizontal = old_scan->FirstChildElement("horizontal");
    const auto* min = horizontal ? horizontal->FirstChildElement("min_angle") : nullptr;
    const auto* max = horizontal ? horizontal->FirstChildElement("max_angle") : nullptr;
    if (min && max && min->DoubleText() < max->DoubleText()) {
      min_angle = min->DoubleText();
      max_angle = max->DoubleText();
    }
    ray->DeleteChild(old_scan);
  }
  tinyxml2::XMLElement* scan = ray->InsertNewChildElement("scan");
  tinyxml2::XMLElement* horizontal = scan->InsertNewChildElement("horizontal");
  setChildText(horizontal, "samples", samples);
  setChildText(horizontal, "resolution", 1);
  setChildText(horizontal, "min_angle", min_angle);
  setChildText(horizontal, "max_angle", max_angle);
  if (channels == 1) return;
  tinyxml2::XMLElement* vertical = scan->InsertNewChildElement("vertical");
  setChildText(vertical, "samples", channels);
  setChildText(vertical, "resolution", 1);
  setChildText(vertical, "min_angle", -kChannelSpread);
  setChildText(vertical, "max_angle", kChannelSpread);
  if (auto* plugin = sensor->FirstChildElement("plugin")) {
    const std::string filename = plugin->Attribute("filename") ? plugin->Attribute("filename") : "";
    if (filename == "libgazebo_ros_laser.so")
      plugin->SetAttribute("filename", "libgazebo_ros_velodyne_laser.so");
    if (filename == "libgazebo_ros_gpu_laser.so")
      plugin->SetAttribute("filename", "libgazebo_ros_velodyne_gpu_laser.so");
  }
}

/// The URDF with the wheel model and lidar options applied to its <gazebo> blocks. Text that is not XML is
/// returned as it is, for parseModel to report.
std::string applyRobotOptions(const std::string& description, const Options& options) {
  const bool lidar = options.lidar_samples > 0 || options.lidar_rate;
  int drives = 0;
  const std::string urdf =
      options.wheel_model ? withWheelModel(description, *options.wheel_model, &drives) : description;
  if (options.wheel_model && drives == 0) {
    throw Failure(
        "--wheel-model: " + options.robot +
        " has no libgazebo_ros_diff_drive.so, libgazebo_ros_skid_steer_drive.so or "
        "libgazebo_ros_ackermann_drive.so plugin to set <wheelModel> in; bench drives robots through one");
  }
  if (!lidar) return urdf;
  tinyxml2::XMLDocument document;
  if (document.Parse(urdf.c_str(), urdf.size()) != tinyxml2::XML_SUCCESS || !document.RootElement())
    return urdf;

  int sensors = 0;
  for (auto* gazebo = document.RootElement()->FirstChildElement("gazebo"); gazebo;
       gazebo = gazebo->NextSiblingElement("gazebo")) {
    for (auto* sensor = gazebo->FirstChildElement("sensor"); sensor;
         sensor = sensor->NextSiblingElement("sensor")) {
      const char* type = sensor->Attribute("type");
      if (!lidar || !type || !isRaySensor(type)) continue;
      if (options.lidar_samples > 0) overrideScan(sensor, options.lidar_samples, options.lidar_channels);
      setChildText(sensor, "update_rate", options.lidar_rate.value_or(kDefaultLidarRate));
      ++sensors;
    }
  }
  if (sensors == 0) {
    throw Failure(
        "--lidar / --lidar-rate: " + options.robot +
        " declares no <sensor type=\"ray\"> in a <gazebo> block; add one, or leave these options out");
  }
  tinyxml2::XMLPrinter printer;
  document.Print(&printer);
  return printer.CStr();
}

/// Static posts scattered over the world's floor, at least kPostClearance from the path the command would
/// take the robot's base frame along, so that they are seen but never hit.
void addObstacles(WorldSpec& world, const Options& options) {
  if (options.obstacles == 0) return;
  Eigen::AlignedBox3d bounds = worldBounds(world);
  if (bounds.isEmpty()) bounds = Eigen::AlignedBox3d(Eigen::Vector3d(-5, -5, 0), Eigen::Vector3d(5, 5, 0));
  std::vector<Eigen::Vector2d> path;
  double x = options.pose.x, y = options.pose.y, yaw = options.pose.yaw;
  const double dt = 0.05;  // [s] samples the path every 2.5 cm at 0.5 m/s
  for (double t = 0; t <= options.duration; t += dt) {
    path.emplace_back(x, y);
    x += options.v * std::cos(yaw) * dt;
    y += options.v * std::sin(yaw) * dt;
    yaw += options.w * dt;
  }
  std::mt19937_64 generator(kPostSeed);
  const auto uniform = [&](double low, double high) {  // portable, unlike std::uniform_real_distribution
    return low + (high - low) * static_cast<double>(generator() >> 11) * 0x1.0p-53;
  };
  Shape post;
  post.type = Shape::Type::kBox;
  post.box_size = Eigen::Vector3d(kPostSide, kPostSide, kPostHeight);
  const long max_tries = 1000L * options.obstacles;
  int placed = 0;
  for (long tries = 0; placed < options.obstacles && tries < max_tries; ++tries) {
    const Eigen::Vector2d at(uniform(bounds.min().x(), bounds.max().x()),
                             uniform(bounds.min().y(), bounds.max().y()));
    if (std::any_of(path.begin(), path.end(),
                    [&](const Eigen::Vector2d& p) { return (p - at).norm() < kPostClearance; })) {
      continue;
    }
    WorldModelSpec model;
    model.name = "bench_post_" + std::to_string(placed++);
    model.pose = Eigen::Translation3d(at.x(), at.y(), kPostHeight / 2) * Eigen::Isometry3d::Identity();
    model.collisions.push_back({Eigen::Isometry3d::Identity(), post});
    model.visuals.push_back({Eigen::Isometry3d::Identity(), post, Eigen::Vector4d(0.5, 0.5, 0.5, 1), ""});
    world.models.push_back(std::move(model));
  }
  if (placed < options.obstacles) {
    throw Failure(
        "--obstacles " + std::to_string(options.obstacles) + ": only " + std::to_string(placed) +
        " fit in the world at least 1.5 m from the robot's path; ask for fewer, or a shorter --duration");
  }
}

/// The model without its ray sensors, for timing the physics alone.
ModelSpec withoutLidars(ModelSpec model) {
  auto& plugins = model.plugins;
  plugins.erase(std::remove_if(plugins.begin(), plugins.end(),
                               [](const PluginDeclaration& plugin) {
                                 return plugin.sensor && isRaySensor(plugin.sensor->type);
                               }),
                plugins.end());
  return model;
}

TagNode tagNode(std::string name, std::string text, std::vector<TagNode> children = {}) {
  TagNode node;
  node.name = std::move(name);
  node.text = std::move(text);
  node.children = std::move(children);
  return node;
}

/// `model` with --camera's camera on its root link, 0.3 m ahead and 1 m up, looking along the link's x: its
/// <sensor> and <plugin> read by the registry, as a URDF's would be.
ModelSpec withCamera(ModelSpec model, const Options::Camera& camera) {
  SensorDeclaration sensor;
  sensor.name = "bench_camera";
  sensor.type = camera.depth ? "depth" : "camera";
  sensor.link = model.root;
  sensor.pose = Eigen::Translation3d(0.3, 0, 1.0);
  sensor.update_rate = camera.rate;
  const TagNode image = tagNode("image", "", {tagNode("width", std::to_string(camera.width)),
                                              tagNode("height", std::to_string(camera.height))});
  const TagNode clip = tagNode("clip", "", {tagNode("near", "0.05"), tagNode("far", "50")});
  const TagNode sensor_node = tagNode("sensor", "", {tagNode("camera", "", {image, clip})});
  const TagNode plugin_node = tagNode("plugin", "", {tagNode("cameraName", "bench_camera")});
  PluginDeclaration declaration;
  declaration.name = "bench_camera_controller";
  declaration.filename = camera.depth ? "libgazebo_ros_openni_kinect.so" : "libgazebo_ros_camera.so";
  declaration.sensor = sensor;
  Diagnostics diagnostics("bench's camera");
  PluginTags tags(&plugin_node, declaration.where(), diagnostics);
  const DeclarationSource source{declaration, tags, &sensor_node, model, diagnostics, Limits()};
  declaration.config = PluginRegistry::builtin().parse(source);
  diagnostics.throwIfErrors();
  model.plugins.push_back(declaration);
  return model;
}

/// The renderer every camera run of this process draws with.
SceneRenderer& benchRenderer() {
  static OffscreenRenderer renderer;
  return renderer;
}

/// Whether anyone wants the outputs a plugin computes only on demand (a camera's): as if subscribed or not.
void setDemand(const Robot& robot, bool wanted) {
  for (const auto& plugin : robot.plugins()) {
    for (const OutputPort& port : plugin->ports().outputs) {
      if (port.demand) port.demand->wanted = wanted;
    }
  }
}

/// The frames the robot's cameras rendered: per camera, the most of any of its image outputs.
uint64_t cameraFrames(const Robot& robot) {
  std::map<const Plugin*, uint64_t> frames;
  for (const RobotOutput<CameraImage>& output : robot.outputs<CameraImage>())
    frames[output.plugin] = std::max(frames[output.plugin], output.stream->count());
  uint64_t total = 0;
  for (const auto& [camera, count] : frames) total += count;
  return total;
}

/// One spawn, settle and drive.
struct DriveRun {
  double startup_s = NAN;      ///< process age at the end of the first step
  double startup_cpu_s = NAN;  ///< CPU time used by then
  double wall_s = 0;           ///< of the driving, the settling left out
  double cpu_s = 0;            ///< the driving's CPU time on the simulation's thread
  uint64_t camera_frames = 0;  ///< rendered while driving
  uint64_t viewer_frames = 0;  ///< --web-viewer: the frames its page took in
  std::string wheel_model;
  Planar settled, after_spin_up, end;  ///< of the drive axle
};

/// Cameras render only when `cameras_wanted`, as when someone subscribes to them. `after_step` is called
/// after every step of the drive.
DriveRun driveOnce(const WorldSpec& world, const ModelSpec& model, const Options& options,
                   std::vector<std::string>& warnings, bool cameras_wanted = true,
                   const std::function<void(const Simulation&)>& after_step = {}) {
  DriveRun run;
  SimulationOptions simulation_options;
  simulation_options.physics.step_size = options.step;
  simulation_options.images = imagesFrom(benchRenderer);
  simulation_options.lockstep = options.lockstep;
  Simulation simulation(world, simulation_options);
  Robot& robot = simulation.spawn(model.name, model, options.pose, &warnings);
  const Drive drive = driveOf(robot, model.source);
  setDemand(robot, cameras_wanted);
  run.wheel_model = robot.wheelModel();

  simulation.step();
  run.startup_s = processAge().value_or(NAN);
  run.startup_cpu_s = cpuSeconds();
  for (long i = 1; i < std::lround(kSettleTime / options.step); ++i) simulation.step();
  run.settled = axlePose(robot, drive.joints);

  const long steps = std::lround(options.duration / options.step);
  const long resend = std::max(1L, std::lround(kCommandPeriod / options.step));
  const long spin_up = std::lround(kSpinUpTime / options.step);
  const Clock::time_point start = Clock::now();
  const double cpu_start = threadCpuSeconds();
  for (long i = 0; i < steps; ++i) {
    if (i % resend == 0) (*drive.command)(Twist{{options.v, 0, 0}, {0, 0, options.w}}, simulation.time());
    simulation.step();
    if (after_step) after_step(simulation);
    if (i + 1 == spin_up) run.after_spin_up = axlePose(robot, drive.joints);
  }
  simulation.finishCasts();
  run.wall_s = secondsSince(start);
  run.cpu_s = threadCpuSeconds() - cpu_start;
  run.end = axlePose(robot, drive.joints);
  run.camera_frames = cameraFrames(robot);
  return run;
}

/// A drive with one page open on the live viewer, which publishes a frame after every step that one is due.
DriveRun driveWatched(const WorldSpec& world, const ModelSpec& model, const Options& options,
                      std::vector<std::string>& warnings) {
  WebViewerOptions viewer_options;
  viewer_options.page_dir =
      PackageResolver::fromEnvironment().packageDirectory("bullet_sim").value_or(".") + "/web";
  WebViewer viewer(viewer_options, [](const ViewerCommand&) {});
  const ViewerProbe page(viewer.port());
  DriveRun run = driveOnce(world, model, options, warnings, true,
                           [&viewer](const Simulation& simulation) { viewer.update(simulation, false); });
  page.waitForFrames(1, kFirstFrameWait);  // a run shorter than a frame's way to the page still shows one
  run.viewer_frames = page.frames();
  return run;
}

/// Rays per wall second of a RayCaster holding the world and the robot's parts where they are, casting every
/// lidar's rays in turn on this thread, each lidar skipping the part it sits on: `repeat` measurements.
std::vector<double> measureRays(const WorldSpec& world, const Robot& robot,
                                const std::vector<RayPattern>& lidars, int repeat) {
  RayCaster caster;
  for (const auto& model : world.models) {
    if (!model.collisions.empty()) caster.addBody(model.collisions, model.pose, /*is_static=*/true);
  }
  const RobotBody& body = robot.body();
  std::vector<BodyId> part_bodies;
  for (size_t k = 0; k < body.parts().size(); ++k) {
    const auto& collisions = body.parts()[k].collisions;
    part_bodies.push_back(collisions.empty() ? kNoBody : caster.addBody(collisions, body.partPose(k), false));
  }
  caster.commit();

  std::vector<double> rays_per_s;
  std::vector<double> ranges;
  for (int run = 0; run < repeat; ++run) {
    double rays = 0;
    const Clock::time_point start = Clock::now();
    do {
      for (const RayPattern& lidar : lidars) {
        const BodyId own = part_bodies[body.partOf(lidar.link)];
        caster.cast(lidar.sensor.translation(), lidar.directions, lidar.range_max, own, ranges);
        rays += static_cast<double>(lidar.directions.size());
      }
    } while (secondsSince(start) < kRayTimingSlice);
    rays_per_s.push_back(rays / secondsSince(start));
  }
  return rays_per_s;
}

/// Render and PNG timings of the chase view [ms].
struct RenderTimes {
  double scene_ms = NAN;         ///< building the scene from the simulation
  double first_render_ms = NAN;  ///< the first render, which uploads the meshes
  std::vector<double> render_ms, png_ms;
  size_t png_bytes = 0;
};

RenderTimes measureRender(const Simulation& simulation, const std::string& robot, const Options& options) {
  RenderTimes times;
  Clock::time_point start = Clock::now();
  const Scene scene = simulationScene(simulation, View::kChase, robot);
  times.scene_ms = 1e3 * secondsSince(start);
  OffscreenRenderer renderer;
  start = Clock::now();
  Image image = renderer.render(scene, options.render_width, options.render_height);
  times.first_render_ms = 1e3 * secondsSince(start);
  const int count = std::max(kMinRenders, options.repeat);
  for (int i = 0; i < count; ++i) {
    start = Clock::now();
    image = renderer.render(scene, options.render_width, options.render_height);
    times.render_ms.push_back(1e3 * secondsSince(start));
  }

  const TemporaryFile png_file("", ".png");
  for (int i = 0; i < count; ++i) {
    std::string error;
    start = Clock::now();
    const bool written = writePng(png_file.path(), image, &error);
    times.png_ms.push_back(1e3 * secondsSince(start));
    if (!written) throw Failure(error);
  }
  std::ifstream png(png_file.path(), std::ios::binary | std::ios::ate);
  times.png_bytes = static_cast<size_t>(png.tellg());
  return times;
}

using Json = nlohmann::ordered_json;  // fields in the order they are set

/// A figure: null when it is not finite.
Json figure(double value) { return std::isfinite(value) ? Json(value) : Json(nullptr); }

Json figureList(const std::vector<double>& values) {
  Json list = Json::array();
  for (double value : values) list.push_back(figure(value));
  return list;
}

double distance(const Planar& a, const Planar& b) { return std::hypot(a.x - b.x, a.y - b.y); }

/// Everything bench measures, for the report.
struct Figures {
  std::string world_file;
  std::vector<DriveRun> lidar_runs, physics_runs, camera_runs, idle_camera_runs, viewer_runs;
  std::vector<RayPattern> lidars;
  std::vector<double> rays_per_s;
  double peak_rss_before_render_mb = 0;
  WorldLoad world_load;
  DeleteCycle delete_cycle;
  RenderTimes render;
  std::vector<std::string> warnings;  ///< each once
};

/// The timed drives, with and without lidars, of the robot the options describe.
Figures drive(const Options& options, const ModelSpec& model, const WorldSpec& world,
              std::vector<std::string>& warnings) {
  Figures figures;
  const ModelSpec model_without_lidars = withoutLidars(model);
  const bool has_lidars = model_without_lidars.plugins.size() != model.plugins.size();
  // Runs with and without lidars take turns, so that a slow spell of a shared machine hits both alike; a
  // camera run comes right after the run it is compared with (the lidar run, or the physics-only one when
  // the robot has no lidar); the idle camera's run comes soon after the physics-only one. The first spawn
  // is of the whole robot: startup_s is to its first step.
  const auto camera_run = [&]() {
    figures.camera_runs.push_back(driveOnce(world, withCamera(model, *options.camera), options, warnings));
  };
  const auto viewer_run = [&]() {
    figures.viewer_runs.push_back(driveWatched(world, model, options, warnings));
  };
  for (int i = 0; i < options.repeat; ++i) {
    if (has_lidars) figures.lidar_runs.push_back(driveOnce(world, model, options, warnings));
    if (has_lidars && options.camera) camera_run();
    if (has_lidars && options.web_viewer) viewer_run();
    figures.physics_runs.push_back(driveOnce(world, model_without_lidars, options, warnings));
    if (!has_lidars && options.web_viewer) viewer_run();
    if (!options.camera) continue;
    if (!has_lidars) camera_run();
    figures.idle_camera_runs.push_back(
        driveOnce(world, withCamera(model_without_lidars, *options.camera), options, warnings, false));
  }
  return figures;
}

Figures measure(const Options& options) {
  const PackageResolver resolver = PackageResolver::fromEnvironment();
  std::vector<std::string> warnings;
  const std::string urdf =
      endsWith(options.robot, ".xacro") ? runXacro(options.robot, {}) : readUrdfFile(options.robot);
  const ModelSpec model =
      parseModel(applyRobotOptions(urdf, options), options.robot, resolver, &warnings, options.limits);
  std::optional<TemporaryFile> box_world;
  if (options.boxes > 0) box_world.emplace(boxWorld(options.boxes, kBoxClearance), ".world");
  const std::string world_file = box_world ? box_world->path() : findWorld(options.world, resolver);
  WorldSpec world;
  const WorldLoad world_load =
      measureWorldLoad(world_file, resolver, world, &warnings, WorldOptions{false, options.limits});
  addObstacles(world, options);
  Figures figures = drive(options, model, world, warnings);
  figures.world_file = world_file;
  figures.world_load = world_load;
  figures.delete_cycle = measureDeleteCycle(world, model, options.pose, options.delete_cycles);

  // Rays and pictures of the robot settled at its spawn pose, its lidars having scanned.
  SimulationOptions simulation_options;
  simulation_options.physics.step_size = options.step;
  Simulation settled(world, simulation_options);
  const Robot& robot = settled.spawn(model.name, model, options.pose);
  for (long i = 0; i < std::lround(kSettleTime / options.step); ++i) settled.step();
  for (const auto& [plugin, sensor] : robot.sensors<RaySensor>())
    figures.lidars.push_back(sensor->rayPattern(robot.body()));
  if (!figures.lidars.empty()) figures.rays_per_s = measureRays(world, robot, figures.lidars, options.repeat);
  figures.peak_rss_before_render_mb = peakRssMb();
  figures.render = measureRender(settled, robot.name(), options);
  for (const auto& warning : warnings) {
    if (std::find(figures.warnings.begin(), figures.warnings.end(), warning) == figures.warnings.end())
      figures.warnings.push_back(warning);
  }
  return figures;
}

std::vector<double> realTimeFactors(const Options& options, const std::vector<DriveRun>& runs) {
  std::vector<double> factors;
  for (const DriveRun& run : runs) factors.push_back(options.duration / run.wall_s);
  return factors;
}

/// --camera's figures: RTF while it renders and while nobody wants it, and what the idle camera costs.
void reportCamera(Json& json, const Options& options, const Figures& figures) {
  const Options::Camera& camera = *options.camera;
  json["camera"] = {
      {"size", {camera.width, camera.height}}, {"rate_hz", camera.rate}, {"depth", camera.depth}};
  const double rtf = median(realTimeFactors(options, figures.camera_runs));
  const double idle = median(realTimeFactors(options, figures.idle_camera_runs));
  json["rtf_camera"] = figure(rtf);
  json["rtf_camera_idle"] = figure(idle);
  // Medians of the differences within pairs of adjacent runs (see drive).
  const std::vector<DriveRun>& base = figures.lidar_runs.empty() ? figures.physics_runs : figures.lidar_runs;
  std::vector<double> frame_ms, idle_pct;
  for (size_t i = 0; i < figures.camera_runs.size(); ++i) {
    const DriveRun& run = figures.camera_runs[i];
    if (run.camera_frames > 0)
      frame_ms.push_back(1000 * (run.wall_s - base.at(i).wall_s) / static_cast<double>(run.camera_frames));
    // In CPU time: a run of physics alone is too short for its wall time to be steady on a shared machine.
    idle_pct.push_back(100 * (figures.idle_camera_runs[i].cpu_s / figures.physics_runs.at(i).cpu_s - 1));
  }
  json["camera_ms_per_frame"] = frame_ms.empty() ? Json(nullptr) : figure(median(frame_ms));
  json["camera_idle_cost_pct"] = figure(median(idle_pct));
  json["camera_frames_per_run"] = figures.camera_runs.front().camera_frames;
  json["camera_idle_frames_per_run"] = figures.idle_camera_runs.front().camera_frames;
  json["rtf_camera_runs"] = figureList(realTimeFactors(options, figures.camera_runs));
  json["rtf_camera_idle_runs"] = figureList(realTimeFactors(options, figures.idle_camera_runs));
}

/// --web-viewer's figures: RTF with a page open, and the wall time it adds to the run before it.
void reportViewer(Json& json, const Options& options, const Figures& figures) {
  const std::vector<DriveRun>& base = figures.lidar_runs.empty() ? figures.physics_runs : figures.lidar_runs;
  std::vector<double> cost_pct, cpu_cost_pct, frames;
  for (size_t i = 0; i < figures.viewer_runs.size(); ++i) {
    cost_pct.push_back(100 * (figures.viewer_runs[i].wall_s / base.at(i).wall_s - 1));
    cpu_cost_pct.push_back(100 * (figures.viewer_runs[i].cpu_s / base.at(i).cpu_s - 1));
    frames.push_back(static_cast<double>(figures.viewer_runs[i].viewer_frames));
  }
  json["rtf_web_viewer"] = figure(median(realTimeFactors(options, figures.viewer_runs)));
  json["web_viewer_cost_pct"] = figure(median(cost_pct));
  json["web_viewer_cpu_cost_pct"] = figure(median(cpu_cost_pct));
  json["web_viewer_frames_per_run"] = figure(median(frames));
  json["rtf_web_viewer_runs"] = figureList(realTimeFactors(options, figures.viewer_runs));
  json["web_viewer_cost_pct_runs"] = figureList(cost_pct);
}

/// The inputs, then the figures (medians of the runs), then every run's figures and the warnings.
Json report(const Options& options, const Figures& figures) {
  const bool has_lidars = !figures.lidar_runs.empty();
  const DriveRun& first = has_lidars ? figures.lidar_runs.front() : figures.physics_runs.front();
  // every run follows the same path: it is deterministic
  const DriveRun& drive = figures.physics_runs.front();
  const auto rtf = [&](const std::vector<DriveRun>& runs) { return realTimeFactors(options, runs); };
  size_t rays_per_scan = 0;
  for (const auto& lidar : figures.lidars) rays_per_scan += lidar.directions.size();
  const Planar ideal = unicycle(drive.settled, options.v, options.w, options.duration);
  const bool steady = options.duration > kSpinUpTime;
  const Planar steady_ideal =
      unicycle(drive.after_spin_up, options.v, options.w, options.duration - kSpinUpTime);
  const RenderTimes& render = figures.render;

  Json json;
  json["robot"] = options.robot;
  json["world"] = figures.world_file;
  json["pose"] = figureList({options.pose.x, options.pose.y, options.pose.yaw});
  json["wheel_model"] = first.wheel_model;
  json["wheel_model_requested"] = options.wheel_model ? Json(*options.wheel_model) : Json(nullptr);
  json["step_s"] = options.step;
  json["duration_s"] = options.duration;
  json["cmd"] = figureList({options.v, options.w});
  json["lidars"] = figures.lidars.size();
  json["lidar_rays_per_scan"] = rays_per_scan;
  json["lidar_rate_hz"] = figure(figures.lidars.empty() ? NAN : figures.lidars.front().update_rate);
  json["obstacles"] = options.obstacles;
  json["render_size"] = {options.render_width, options.render_height};
  json["repeat"] = options.repeat;
  json["lockstep"] = options.lockstep;
  json["rtf_physics"] = figure(median(rtf(figures.physics_runs)));
  json["rtf_lidar"] = figure(median(rtf(figures.lidar_runs)));
  json["rays_per_s"] = figure(median(figures.rays_per_s));
  if (options.camera) reportCamera(json, options, figures);
  if (options.web_viewer) reportViewer(json, options, figures);
  json["render_ms"] = figure(median(render.render_ms));
  json["png_ms"] = figure(median(render.png_ms));
  json["startup_s"] = first.startup_s;
  json["startup_cpu_s"] = first.startup_cpu_s;
  json["peak_rss_mb"] = peakRssMb();
  json["pose_error_m"] = distance(drive.end, ideal);
  json["pose_error_steady_m"] = figure(steady ? distance(drive.end, steady_ideal) : NAN);
  json["yaw_error_deg"] = std::remainder(drive.end.yaw - ideal.yaw, 2 * M_PI) * 180 / M_PI;
  json["rtf_physics_runs"] = figureList(rtf(figures.physics_runs));
  json["rtf_lidar_runs"] = figureList(rtf(figures.lidar_runs));
  json["rays_per_s_runs"] = figureList(figures.rays_per_s);
  json["render_ms_runs"] = figureList(render.render_ms);
  json["render_first_ms"] = figure(render.first_render_ms);
  json["scene_ms"] = figure(render.scene_ms);
  json["png_ms_runs"] = figureList(render.png_ms);
  json["png_bytes"] = render.png_bytes;
  json["peak_rss_before_render_mb"] = figures.peak_rss_before_render_mb;
  json["boxes"] = options.boxes * options.boxes;
  json["world_load_s"] = figures.world_load.load_s;
  json["world_first_step_s"] = figures.world_load.first_step_s;
  json["world_rss_mb"] = figures.world_load.rss_mb;
  const DeleteCycle& cycle = figures.delete_cycle;
  json["delete_cycles"] = options.delete_cycles;
  json["rss_before_spawn_mb"] = cycle.rss_before_mb;
  json["rss_after_delete_mb"] = cycle.rss_after_mb;
  json["rss_delete_growth_pct"] = figure(100 * (cycle.rss_after_mb / cycle.rss_before_mb - 1));
  json["warnings"] = figures.warnings;
  return json;
}

/// --snapshot's pictures of a fleet: from straight above (the top view frames the world's obstacles) and from
/// above the world's south-west corner, looking at its centre.
std::function<void(const Simulation&, int, const std::string&)> fleetPictures(const Options& options) {
  std::error_code error;  // made up front, as scenario --out does: a run must not end on a missing folder
  std::filesystem::create_directories(options.snapshot_dir, error);
  if (error) throw Failure("--snapshot: cannot make [" + options.snapshot_dir + "]: " + error.message());
  auto renderer = std::make_shared<std::unique_ptr<OffscreenRenderer>>();  // made for the first picture
  return [renderer, dir = options.snapshot_dir, width = options.render_width, height = options.render_height](
             const Simulation& simulation, int count, const std::string& moment) {
    if (!*renderer) *renderer = std::make_unique<OffscreenRenderer>();
    Scene scene = simulationScene(simulation, View::kTop);
    const std::string stem = dir + "/fleet_" + std::to_string(count) + "_" + moment;
    std::string error;
    if (!writePng(stem + "_top.png", (*renderer)->render(scene, width, height), &error))
      throw Failure("--snapshot: " + error);
    const Eigen::Vector2d centre = scene.camera.centre, half = scene.camera.half_extents;
    const Eigen::Vector3d target(centre.x(), centre.y(), 0);
    scene.outline_step = 0;  // the plan view's outlines would darken the far floor, seen at a glancing angle
    const Eigen::Vector3d corner(-half.x(), -1.6 * half.y(), 1.1 * half.norm());
    scene.camera = Camera::perspective(target + corner, target);
    if (!writePng(stem + "_corner.png", (*renderer)->render(scene, width, height), &error))
      throw Failure("--snapshot: " + error);
  };
}

/// bench --robots: the inputs, each fleet's figures and the warnings (each once).
Json fleetReport(Options options) {
  const PackageResolver resolver = PackageResolver::fromEnvironment();
  if (options.robot.empty()) {
    const auto package = resolver.packageDirectory("smartwheelchair_model");
    if (!package)
      throw Failure("--robots: smartwheelchair_model is not on ROS_PACKAGE_PATH; give --robot FILE");
    options.robot = *package + "/" + kFleetRobot;
  }
  FleetOptions fleet;
  const std::string urdf =
      endsWith(options.robot, ".xacro") ? runXacro(options.robot, {}) : readUrdfFile(options.robot);
  fleet.urdf = applyRobotOptions(urdf, options);
  fleet.source = options.robot;
  fleet.step = options.step;
  fleet.duration = options.duration;
  if (options.cmd_given) {
    fleet.v = options.v;
    fleet.w = options.w;
  }
  fleet.origin = options.pose;
  fleet.limits = options.limits;
  fleet.threads = options.threads;
  fleet.lockstep = options.lockstep;
  fleet.spacing = options.spacing;
  if (!options.snapshot_dir.empty()) fleet.snapshot = fleetPictures(options);
  std::vector<std::string> warnings;
  const std::string world_file = findWorld(options.world, resolver);
  const WorldSpec world = loadWorld(world_file, resolver, &warnings, WorldOptions{false, options.limits});

  Json json;
  json["robot"] = options.robot;
  json["world"] = world_file;
  json["wheel_model_requested"] = options.wheel_model ? Json(*options.wheel_model) : Json(nullptr);
  json["step_s"] = options.step;
  json["settle_s"] = kSettleTime;
  json["duration_s"] = options.duration;
  json["cmd"] = figureList({fleet.v, fleet.w});
  json["spacing_m"] = fleet.spacing;
  json["repeat"] = options.repeat;
  json["lockstep"] = options.lockstep;
  json["threads"] = options.threads > 0 ? options.threads : defaultPoolThreads();
  json["fleets"] = fleetFigures(world, options.robots, options.repeat, fleet, &warnings);
  std::vector<std::string> unique;
  for (const auto& warning : warnings) {
    if (std::find(unique.begin(), unique.end(), warning) == unique.end()) unique.push_back(warning);
  }
  json["warnings"] = unique;
  return json;
}

int run(const Options& options) {
  if (options.strikes) {
    std::cout << strikeMatrixReport(options.strike_options).dump(2) << "\n";
    return EXIT_SUCCESS;
  }
  if (!options.robots.empty()) {
    const Json json = fleetReport(options);
    for (const auto& warning : json["warnings"])
      std::cerr << "bench: warning: " << warning.get<std::string>() << "\n";
    std::cout << json.dump(2) << "\n";
    return EXIT_SUCCESS;
  }
  const Figures figures = measure(options);
  for (const auto& warning : figures.warnings) std::cerr << "bench: warning: " << warning << "\n";
  std::cout << report(options, figures).dump(2) << "\n";
  return EXIT_SUCCESS;
}

}  // namespace
}  // namespace bullet_sim

int main(int argc, char** argv) {
  return bullet_sim::toolMain("bench", bullet_sim::kUsage, argc, argv, bullet_sim::parseArguments,
                              bullet_sim::run);
}
