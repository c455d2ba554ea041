#include "scenario/scenario_launch.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <tinyxml2.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <stdexcept>

extern char** environ;

namespace bullet_sim {
namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;

/// [s] of wall time allowed for starting and stopping, on top of the run
constexpr double kStartAndStop = 30;
constexpr double kInterruptGrace = 10;  ///< [s] roslaunch gets to stop its nodes after SIGINT
constexpr double kTermGrace = 3;        ///< [s] a process gets after SIGTERM, before SIGKILL

/// A TCP port on 127.0.0.1 that nobody listens on now (the kernel's choice), as rostest finds one.
int freePort() {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t length = sizeof address;
  if (fd < 0 || bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0 ||
      getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length) != 0) {
    if (fd >= 0) close(fd);
    throw std::runtime_error(std::string("cannot find a free port for the ROS master: ") +
                             std::strerror(errno));
  }
  close(fd);
  return ntohs(address.sin_port);
}

/// The launch file that brings up the run: sim time, the simulator, each robot's description and
/// robot_state_publisher (in the robot's namespace when there are several), and the user's launch file.
std::string launchFile(const ScenarioSpec& spec, const std::vector<std::string>& robots,
                       const std::string& urdf_file, const std::vector<std::string>& host_arguments) {
  tinyxml2::XMLDocument document;
  tinyxml2::XMLElement* launch = document.NewElement("launch");
  document.InsertEndChild(launch);
  tinyxml2::XMLElement* sim_time = launch->InsertNewChildElement("param");
  sim_time->SetAttribute("name", "/use_sim_time");
  sim_time->SetAttribute("value", "true");
  std::string args;
  for (const auto& word : host_arguments) args += (args.empty() ? "'" : " '") + word + "'";
  tinyxml2::XMLElement* host = launch->InsertNewChildElement("node");
  host->SetAttribute("pkg", "bullet_sim");
  host->SetAttribute("type", "scenario_host");
  host->SetAttribute("name", "gazebo");  // as gzserver registers, so /gazebo/... works
  host->SetAttribute("required", "true");
  host->SetAttribute("args", args.c_str());
  for (const auto& robot : robots) {
    tinyxml2::XMLElement* group = launch->InsertNewChildElement("group");
    if (robots.size() > 1) group->SetAttribute("ns", robot.c_str());
    tinyxml2::XMLElement* description = group->InsertNewChildElement("param");
    description->SetAttribute("name", "robot_description");
    description->SetAttribute("textfile", urdf_file.c_str());
    tinyxml2::XMLElement* publisher = group->InsertNewChildElement("node");
    publisher->SetAttribute("pkg", "robot_state_publisher");
    publisher->SetAttribute("type", "robot_state_publisher");
    publisher->SetAttribute("name", "robot_state_publisher");
    if (robots.size() > 1) {
      tinyxml2::XMLElement* prefix = publisher->InsertNewChildElement("param");
      prefix->SetAttribute("name", "tf_prefix");
      prefix->SetAttribute("value", robot.c_str());
    }
  }
  tinyxml2::XMLElement* include = launch->InsertNewChildElement("include");
  include->SetAttribute("file", spec.launch->file.c_str());
  for (const auto& [name, value] : spec.launch->args) {
    tinyxml2::XMLElement* arg = include->InsertNewChildElement("arg");
    arg->SetAttribute("name", name.c_str());
    arg->SetAttribute("value", value.c_str());
  }
  tinyxml2::XMLPrinter printer;
  document.Print(&printer);
  return printer.CStr();
}

/// This process's environment for the run's processes: its own master, its logs in the run's folder, and its
/// traffic on this machine.
std::vector<std::string> runEnvironment(int port, const std::string& out) {
  std::vector<std::string> environment;
  for (char** entry = environ; *entry; ++entry) {
    const std::string text = *entry;
    const bool replaced = text.rfind("ROS_MASTER_URI=", 0) == 0 || text.rfind("ROS_LOG_DIR=", 0) == 0 ||
                          text.rfind("ROS_IP=", 0) == 0 || text.rfind("ROS_HOSTNAME=", 0) == 0;
    if (!replaced) environment.push_back(text);
  }
  environment.push_back("ROS_MASTER_URI=http://127.0.0.1:" + std::to_string(port));
  environment.push_back("ROS_LOG_DIR=" + fs::absolute(out).string() + "/ros_log");
  environment.push_back("ROS_HOSTNAME=127.0.0.1");
  return environment;
}

/// Starts `words` in a session of its own (so SIGINT reaches it as Ctrl-C would, and nothing else), its
/// output appended to `log`.
pid_t startInSession(std::vector<std::string> words, std::vector<std::string> environment,
                     const std::string& log) {
  std::vector<char*> argv, envp;
  for (auto& word : words) argv.push_back(word.data());
  argv.push_back(nullptr);
  for (auto& entry : environment) envp.push_back(entry.data());
  envp.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  // Signals as a terminal gives them: a caller that blocks or ignores SIGINT (a Ray worker blocks it) would
  // otherwise pass that on to roslaunch and every node, which then stop only at roslaunch's SIGTERM, 15 s
  // late.
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  sigset_t none, defaults;
  sigemptyset(&none);
  sigemptyset(&defaults);
  for (int signal_number : {SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGPIPE}) sigaddset(&defaults, signal_number);
  posix_spawnattr_setsigmask(&attributes, &none);
  posix_spawnattr_setsigdefault(&attributes, &defaults);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSID | POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
  pid_t pid = 0;
  const int spawned = posix_spawnp(&pid, argv[0], &actions, &attributes, argv.data(), envp.data());
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attributes);
  if (spawned != 0) {
    throw std::runtime_error("cannot run " + words.front() + ": " + std::strerror(spawned) +
                             "; install ROS (scripts/workspace.sh install) and source devel/setup.bash");
  }
  return pid;
}

