// What bullet_sim's ROS-free command-line tools (render_model, bench) share: argument parsing helpers, the
// robot description from a URDF or an xacro file, and the world file a user means.
#pragma once

#include <cstdlib>
#include <exception>
#include <functional>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "bullet_sim/common/limits.h"
#include "bullet_sim/assets/package_resolver.h"

namespace bullet_sim {

/// A bad command line: the tool prints the message and its usage, and exits with status 2.
class UsageError : public std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// A failure to report on stderr, ending the tool with exit status 1.
class Failure : public std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// An option of a tool's command line: its name ("--world"), and what takes its text, once per use.
struct ToolOption {
  std::string name;
  std::function<void(const std::string& value)> take;
  bool repeatable = false;
  bool flag = false;  ///< takes no value: `take` gets "" once when it is given
};

/// Parses a tool's command line with CLI11: each option's values go to its `take`, in the order of
/// `options`; -h or --help sets `help` (and nothing else is taken). Positional words go to `positional`'s
/// `take`, when given. Anything CLI11 refuses (an unknown option, a missing value) is a UsageError.
void parseCommandLine(int argc, char** argv, const std::vector<ToolOption>& options, bool* help,
                      const ToolOption* positional = nullptr);

/// "WxH" as two whole numbers from 1 to `largest`; UsageError naming `option` otherwise.
std::pair<int, int> parseSize(const std::string& text, const std::string& option, int largest);

/// "x,y,yaw" [m, m, rad]; UsageError naming `option` otherwise.
void parsePlanarPose(const std::string& text, const std::string& option, double* x, double* y, double* yaw);

/// A finite number that is the whole of `text`; UsageError naming `option` otherwise.
double parseNumber(const std::string& text, const std::string& option);

/// `text` cut at every `separator`; a trailing separator gives a trailing empty part.
std::vector<std::string> split(const std::string& text, char separator);

/// The URDF that `xacro file args...` prints (expandXacro); a Failure with xacro's message when it fails.
std::string runXacro(const std::string& file, const std::vector<std::string>& args);

/// The whole of a URDF file: a regular file of at most limits.max_description_bytes; a Failure otherwise.
std::string readUrdfFile(const std::string& path, const Limits& limits = Limits());

/// --limit NAME=VALUE (repeatable): sets one of `limits` (common/limits.h); a UsageError names the
/// limits there are when NAME is none of them.
ToolOption limitOption(Limits& limits);

/// The world file for a --world option (see findWorldFile); bullet_sim's empty.world when `name` is empty.
std::string findWorld(const std::string& name, const PackageResolver& resolver);

/// With --list-plugins anywhere on the command line: prints the plugin registry the tool was built with (one
/// "folder filename [sensor types]" line per plugin type) and returns true, for the tool to exit 0.
bool listPlugins(int argc, char** argv);

/// A tool's whole main: --list-plugins, `usage` on --help (exit 0) or after a UsageError (exit 2), then
/// `run`, whose exceptions are reported on stderr (exit 1). A SpecError lists every problem of the file, one
/// per line.
template <typename Options>
int toolMain(const char* tool, const char* usage, int argc, char** argv, Options (*parse)(int, char**),
             int (*run)(const Options&)) {
  if (listPlugins(argc, argv)) return EXIT_SUCCESS;
  Options options;
  try {
    options = parse(argc, argv);
  } catch (const UsageError& error) {
    std::cerr << tool << ": " << error.what() << "\n\n" << usage;
    return 2;
  }
  if (options.help) {
    std::cout << usage;
    return EXIT_SUCCESS;
  }
  try {
    return run(options);
  } catch (const std::exception& error) {
    std::cerr << tool << ": " << error.what() << "\n";
    return EXIT_FAILURE;
  }
}

}  // namespace bullet_sim
