// The tags of a <plugin> or <sensor>, read once at load by the plugin's config parser. The URDF reader turns
// its elements into plain TagNodes, so no XML library reaches a plugin or this API.
#pragma once

#include <initializer_list>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "bullet_sim/common/diagnostics.h"

namespace bullet_sim {

/// An element as plain data: its name, attributes, trimmed text and children, and the line it came from.
struct TagNode {
  std::string name;
  std::map<std::string, std::string> attributes;
  std::string text;  ///< without leading and trailing white space
  std::vector<TagNode> children;
  int line = 0;

  /// The first child named `tag`, or nullptr.
  const TagNode* child(const std::string& tag) const;
  /// The end of a path of first children (e.g. {"ray", "scan", "horizontal"}), or nullptr.
  const TagNode* find(std::initializer_list<const char*> path) const;
  /// The attribute's value, or "" when it is absent.
  std::string attribute(const std::string& key) const;
};

/// How a tag's text is read, as a plugin's reference page names it.
enum class TagType { kText, kTopic, kFrame, kNumber, kPositive, kRate, kDeviation, kFlag, kList, kIgnored };

/// "text", "topic", "frame", "number", "number >= 0", "number (< 0: as 0)" (a rate), "number (< 0: as its
/// absolute value)" (a standard deviation), "true/false", "list" or "ignored".
const char* tagTypeName(TagType type);

/// One row of a plugin's tag table: its reference page shows it, and its parser reads the tag through it.
struct TagRow {
  std::string name;
  TagType type = TagType::kText;
  /// the default as the reference shows it ("" for none); parsed when the reader gives none
  std::string fallback;
  std::string unit;      ///< "m", "Hz", ...; "" for none
  std::string gazebo;    ///< what Gazebo's plugin does with it
  std::string ours;      ///< what bullet_sim does where it differs; "" when it does the same
};

/// A plugin's tags, in the order its reference page lists them.
class TagTable {
 public:
  TagTable() = default;
  TagTable(std::initializer_list<TagRow> rows) : rows_(rows) {}

  const std::vector<TagRow>& rows() const { return rows_; }
  /// The row of that tag, or nullptr.
  const TagRow* row(const std::string& name) const;
  /// Adds a row, or replaces the one of the same name.
  void add(TagRow row);

 private:
  std::vector<TagRow> rows_;
};

/// Reads a plugin's or sensor's child tags. Problems go to `diagnostics`, naming `where` and the tag;
/// finish() warns once about each tag nothing read (Gazebo ignores unknown tags silently).
///
/// With a tag table, the table is the list of what the parser may read: reading a tag it lacks, or through a
/// reader of another type, is a std::logic_error (a plugin's tests find it); its ignored rows are accepted,
/// and the readers without a fallback take the row's.
class PluginTags {
 public:
  /// `element` may be nullptr: every tag is then absent.
  PluginTags(const TagNode* element, std::string where, Diagnostics& diagnostics);

  /// From now on, reads go through `table`, which must outlive this reader.
  void useTable(const TagTable* table);
  const TagTable* table() const { return table_; }

  bool has(const std::string& tag) const;
  /// The tag's text. A topic tag (named ...Topic, ...TopicName, topicName or ..._topic) must not be empty:
  /// ROS has no topic of that name, so Gazebo's plugin fails to load; that is an error.
  std::string text(const std::string& tag, const std::string& fallback);
  /// A tf frame or link name. A leading '/' is dropped: tf2 frame ids have none, and Gazebo's plugins drop it
  /// too (tf::resolve) where `gazebo_drops_slash`; where they keep it, a warning says it is dropped. Either
  /// way the frame is remembered as global (globalFrames): tf::resolve gives it no tf_prefix.
  std::string frame(const std::string& tag, const std::string& fallback, bool gazebo_drops_slash = true);
  double number(const std::string& tag, double fallback);
  /// A number that must be > 0 (or >= 0 with `allow_zero`).
  double positive(const std::string& tag, double fallback, bool allow_zero = false);
  /// A positive number that Gazebo takes at any size, but that is absurd above `limit` (a torque of 1e308):
  /// above it, a warning names the value and `limit_name`, and `limit` is used.
  double capped(const std::string& tag, double fallback, double limit, const char* limit_name,
                const std::string& unit);
  /// A motor's torque or force limit, which Gazebo takes at any value: as capped(), but one not above 0 is
  /// 0, with a warning that the motor gives nothing (Gazebo's ODE drives no motor with such a limit).
  double motorLimit(const std::string& tag, double fallback, double limit, const char* limit_name,
                    const std::string& unit);
  /// An update rate [Hz]. Gazebo's plugins take any: each updates at every world (or sensor) update when its
  /// rate is not above 0, so one below 0 is read as 0, with a warning naming it.
  double rate(const std::string& tag, double fallback);
  /// A noise's standard deviation. Gazebo's noise takes any sign (it draws sigma * z + mu, z standard
  /// normal), so a negative one is read as its absolute value, with a warning naming it.
  double deviation(const std::string& tag, double fallback);
  bool flag(const std::string& tag, bool fallback);
  /// The same readers with the table row's fallback.
  std::string text(const std::string& tag);
  double number(const std::string& tag);
  double positive(const std::string& tag);     ///< > 0
  double nonNegative(const std::string& tag);  ///< >= 0
  double rate(const std::string& tag);
  double deviation(const std::string& tag);
  bool flag(const std::string& tag);
  /// A comma- or space-separated list.
  std::vector<std::string> list(const std::string& tag);
  /// Marks tags as known but not modelled: no warning.
  void accept(std::initializer_list<const char*> tags);
  /// Warns about the tags nothing read.
  void finish();
  /// The frames read with a leading '/', without it: they take no tf_prefix.
  const std::set<std::string>& globalFrames() const { return global_frames_; }

  Diagnostics& diagnostics() { return diagnostics_; }
  const std::string& where() const { return where_; }

 private:
  const TagNode* find(const std::string& tag);
  /// The table's row of `tag` after checking that it is read as `type`; nullptr without a table.
  const TagRow* checkedRow(const std::string& tag, std::initializer_list<TagType> types) const;
  double rowNumber(const std::string& tag, std::initializer_list<TagType> types) const;
  std::string rawText(const std::string& tag, const std::string& fallback);
  double rawNumber(const std::string& tag, double fallback);
  /// `value`, or `limit` with a warning when it is above it.
  double cap(const std::string& tag, double value, double limit, const char* limit_name,
             const std::string& unit);

  const TagNode* element_;
  const TagTable* table_ = nullptr;
  std::string where_;
  Diagnostics& diagnostics_;
  std::set<std::string> read_;
  std::set<std::string> global_frames_;
};

}  // namespace bullet_sim
