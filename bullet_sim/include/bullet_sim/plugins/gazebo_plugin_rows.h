// Tag rows that several gazebo_plugins share, for their plugins' tag tables.
#pragma once

#include <initializer_list>

#include "bullet_sim/model/plugin_tags.h"

namespace bullet_sim {

/// `own` rows, then the tags gazebo_plugins' p3d and imu plugins leave unread: the misspelt xyzOffsets and
/// rpyOffsets that tutorials carry, and older versions' alwaysOn.
TagTable withUnreadTutorialTags(std::initializer_list<TagRow> own);

}  // namespace bullet_sim
