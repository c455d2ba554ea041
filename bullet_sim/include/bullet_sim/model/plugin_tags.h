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

/// Reads a plugin's or sensor's child tags. Problems go to `diagnostics`, naming `where` and the tag;
/// finish() warns once about each tag nothing read (Gazebo ignores unknown tags silently).
class PluginTags {
 public:
  /// `element` may be nullptr: every tag is then absent.
  PluginTags(const TagNode* element, std::string where, Diagnostics& diagnostics);

  bool has(const std::string& tag) const;
  /// The tag's text. A topic tag (named ...Topic, ...TopicName, topicName or ..._topic) must not be empty:
  /// ROS has no topic of that name, so Gazebo's plugin fails to load; that is an error.
  std::string text(const std::string& tag, const std::string& fallback);
  /// A tf frame or link name. A leading '/' is dropped: tf2 frame ids have none, and Gazebo's plugins drop it
  /// too (tf::resolve) where `gazebo_drops_slash`; where they keep it, a warning says it is dropped.
  std::string frame(const std::string& tag, const std::string& fallback, bool gazebo_drops_slash = true);
  double number(const std::string& tag, double fallback);
  /// A number that must be > 0 (or >= 0 with `allow_zero`).
  double positive(const std::string& tag, double fallback, bool allow_zero = false);
  /// A positive number that Gazebo takes at any size, but that is absurd above `limit` (a torque of 1e308):
  /// above it, a warning names the value and `limit_name`, and `limit` is used.
  double capped(const std::string& tag, double fallback, double limit, const char* limit_name,
                const std::string& unit);
  bool flag(const std::string& tag, bool fallback);
  /// A comma- or space-separated list.
  std::vector<std::string> list(const std::string& tag);
  /// Marks tags as known but not modelled: no warning.
  void accept(std::initializer_list<const char*> tags);
  /// Warns about the tags nothing read.
  void finish();

  Diagnostics& diagnostics() { return diagnostics_; }
  const std::string& where() const { return where_; }

 private:
  const TagNode* find(const std::string& tag);

  const TagNode* element_;
  std::string where_;
  Diagnostics& diagnostics_;
  std::set<std::string> read_;
};

}  // namespace bullet_sim
