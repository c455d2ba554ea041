// Names as ROS spells them: namespaces, topics and frames.
#pragma once

#include <string>

namespace bullet_sim {

/// `text` without its leading and trailing slashes: "/a/b/" -> "a/b".
std::string withoutSlashes(std::string text);

}  // namespace bullet_sim
