// urdf_doctor FILE [name:=value ...]: says what in a URDF or xacro makes the simulation misbehave, and how to
// fix it. Exit status 0 when clean or warnings only, 1 on errors (or warnings, with --warnings-as-errors), 2
// when the file cannot be read, expanded or parsed. ROS-free: it needs ROS_PACKAGE_PATH for package:// URIs
// and the xacro executable for .xacro files.
#include <cerrno>
#include <cstring>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "bullet_sim/common/files.h"
#include "bullet_sim/doctor/doctor.h"
#include "bullet_sim/tools/subprocess.h"
#include "tools/command_line.h"

namespace bullet_sim {
namespace {

constexpr char kUsage[] =
    "usage: urdf_doctor [--warnings-as-errors] [--limit NAME=VALUE]... FILE [name:=value ...]\n"
    "\n"
    "Checks a URDF, or a .xacro expanded with the xacro executable and the name:=value arguments, and\n"
    "reports each problem with the element, the reason and the fix. What the simulator refuses is an\n"
    "error here, with the same message; --limit sets one of its limits as the simulator's\n"
    "~limits/NAME parameter does (e.g. --limit max_links=2000).\n"
    "--warnings-as-errors: warnings count as errors for the exit status.\n"
    "Exit status: 0 clean or warnings only, 1 errors, 2 the file cannot be read, expanded or parsed.\n";

bool endsWith(const std::string& text, const std::string& end) {
  return text.size() >= end.size() && text.compare(text.size() - end.size(), end.size(), end) == 0;
}

DoctorReport examineFile(const std::string& file, const std::vector<std::string>& args,
                         const Limits& limits) {
  const PackageResolver resolver = PackageResolver::fromEnvironment();
  try {
    // A FIFO or /dev/zero would block or fill the memory, here or in xacro.
    if (auto problem = fileProblem(file, limits.max_description_bytes, "max_description_bytes"))
      return unreadableReport(file, "the file " + *problem);
    if (!endsWith(file, ".xacro") && args.empty()) {
      return examineUrdf(readRegularFile(file, limits.max_description_bytes, "max_description_bytes"), file,
                         resolver, limits);
    }
    return examineUrdf(expandXacro(file, args), file, resolver, limits);
  } catch (const std::runtime_error& error) {
    return unreadableReport(file, error.what());
  }
}

}  // namespace
}  // namespace bullet_sim

int main(int argc, char** argv) {
  using bullet_sim::UsageError;
  if (bullet_sim::listPlugins(argc, argv)) return 0;
  bool help = false;
  bool warnings_as_errors = false;
  bullet_sim::Limits limits;
  std::vector<std::string> words;  // FILE, then name:=value arguments for xacro
  const bullet_sim::ToolOption positional{
      "words", [&](const std::string& word) {
        if (!words.empty() && word.find(":=") == std::string::npos)
          throw UsageError("[" + word + "]: xacro arguments are name:=value");
        words.push_back(word);
      }};
  try {
    const bullet_sim::ToolOption strict{"--warnings-as-errors",
                                        [&](const std::string&) { warnings_as_errors = true; }, false, true};
    bullet_sim::parseCommandLine(argc, argv, {strict, bullet_sim::limitOption(limits)}, &help, &positional);
    if (!help && words.empty()) throw UsageError("FILE is missing");
  } catch (const UsageError& error) {
    std::cerr << "urdf_doctor: " << error.what() << "\n\n" << bullet_sim::kUsage;
    return 2;
  }
  if (help) {
    std::cout << bullet_sim::kUsage;
    return 0;
  }
  const bullet_sim::DoctorReport report = bullet_sim::examineFile(
      words.front(), std::vector<std::string>(words.begin() + 1, words.end()), limits);
  std::cout << report.text();
  return report.exitCode(warnings_as_errors);
}
