#include "bullet_sim/plugins/gazebo_plugin_rows.h"

namespace bullet_sim {

TagTable withUnreadTutorialTags(std::initializer_list<TagRow> own) {
  TagTable table(own);
  table.add({"xyzOffsets", TagType::kIgnored, "", "m",
             "not read (a misspelling of xyzOffset that tutorials carry)", ""});
  table.add({"rpyOffsets", TagType::kIgnored, "", "rad",
             "not read (a misspelling of rpyOffset that tutorials carry)", ""});
  table.add({"alwaysOn", TagType::kIgnored, "", "", "not read (a tag of older gazebo_plugins)", ""});
  return table;
}

}  // namespace bullet_sim
