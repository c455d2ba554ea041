#include "bullet_sim/tools/process_stats.h"

#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#include <fstream>
#include <sstream>
#include <string>

namespace bullet_sim {

std::optional<double> processAge() {
  std::ifstream stat("/proc/self/stat");
  std::string text;
  std::getline(stat, text);
  // Field 2, the command name, may hold spaces: count fields after its closing parenthesis.
  const size_t name_end = text.rfind(')');
  if (name_end == std::string::npos) return std::nullopt;
  std::istringstream fields(text.substr(name_end + 1));
  std::string field;
  for (int index = 3; index <= 22 && fields >> field; ++index) {
  }
  timespec now{};
  const long ticks_per_second = sysconf(_SC_CLK_TCK);
  if (!fields || ticks_per_second <= 0 || clock_gettime(CLOCK_BOOTTIME, &now) != 0) return std::nullopt;
  const double started = std::stod(field) / ticks_per_second;  // field 22: start time since boot
  return now.tv_sec + now.tv_nsec * 1e-9 - started;
}

double cpuSeconds() {
  const auto seconds = [](int who) {
    rusage usage{};
    getrusage(who, &usage);
    const auto of = [](const timeval& time) { return time.tv_sec + time.tv_usec * 1e-6; };
    return of(usage.ru_utime) + of(usage.ru_stime);
  };
  return seconds(RUSAGE_SELF) + seconds(RUSAGE_CHILDREN);
}

double peakRssMb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;  // reported in KiB
}

double currentRssMb() {
  std::ifstream statm("/proc/self/statm");
  double size = 0, resident = 0;
  if (!(statm >> size >> resident)) return 0;
  return resident * static_cast<double>(sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

}  // namespace bullet_sim
