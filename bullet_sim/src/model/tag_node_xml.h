// The model readers' bridge from tinyxml2 to TagNode, private to src/ so that no public header names an XML
// library.
#pragma once

#include <tinyxml2.h>

#include "bullet_sim/model/plugin_tags.h"

namespace bullet_sim {

/// An XML element (with its children) as a TagNode: the model readers call it once per <plugin> and <sensor>.
TagNode readTagNode(const tinyxml2::XMLElement& element);

}  // namespace bullet_sim
