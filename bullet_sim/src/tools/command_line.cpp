#include "tools/command_line.h"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>

#include "bullet_sim/description/world_spec.h"
#include "bullet_sim/tools/subprocess.h"

namespace bullet_sim {

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

std::string readUrdfFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw Failure("cannot read URDF [" + path + "]: " + std::strerror(errno));
  return std::string(std::istreambuf_iterator<char>(in), {});
}

std::string findWorld(const std::string& name, const PackageResolver& resolver) {
  std::string error;
  const auto path = findWorldFile(name.empty() ? "empty.world" : name, resolver, &error);
  if (!path)
    throw Failure(error + "; pass an existing file, or source devel/setup.bash for ROS_PACKAGE_PATH");
  return *path;
}

}  // namespace bullet_sim
