// Names as ROS spells them (namespaces, topics and frames), and lists of names in messages.
#pragma once

#include <string>
#include <vector>

namespace bullet_sim {

/// `text` without its leading and trailing slashes: "/a/b/" -> "a/b".
std::string withoutSlashes(std::string text);

/// "a, b, c"; `none` when there are none.
std::string joinedNames(const std::vector<std::string>& names, const std::string& none = "");
/// The items with `separator` between them: joined({"a", "b"}, "; ") is "a; b"; "" when there are none.
std::string joined(const std::vector<std::string>& items, const std::string& separator);

}  // namespace bullet_sim
