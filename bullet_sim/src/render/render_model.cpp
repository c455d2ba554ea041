// render_model: a PNG picture of a robot as bullet_sim simulates it, for servers and CI where rviz cannot
// run. ROS-free: it needs ROS_PACKAGE_PATH for package:// URIs and the xacro executable for --xacro only.
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "bullet_sim/render/offscreen_renderer.h"
#include "bullet_sim/render/robot_snapshot.h"
#include "bullet_sim/spec/diagnostics.h"

extern char** environ;

namespace bullet_sim {
namespace {

constexpr int kExitFailure = 1;
constexpr int kExitUsage = 2;

constexpr char kUsage[] =
    "usage: render_model (--xacro FILE [--arg name:=value]... | --urdf FILE) [--world FILE]\n"
    "                    [--view chase|top|front] [--size WxH] [--pose x,y,yaw] --out FILE.png\n"
    "\n"
    "Spawns the robot in the world, resting on the ground at the pose (x [m], y [m], yaw [rad]), lets\n"
    "each of its lidars scan once, and writes a picture of the robot, the world, a 1 m ground grid and\n"
    "the lidar hits (red). A relative --world is looked up in bullet_sim/worlds, then\n"
    "bullet_sim_bringup/worlds, then the working directory.\n"
    "Defaults: --world empty.world --view chase (from behind and above) --size 640x480 --pose 0,0,0\n";

struct Options {
  std::string xacro;
  std::vector<std::string> xacro_args;  ///< "name:=value"
  std::string urdf;
  std::string world;
  View view = View::kChase;
  int width = 640, height = 480;
  SpawnPose pose;
  std::string out;
  bool help = false;
};

class UsageError : public std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// A number that is the whole of `text`.
double parseNumber(const std::string& text, const std::string& option) {
  size_t used = 0;
  double value = NAN;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size() || !std::isfinite(value)) {
    throw UsageError(option + ": [" + text + "] is not a number");
  }
  return value;
}

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::istringstream stream(text);
  for (std::string part; std::getline(stream, part, separator);) parts.push_back(part);
  if (!text.empty() && text.back() == separator) parts.emplace_back();
  return parts;
}

Options parseArguments(int argc, char** argv) {
  Options options;
  for (int i = 1; i < argc; ++i) {
    const std::string option = argv[i];
    if (option == "--help" || option == "-h") {
      options.help = true;
      return options;
    }
    if (i + 1 >= argc) throw UsageError(option + " needs a value");
    const std::string value = argv[++i];
    if (option == "--xacro") {
      options.xacro = value;
    } else if (option == "--arg") {
      if (value.find(":=") == std::string::npos) throw UsageError("--arg [" + value + "]: write name:=value");
      options.xacro_args.push_back(value);
    } else if (option == "--urdf") {
      options.urdf = value;
    } else if (option == "--world") {
      options.world = value;
    } else if (option == "--view") {
      const auto view = parseView(value);
      if (!view) throw UsageError("--view [" + value + "]: choose chase, top or front");
      options.view = *view;
    } else if (option == "--size") {
      const auto sides = split(value, 'x');
      const auto side = [&](const std::string& text) {
        const double pixels = parseNumber(text, "--size");
        if (pixels < 1 || pixels > 16384 || pixels != std::floor(pixels)) {
          throw UsageError("--size [" + value + "]: width and height are whole numbers from 1 to 16384");
        }
        return static_cast<int>(pixels);
      };
      if (sides.size() != 2) throw UsageError("--size [" + value + "]: write WxH, e.g. 640x480");
      options.width = side(sides[0]);
      options.height = side(sides[1]);
    } else if (option == "--pose") {
      const auto parts = split(value, ',');
      if (parts.size() != 3) throw UsageError("--pose [" + value + "]: write x,y,yaw in m, m, rad");
      options.pose.x = parseNumber(parts[0], "--pose");
      options.pose.y = parseNumber(parts[1], "--pose");
      options.pose.yaw = parseNumber(parts[2], "--pose");
    } else if (option == "--out") {
      options.out = value;
    } else {
      throw UsageError("unknown option [" + option + "]");
    }
  }
  if (options.xacro.empty() == options.urdf.empty()) throw UsageError("give one of --xacro or --urdf");
  if (!options.xacro_args.empty() && options.xacro.empty()) throw UsageError("--arg goes with --xacro");
  if (options.out.empty()) throw UsageError("--out FILE.png is missing");
  return options;
}

