// render_model: a PNG picture of a robot as bullet_sim simulates it, for servers and CI where rviz cannot
// run. ROS-free: it needs ROS_PACKAGE_PATH for package:// URIs and the xacro executable for --xacro only.
#include <cmath>
#include <iostream>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "bullet_sim/common/diagnostics.h"
#include "bullet_sim/render/image.h"
#include "bullet_sim/render/offscreen_renderer.h"
#include "bullet_sim/scene/robot_snapshot.h"
#include "tools/command_line.h"

namespace bullet_sim {
namespace {

constexpr char kUsage[] =
    "usage: render_model (--xacro FILE [--arg name:=value]... | --urdf FILE) [--world FILE]\n"
    "                    [--view chase|top|front|camera:NAME|depth:NAME] [--size WxH]\n"
    "                    [--pose x,y,yaw] [--limit NAME=VALUE]... --out FILE.png\n"
    "\n"
    "Spawns the robot in the world, resting on the ground at the pose (x [m], y [m], yaw [rad]), lets\n"
    "each of its lidars scan once, and writes a picture of the robot, the world, a 1 m ground grid and\n"
    "the lidar hits (red). A relative --world is looked up in bullet_sim/worlds, then\n"
    "bullet_sim_bringup/worlds, then the working directory.\n"
    "camera:NAME draws what the robot's camera NAME (its <sensor> name or cameraName) sees after\n"
    "1 s of settling, at the camera's own size; depth:NAME its depth camera's depth, in grey.\n"
    "--limit sets one of the simulator's limits (its ~limits/NAME), e.g. max_links=2000.\n"
    "Defaults: --world empty.world --view chase (from behind and above) --size 640x480 --pose 0,0,0\n";

struct Options {
  std::string xacro;
  std::vector<std::string> xacro_args;  ///< "name:=value"
  std::string urdf;
  std::string world;
  View view = View::kChase;
  std::optional<CameraView> camera;
  int width = 640, height = 480;
  SpawnPose pose;
  std::string out;
  Limits limits;
  bool help = false;
};

Options parseArguments(int argc, char** argv) {
  Options options;
  parseCommandLine(argc, argv,
                   {{"--xacro", [&](const std::string& value) { options.xacro = value; }},
                    {"--arg",
                     [&](const std::string& value) {
                       if (value.find(":=") == std::string::npos)
                         throw UsageError("--arg [" + value + "]: write name:=value");
                       options.xacro_args.push_back(value);
                     },
                     /*repeatable=*/true},
                    {"--urdf", [&](const std::string& value) { options.urdf = value; }},
                    {"--world", [&](const std::string& value) { options.world = value; }},
                    {"--view",
                     [&](const std::string& value) {
                       options.camera = parseCameraView(value);
                       const auto view = parseView(value);
                       if (!view && !options.camera) {
                         throw UsageError("--view [" + value +
                                          "]: choose chase, top, front, camera:NAME or depth:NAME");
                       }
                       options.view = view.value_or(View::kChase);
                     }},
                    {"--size",
                     [&](const std::string& value) {
                       std::tie(options.width, options.height) = parseSize(value, "--size", 16384);
                     }},
                    {"--pose",
                     [&](const std::string& value) {
                       parsePlanarPose(value, "--pose", &options.pose.x, &options.pose.y, &options.pose.yaw);
                     }},
                    {"--out", [&](const std::string& value) { options.out = value; }},
                    limitOption(options.limits)},
                   &options.help);
  if (options.help) return options;
  if (options.xacro.empty() == options.urdf.empty()) throw UsageError("give one of --xacro or --urdf");
  if (!options.xacro_args.empty() && options.xacro.empty()) throw UsageError("--arg goes with --xacro");
  if (options.out.empty()) throw UsageError("--out FILE.png is missing");
  return options;
}

int run(const Options& options) {
  const PackageResolver resolver = PackageResolver::fromEnvironment();
  std::vector<std::string> warnings;
  const std::string source = options.xacro.empty() ? options.urdf : options.xacro;
  const std::string urdf = options.xacro.empty() ? readUrdfFile(options.urdf, options.limits)
                                                 : runXacro(options.xacro, options.xacro_args);
  // Said as soon as known, so that they are not lost when a later step fails.
  const auto say = [](const std::vector<std::string>& warnings) {
    for (const std::string& warning : warnings) std::cerr << "render_model: warning: " << warning << "\n";
  };
  ModelSpec model = parseModel(urdf, source, resolver, &warnings, options.limits);
  WorldSpec world =
      loadWorld(findWorld(options.world, resolver), resolver, &warnings, WorldOptions{false, options.limits});
  say(warnings);
  OffscreenRenderer renderer;
  Image image;
  if (options.camera) {
    std::vector<std::string> spawn_warnings;
    image = snapshotCamera(std::move(world), std::move(model), options.pose, *options.camera, renderer,
                           &spawn_warnings);
    say(spawn_warnings);
  } else {
    RobotSnapshot snapshot = snapshotRobot(std::move(world), std::move(model), options.pose, options.view);
    say(snapshot.warnings);
    image = renderer.render(snapshot.scene, options.width, options.height);
  }
  std::string error;
  if (!writePng(options.out, image, &error)) throw Failure(error);
  return EXIT_SUCCESS;
}

}  // namespace
}  // namespace bullet_sim

int main(int argc, char** argv) {
  return bullet_sim::toolMain("render_model", bullet_sim::kUsage, argc, argv, bullet_sim::parseArguments,
                              bullet_sim::run);
}
