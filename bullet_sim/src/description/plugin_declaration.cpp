#include "bullet_sim/description/plugin_declaration.h"

namespace bullet_sim {

std::string PluginDeclaration::where() const {
  return sensor ? "sensor [" + sensor->name + "] on link [" + sensor->link + "]" : "plugin [" + name + "]";
}

}  // namespace bullet_sim
