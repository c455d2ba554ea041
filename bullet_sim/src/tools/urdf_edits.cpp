#include "bullet_sim/tools/urdf_edits.h"

#include <tinyxml2.h>

namespace bullet_sim {

std::string withWheelModel(const std::string& urdf, const std::string& wheel_model, int* drives) {
  int found = 0;
  tinyxml2::XMLDocument document;
  if (document.Parse(urdf.c_str(), urdf.size()) != tinyxml2::XML_SUCCESS || !document.RootElement()) return urdf;
  for (auto* gazebo = document.RootElement()->FirstChildElement("gazebo"); gazebo;
       gazebo = gazebo->NextSiblingElement("gazebo")) {
    for (auto* plugin = gazebo->FirstChildElement("plugin"); plugin; plugin = plugin->NextSiblingElement("plugin")) {
      const std::string name = plugin->Attribute("filename") ? plugin->Attribute("filename") : "";
      if (name != "libgazebo_ros_diff_drive.so" && name != "libgazebo_ros_skid_steer_drive.so" &&
          name != "libgazebo_ros_ackermann_drive.so") {
        continue;
      }
      tinyxml2::XMLElement* tag = plugin->FirstChildElement("wheelModel");
      (tag ? tag : plugin->InsertNewChildElement("wheelModel"))->SetText(wheel_model.c_str());
      ++found;
    }
  }
  if (drives) *drives = found;
  tinyxml2::XMLPrinter printer;
  document.Print(&printer);
  return printer.CStr();
}

}  // namespace bullet_sim
