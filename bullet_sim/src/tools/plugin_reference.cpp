// plugin_reference PLUGINS_DIR OUT_DIR: the docs site's plugin reference. For every Gazebo plugin filename
// the registry accepts it writes OUT_DIR/<filename without .so>.md: the prose of its folder's README.md, and
// the table of the tags its parser reads, from the same tag table the parser reads through (so the page
// cannot drift from the code); and OUT_DIR/index.md, the list of them. ROS-free; scripts/docs.sh runs it.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "bullet_sim/common/names.h"
#include "bullet_sim/plugins/registry.h"
#include "tools/command_line.h"

namespace bullet_sim {
namespace {

namespace fs = std::filesystem;

constexpr char kUsage[] =
    "usage: plugin_reference PLUGINS_DIR OUT_DIR\n"
    "\n"
    "Writes the docs site's plugin reference into OUT_DIR: one page per Gazebo plugin filename bullet_sim\n"
    "accepts (OUT_DIR/<filename without .so>.md), made of the prose in PLUGINS_DIR/<folder>/README.md\n"
    "and the table of its tags (name, type, default, unit, what Gazebo does, what bullet_sim does)\n"
    "generated from the tag table its parser reads through; and OUT_DIR/index.md, which lists them.\n"
    "Pages of filenames no longer registered are not removed.\n"
    "Exit status: 0 written, 1 a page could not be written, 2 usage.\n";

struct Options {
  bool help = false;
  std::vector<std::string> dirs;  // PLUGINS_DIR, OUT_DIR
};

Options parse(int argc, char** argv) {
  Options options;
  const ToolOption positional{"DIR", [&](const std::string& word) { options.dirs.push_back(word); }, true};
  parseCommandLine(argc, argv, {}, &options.help, &positional);
  if (!options.help && options.dirs.size() != 2) throw UsageError("give PLUGINS_DIR and OUT_DIR");
  return options;
}

/// A folder's README.md cut at its first "## " heading: the title (its "# " line's text), the introduction
/// before the first section, and the sections.
struct Prose {
  std::string title, introduction, sections;
};

Prose readProse(const fs::path& readme) {
  std::ifstream file(readme);
  if (!file) {
    return {"", "No prose yet: `" + readme.parent_path().filename().string() + "/README.md` is missing.\n",
            ""};
  }
  Prose prose;
  std::string line;
  bool in_sections = false, in_code = false;
  while (std::getline(file, line)) {
    if (line.rfind("```", 0) == 0) in_code = !in_code;
    if (!in_code && prose.title.empty() && line.rfind("# ", 0) == 0) {
      prose.title = line.substr(2);
      continue;
    }
    if (!in_code && line.rfind("## ", 0) == 0) in_sections = true;
    (in_sections ? prose.sections : prose.introduction) += line + "\n";
  }
  return prose;
}

/// `text` as one Markdown table cell: no line breaks, '|' escaped, and outside `code` '<' and '>' as entities
/// (a tag's name such as <update_rate> would read as HTML and vanish).
std::string cell(const std::string& text) {
  std::string out;
  bool code = false;
  for (char c : text) {
    if (c == '`') code = !code;
    if (c == '|') out += "\\|";
    else if (c == '\n') out += ' ';
    else if (!code && c == '<') out += "&lt;";
    else if (!code && c == '>') out += "&gt;";
    else out += c;
  }
  return out;
}

/// `text` without the blank lines around it, ending in one line break ("" stays "").
std::string trimmed(const std::string& text) {
  const size_t begin = text.find_first_not_of('\n');
  if (begin == std::string::npos) return "";
  return text.substr(begin, text.find_last_not_of('\n') - begin + 1) + "\n";
}

std::string code(const std::string& text) { return text.empty() ? "" : "`" + text + "`"; }

std::string pageName(const std::string& filename) {
  const std::string suffix = ".so";
  const bool so = filename.size() > suffix.size() && filename.compare(filename.size() - 3, 3, suffix) == 0;
  return so ? filename.substr(0, filename.size() - 3) : filename;
}

/// "as a model plugin", or "on a <sensor type="ray"> or <sensor type="gpu_ray">".
std::string servedAs(const PluginType& type) {
  if (type.sensor_types.empty()) return "as a model plugin";
  std::string text = "on a";
  for (size_t i = 0; i < type.sensor_types.size(); ++i)
    text += std::string(i ? " or" : "") + " `<sensor type=\"" + type.sensor_types[i] + "\">`";
  return text;
}

std::string tagTable(const PluginType& type) {
  std::ostringstream out;
  out << "| tag | type | default | unit | Gazebo | bullet_sim |\n|---|---|---|---|---|---|\n";
  for (const TagRow& row : type.tags.rows()) {
    out << "| " << code(row.name) << " | " << tagTypeName(row.type) << " | " << cell(code(row.fallback))
        << " | " << cell(row.unit) << " | " << cell(row.gazebo) << " | "
        << (row.ours.empty() ? "the same" : cell(row.ours)) << " |\n";
  }
  return out.str();
}

/// The other filenames its folder registers, as links to their pages.
std::string siblings(const PluginRegistry& registry, const PluginType& type) {
  std::vector<std::string> names;
  for (const PluginType& other : registry.types())
    if (other.folder == type.folder && other.filename != type.filename) names.push_back(other.filename);
  std::sort(names.begin(), names.end());
  names.erase(std::unique(names.begin(), names.end()), names.end());
  for (std::string& name : names) name = "[`" + name + "`](" + pageName(name) + ".md)";
  return names.empty() ? "" : " It also serves " + joinedNames(names) + ".";
}

std::string page(const PluginRegistry& registry, const std::vector<const PluginType*>& types,
                 const Prose& prose) {
  const PluginType& first = *types.front();
  std::ostringstream out;
  out << "<!-- Written by scripts/docs.sh (plugin_reference) from bullet_sim/plugins/" << first.folder
      << "/README.md and the plugin's tag table: edit those, not this page. -->\n"
      << "# `" << first.filename << "`\n\n";
  if (!prose.title.empty()) out << "**" << prose.title << "**\n\n";
  out << trimmed(prose.introduction) << "\nFolder `bullet_sim/plugins/" << first.folder << "/`."
      << siblings(registry, first) << "\n";
  for (const PluginType* type : types) {
    out << "\n## Tags" << (types.size() > 1 ? " " + servedAs(*type) : "") << "\n";
    out << "Read " << servedAs(*type) << ", in this order:\n\n" << tagTable(*type);
  }
  if (!prose.sections.empty()) out << "\n" << trimmed(prose.sections);
  return out.str();
}

void write(const fs::path& path, const std::string& text) {
  std::ofstream file(path);
  file << text;
  if (!file) throw Failure("cannot write [" + path.string() + "]");
}

std::string index(const std::map<std::string, std::vector<const PluginType*>>& by_filename,
                  const std::map<std::string, Prose>& prose) {
  std::ostringstream out;
  out << "<!-- Written by scripts/docs.sh (plugin_reference) from the plugin registry: "
         "edit the plugins' folders, not this page. -->\n"
      << "# Plugins\n\n"
      << "Every Gazebo plugin filename bullet_sim accepts, with the tags it reads. "
         "A `<plugin>` of any other\n"
      << "filename gets one warning naming it and saying it is ignored. "
         "Each page's table is generated from the\n"
      << "tag table the plugin's parser reads through (`rosrun bullet_sim urdf_doctor --list-plugins` lists\n"
      << "them too).\n\n"
      << "| filename | served | what |\n|---|---|---|\n";
  for (const auto& [filename, types] : by_filename) {
    std::string served;
    for (const PluginType* type : types) served += (served.empty() ? "" : "; ") + servedAs(*type);
    const std::string& folder = types.front()->folder;
    const std::string& what = prose.at(folder).title;
    out << "| [`" << filename << "`](" << pageName(filename) << ".md) | " << cell(served) << " | "
        << cell(what.empty() ? "`" + folder + "`" : what) << " |\n";
  }
  return out.str();
}

int run(const Options& options) {
  const fs::path plugins_dir = options.dirs[0], out_dir = options.dirs[1];
  const PluginRegistry& registry = PluginRegistry::builtin();
  std::map<std::string, std::vector<const PluginType*>> by_filename;
  std::map<std::string, Prose> prose;
  for (const PluginType& type : registry.types()) {
    by_filename[type.filename].push_back(&type);
    if (!prose.count(type.folder)) prose[type.folder] = readProse(plugins_dir / type.folder / "README.md");
  }
  fs::create_directories(out_dir);
  for (const auto& [filename, types] : by_filename)
    write(out_dir / (pageName(filename) + ".md"), page(registry, types, prose.at(types.front()->folder)));
  write(out_dir / "index.md", index(by_filename, prose));
  return 0;
}

}  // namespace
}  // namespace bullet_sim

int main(int argc, char** argv) {
  return bullet_sim::toolMain("plugin_reference", bullet_sim::kUsage, argc, argv, bullet_sim::parse,
                              bullet_sim::run);
}
