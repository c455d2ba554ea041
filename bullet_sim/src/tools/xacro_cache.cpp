#include "bullet_sim/tools/xacro_cache.h"

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

#include "bullet_sim/plugins/plugin.h"
#include "bullet_sim/tools/subprocess.h"

namespace bullet_sim {
namespace fs = std::filesystem;

namespace {

/// "<modification time> <path>" per line, for the file and what it includes; "" when one is missing.
std::string stamps(const std::vector<std::string>& files) {
  std::ostringstream text;
  for (const auto& file : files) {
    std::error_code ec;
    const auto time = fs::last_write_time(file, ec);
    if (ec) return "";
    text << time.time_since_epoch().count() << " " << file << "\n";
  }
  return text.str();
}

std::string readAll(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return "";
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// The files of a cache entry's stamps, as written by stamps().
std::vector<std::string> stampedFiles(const std::string& text) {
  std::vector<std::string> files;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    const size_t space = line.find(' ');
    if (space != std::string::npos) files.push_back(line.substr(space + 1));
  }
  return files;
}

/// The files xacro reads for `file` besides itself; `ok` is false when xacro cannot list them.
std::vector<std::string> dependencies(const std::string& file, const std::vector<std::string>& args,
                                      bool* ok) {
  std::vector<std::string> command = {"xacro", "--deps", file};
  command.insert(command.end(), args.begin(), args.end());
  std::string error;
  const auto output = runProcess(command, &error);
  *ok = output && output->status == 0;
  std::vector<std::string> files;
  if (!*ok) return files;
  std::istringstream words(output->output);
  for (std::string word; words >> word;) files.push_back(fs::absolute(word).string());
  return files;
}

/// Writes `text` to `path` through a file of its own beside it, renamed into place.
void writeAtomically(const fs::path& path, const std::string& text) {
  const fs::path temporary = path.string() + ".tmp" + std::to_string(getpid());
  {
    std::ofstream out(temporary, std::ios::binary);
    out << text;
    if (!out) return;
  }
  std::error_code ec;
  fs::rename(temporary, path, ec);
  if (ec) fs::remove(temporary, ec);
}

}  // namespace

std::string xacroCacheDir() {
  if (const char* dir = std::getenv("BULLET_SIM_CACHE_DIR"); dir && *dir) return dir;
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg)
    return std::string(xdg) + "/bullet_sim/xacro";
  const char* home = std::getenv("HOME");
  return std::string(home && *home ? home : "/tmp") + "/.cache/bullet_sim/xacro";
}

std::string cachedXacro(const std::string& file, const std::vector<std::string>& args,
                        const std::string& cache_dir) {
  const std::string absolute = fs::absolute(file).lexically_normal().string();
  std::string key = absolute;
  for (const auto& arg : args) key += '\0' + arg;
  const char* package_path = std::getenv("ROS_PACKAGE_PATH");
  key += '\0' + std::string(package_path ? package_path : "");
  std::ostringstream name;
  name << std::hex << stableHash(key);
  // One file per entry: the stamps, a blank line, then the URDF; written whole, so never half old, half new.
  const fs::path entry = fs::path(cache_dir) / (name.str() + ".urdf");
  const std::string cached = readAll(entry);
  const size_t split = cached.find("\n\n");
  if (split != std::string::npos) {
    const std::string recorded = cached.substr(0, split + 1);
    const auto files = stampedFiles(recorded);
    if (!files.empty() && files.front() == absolute && stamps(files) == recorded)
      return cached.substr(split + 2);
  }
  std::vector<std::string> files = {absolute};
  const std::string before = stamps(files);
  std::string urdf = expandXacro(absolute, args);
  bool ok = false;
  const std::vector<std::string> included = dependencies(absolute, args, &ok);
  files.insert(files.end(), included.begin(), included.end());
  const std::string now = stamps(files);
  // Nothing is kept when a file changed while xacro read it, or when xacro cannot list what it reads.
  if (!ok || now.empty() || now.rfind(before, 0) != 0) return urdf;
  std::error_code ec;
  fs::create_directories(cache_dir, ec);
  if (!ec) writeAtomically(entry, now + "\n" + urdf);
  return urdf;
}

}  // namespace bullet_sim
