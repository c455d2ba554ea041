#include "bullet_sim/model/plugin_declaration.h"

#include <sstream>

#include "bullet_sim/model/model.h"

namespace bullet_sim {

std::string PluginDeclaration::where() const {
  return sensor ? "sensor [" + sensor->name + "] on link [" + sensor->link + "]" : "plugin [" + name + "]";
}

std::string frameLink(const DeclarationSource& source, const std::string& tag, const std::string& frame,
                      const std::string& fallback) {
  return frameLink(source.model, source.tags.where(), tag, frame, fallback, source.diagnostics);
}

std::string frameLink(const ModelSpec& model, const std::string& where, const std::string& tag,
                      const std::string& frame, const std::string& fallback, Diagnostics& diagnostics) {
  if (model.link(frame)) return frame;
  diagnostics.warning(where + " <" + tag + "> [" + frame + "] is not a link of the robot" +
                      didYouMean(frame, model.linkNames()) +
                      ": messages carry it as their frame_id all the same, as Gazebo's do" +
                      (fallback.empty() ? "" : "; link [" + fallback + "] is measured instead"));
  return fallback;
}

double sensorUpdateRate(double hz, const std::string& where, Diagnostics& diagnostics) {
  if (!(hz < 0)) return hz;
  std::ostringstream message;
  message << where << "<update_rate> " << hz << " is below 0: read as 0, every step, as Gazebo does";
  diagnostics.warning(message.str());
  return 0;
}

}  // namespace bullet_sim
