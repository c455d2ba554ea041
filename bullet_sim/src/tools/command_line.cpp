#include "tools/command_line.h"

#include <CLI/CLI.hpp>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iostream>
#include <iterator>
#include <sstream>

#include "bullet_sim/common/files.h"
#include "bullet_sim/model/world.h"
#include "bullet_sim/plugins/registry.h"
#include "bullet_sim/tools/subprocess.h"

namespace bullet_sim {

void parseCommandLine(int argc, char** argv, const std::vector<ToolOption>& options, bool* help,
                      const ToolOption* positional) {
  CLI::App app;
  app.set_help_flag();  // the tool prints its own usage
  app.add_flag("-h,--help", *help);
  std::vector<std::vector<std::string>> values(options.size());
  std::vector<bool> flags(options.size(), false);
  for (size_t i = 0; i < options.size(); ++i) {
    if (options[i].flag) {
      app.add_flag_callback(options[i].name, [&flags, i] { flags[i] = true; });
      continue;
    }
    CLI::Option* option = app.add_option(options[i].name, values[i]);
    if (!options[i].repeatable)
      option->expected(1)->allow_extra_args(false);  // a word after it is positional
  }
  std::vector<std::string> words;
  if (positional) app.add_option(positional->name, words);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    throw UsageError(error.what());
  }
  if (*help) return;
  for (size_t i = 0; i < options.size(); ++i) {
    if (flags[i]) options[i].take("");
    for (const auto& value : values[i]) options[i].take(value);
  }
  for (const auto& word : words) positional->take(word);
}

std::pair<int, int> parseSize(const std::string& text, const std::string& option, int largest) {
  const auto sides = split(text, 'x');
  if (sides.size() != 2) throw UsageError(option + " [" + text + "]: write WxH, e.g. 640x480");
  const auto side = [&](const std::string& part) {
    const double pixels = parseNumber(part, option);
    if (pixels < 1 || pixels > largest || pixels != std::floor(pixels)) {
      throw UsageError(option + " [" + text + "]: width and height are whole numbers from 1 to " +
                       std::to_string(largest));
    }
    return static_cast<int>(pixels);
  };
  return {side(sides[0]), side(sides[1])};
}

void parsePlanarPose(const std::string& text, const std::string& option, double* x, double* y, double* yaw) {
  const auto parts = split(text, ',');
  if (parts.size() != 3) throw UsageError(option + " [" + text + "]: write x,y,yaw in m, m, rad");
  *x = parseNumber(parts[0], option);
  *y = parseNumber(parts[1], option);
  *yaw = parseNumber(parts[2], option);
}

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

std::string runXacro(const std::string& file, const std::vector<std::string>& args) {
  try {
    return expandXacro(file, args);
  } catch (const std::runtime_error& error) {
    throw Failure(error.what());
  }
}

std::string readUrdfFile(const std::string& path, const Limits& limits) {
  if (auto problem = fileProblem(path, limits.max_description_bytes, "max_description_bytes"))
    throw Failure("cannot read URDF [" + path + "]: it " + *problem);
  try {
    return readRegularFile(path, limits.max_description_bytes, "max_description_bytes");
  } catch (const std::runtime_error& e) {
    throw Failure(std::string("cannot read URDF ") + e.what());
  }
}

ToolOption limitOption(Limits& limits) {
  return {"--limit",
          [&limits](const std::string& value) {
            const auto parts = split(value, '=');
            if (parts.size() != 2)
              throw UsageError("--limit [" + value + "]: write NAME=VALUE, e.g. max_links=2000");
            try {
              limits.set(parts[0], parseNumber(parts[1], "--limit"));
            } catch (const std::invalid_argument& e) {
              throw UsageError(std::string("--limit: ") + e.what());
            }
          },
          /*repeatable=*/true};
}

std::string findWorld(const std::string& name, const PackageResolver& resolver) {
  std::string error;
  const auto path = findWorldFile(name.empty() ? "empty.world" : name, resolver, &error);
  if (!path)
    throw Failure(error + "; pass an existing file, or source devel/setup.bash for ROS_PACKAGE_PATH");
  return *path;
}

bool listPlugins(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    if (std::string(argv[i]) != "--list-plugins") continue;
    std::cout << PluginRegistry::builtin().listing();
    return true;
  }
  return false;
}

}  // namespace bullet_sim