/// A failure to report on stderr, ending the program with exit status 1.
class Failure : public std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// The URDF that `xacro file args...` prints. xacro's own messages go straight to our stderr.
std::string runXacro(const std::string& file, const std::vector<std::string>& args) {
  std::vector<std::string> command = {"xacro", file};
  command.insert(command.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& word : command) argv.push_back(word.data());
  argv.push_back(nullptr);

  int pipe_fds[2];
  if (pipe(pipe_fds) != 0)
    throw Failure(std::string("cannot create a pipe for xacro: ") + std::strerror(errno));
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], STDOUT_FILENO);
  posix_spawn_file_actions_addclose(&actions, pipe_fds[0]);
  posix_spawn_file_actions_addclose(&actions, pipe_fds[1]);
  pid_t pid = 0;
  const int spawned = posix_spawnp(&pid, "xacro", &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  close(pipe_fds[1]);
  if (spawned != 0) {
    close(pipe_fds[0]);
    throw Failure(std::string("cannot run xacro: ") + std::strerror(spawned) +
                  "; install it (scripts/workspace.sh install) and put it on PATH, or pass --urdf");
  }
  std::string urdf;
  char buffer[65536];
  for (ssize_t n; (n = read(pipe_fds[0], buffer, sizeof buffer)) != 0;) {
    if (n > 0)
      urdf.append(buffer, n);
    else if (errno != EINTR)
      break;
  }
  close(pipe_fds[0]);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    throw Failure("xacro " + file + " failed (see its message above)");
  }
  return urdf;
}

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw Failure("cannot read URDF [" + path + "]: " + std::strerror(errno));
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// The world file for --world (see findWorldFile); bullet_sim's empty.world by default.
std::string findWorld(const std::string& name, const PackageResolver& resolver) {
  std::string error;
  const auto path = findWorldFile(name.empty() ? "empty.world" : name, resolver, &error);
  if (!path)
    throw Failure(error + "; pass an existing file, or source devel/setup.bash for ROS_PACKAGE_PATH");
  return *path;
}

int run(const Options& options) {
  const PackageResolver resolver = PackageResolver::fromEnvironment();
  std::vector<std::string> warnings;
  const std::string source = options.xacro.empty() ? options.urdf : options.xacro;
  const std::string urdf =
      options.xacro.empty() ? readFile(options.urdf) : runXacro(options.xacro, options.xacro_args);
  // Said as soon as known, so that they are not lost when a later step fails.
  const auto say = [](const std::vector<std::string>& warnings) {
    for (const std::string& warning : warnings) std::cerr << "render_model: warning: " << warning << "\n";
  };
  ModelSpec model = parseModel(urdf, source, resolver, &warnings);
  WorldSpec world = loadWorld(findWorld(options.world, resolver), resolver, &warnings);
  say(warnings);
  RobotSnapshot snapshot = snapshotRobot(std::move(world), std::move(model), options.pose, options.view);
  say(snapshot.warnings);

  const Image image = OffscreenRenderer().render(snapshot.scene, options.width, options.height);
  std::string error;
  if (!writePng(options.out, image, &error)) throw Failure(error);
  return EXIT_SUCCESS;
}

}  // namespace
}  // namespace bullet_sim

int main(int argc, char** argv) {
  using namespace bullet_sim;
  Options options;
  try {
    options = parseArguments(argc, argv);
  } catch (const UsageError& error) {
    std::cerr << "render_model: " << error.what() << "\n\n" << kUsage;
    return kExitUsage;
  }
  if (options.help) {
    std::cout << kUsage;
    return EXIT_SUCCESS;
  }
  try {
    return run(options);
  } catch (const std::exception& error) {  // SpecError lists every problem of the file, one per line
    std::cerr << "render_model: " << error.what() << "\n";
    return kExitFailure;
  }
}