/// Waits up to `seconds` for child `pid` to end, and reaps it; false when it is still running.
bool waitFor(pid_t pid, double seconds) {
  const int fd = static_cast<int>(syscall(SYS_pidfd_open, pid, 0));
  const auto deadline = Clock::now() + std::chrono::duration<double>(seconds);
  while (true) {
    int status = 0;
    const pid_t done = waitpid(pid, &status, WNOHANG);
    if (done == pid || (done < 0 && errno == ECHILD)) break;
    const double left = std::chrono::duration<double>(deadline - Clock::now()).count();
    if (left <= 0) {
      if (fd >= 0) close(fd);
      return false;
    }
    pollfd event{fd, POLLIN, 0};
    if (fd < 0 || poll(&event, 1, static_cast<int>(std::min(left, 0.1) * 1000) + 1) < 0) usleep(10000);
  }
  if (fd >= 0) close(fd);
  return true;
}

/// The processes whose parent is `parent`, from /proc.
std::vector<pid_t> childrenOf(pid_t parent) {
  std::vector<pid_t> children;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator("/proc", ec)) {
    const std::string name = entry.path().filename();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::ifstream stat(entry.path() / "stat");
    std::string text;
    std::getline(stat, text);
    const size_t close = text.rfind(')');
    if (close == std::string::npos) continue;
    char state = 0;
    int ppid = 0;
    if (std::sscanf(text.c_str() + close + 1, " %c %d", &state, &ppid) == 2 && ppid == parent)
      children.push_back(std::stoi(name));
  }
  return children;
}

/// Ends every process left under this one: orphans of roslaunch's nodes come back to us as their subreaper.
/// SIGTERM first, SIGKILL after kTermGrace; all are reaped.
void endDescendants() {
  std::set<pid_t> signalled;
  const auto deadline = Clock::now() + std::chrono::duration<double>(kTermGrace);
  for (std::vector<pid_t> left = childrenOf(getpid()); !left.empty(); left = childrenOf(getpid())) {
    const bool late = Clock::now() > deadline;
    for (pid_t pid : left) {
      if (late) kill(pid, SIGKILL);
      else if (signalled.insert(pid).second) kill(pid, SIGTERM);
      int status = 0;
      waitpid(pid, &status, WNOHANG);
    }
    usleep(20000);
  }
}

Verdict verdictOf(const std::string& out) {
  std::ifstream in(out + "/result.json");
  const auto json = nlohmann::json::parse(in, nullptr, false);
  if (!json.is_object() || !json.contains("exit_code")) {
    throw std::runtime_error("the simulator stopped without writing " + out + "/result.json; see " + out +
                             "/launch.log");
  }
  const int code = json["exit_code"].get<int>();
  return code == 0 ? Verdict::kPass : code == 1 ? Verdict::kFail : Verdict::kError;
}

}  // namespace

Verdict runLaunch(const ScenarioSpec& spec, const ScenarioCommand& command, const std::string& out) {
  // Checked here first, so that a bad robot or world is reported before any process starts.
  const ScenarioAssets assets = loadAssets(spec, PackageResolver::fromEnvironment());
  fs::create_directories(out);
  fs::remove(fs::path(out) / "result.json");
  const std::string urdf_file = fs::absolute(fs::path(out) / "robot.urdf").string();
  std::ofstream(urdf_file) << assets.urdf;
  ScenarioCommand host = command;
  host.out = fs::absolute(out).string();
  if (!host.file.empty()) host.file = fs::absolute(host.file).string();
  if (!host.matrix.empty()) host.matrix = fs::absolute(host.matrix).string();
  const std::string launch_file = fs::absolute(fs::path(out) / "scenario.launch").string();
  std::ofstream(launch_file) << launchFile(spec, assets.robot_names, urdf_file, scenarioArguments(host));

  prctl(PR_SET_CHILD_SUBREAPER, 1);  // the nodes roslaunch leaves behind become ours to end
  // roslaunch starts the master on the free port, as rostest does.
  const int port = freePort();
  const std::string log = (fs::path(out) / "launch.log").string();
  fs::remove(log);
  const pid_t roslaunch =
      startInSession({"roslaunch", "-p", std::to_string(port), "--skip-log-check", launch_file},
                     runEnvironment(port, out), log);
  const double pace = spec.launch->real_time_factor > 0 ? spec.launch->real_time_factor : 1;
  const double limit = spec.launch->ready_timeout + spec.duration / pace + kStartAndStop;
  const bool finished = waitFor(roslaunch, limit);
  if (!finished) {
    kill(-roslaunch, SIGINT);
    if (!waitFor(roslaunch, kInterruptGrace)) {
      kill(-roslaunch, SIGKILL);
      waitFor(roslaunch, kTermGrace);
    }
  }
  endDescendants();
  if (!finished && !fs::exists(fs::path(out) / "result.json")) {
    throw std::runtime_error(
        "the launch did not finish within " + std::to_string(static_cast<int>(limit)) +
        " s of wall time (ready_timeout + duration / real_time_factor + 30 s); stopped it; see " + out +
        "/launch.log");
  }
  return verdictOf(out);
}

}  // namespace bullet_sim
