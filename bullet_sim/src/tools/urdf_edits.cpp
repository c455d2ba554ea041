#include "bullet_sim/tools/urdf_edits.h"

#include <tinyxml2.h>

#include <algorithm>

namespace bullet_sim {

std::string withPluginTag(const std::string& urdf, const std::vector<std::string>& filenames,
                          const std::function<std::string(const std::string& filename)>& tag,
                          const std::string& text, int* plugins) {
  int found = 0;
  tinyxml2::XMLDocument document;
  if (document.Parse(urdf.c_str(), urdf.size()) != tinyxml2::XML_SUCCESS || !document.RootElement())
    return urdf;
  for (auto* gazebo = document.RootElement()->FirstChildElement("gazebo"); gazebo;
       gazebo = gazebo->NextSiblingElement("gazebo")) {
    for (auto* plugin = gazebo->FirstChildElement("plugin"); plugin;
         plugin = plugin->NextSiblingElement("plugin")) {
      const std::string filename = plugin->Attribute("filename") ? plugin->Attribute("filename") : "";
      if (std::find(filenames.begin(), filenames.end(), filename) == filenames.end()) continue;
      const std::string name = tag(filename);
      if (name.empty()) continue;
      tinyxml2::XMLElement* element = plugin->FirstChildElement(name.c_str());
      (element ? element : plugin->InsertNewChildElement(name.c_str()))->SetText(text.c_str());
      ++found;
    }
  }
  if (plugins) *plugins = found;
  tinyxml2::XMLPrinter printer;
  document.Print(&printer);
  return printer.CStr();
}

std::string withEffortLimit(const std::string& urdf, const std::vector<std::string>& joints, double effort) {
  tinyxml2::XMLDocument document;
  if (document.Parse(urdf.c_str(), urdf.size()) != tinyxml2::XML_SUCCESS || !document.RootElement())
    return urdf;
  for (auto* joint = document.RootElement()->FirstChildElement("joint"); joint;
       joint = joint->NextSiblingElement("joint")) {
    const char* name = joint->Attribute("name");
    if (!name || std::find(joints.begin(), joints.end(), name) == joints.end()) continue;
    tinyxml2::XMLElement* limit = joint->FirstChildElement("limit");
    if (!limit) {
      limit = joint->InsertNewChildElement("limit");
      limit->SetAttribute("velocity", 0.0);
    }
    limit->SetAttribute("effort", effort);
  }
  tinyxml2::XMLPrinter printer;
  document.Print(&printer);
  return printer.CStr();
}

std::string withWheelModel(const std::string& urdf, const std::string& wheel_model, int* drives) {
  return withPluginTag(
      urdf,
      {"libgazebo_ros_diff_drive.so", "libgazebo_ros_skid_steer_drive.so",
       "libgazebo_ros_ackermann_drive.so"},
      [](const std::string&) { return "wheelModel"; }, wheel_model, drives);
}

}  // namespace bullet_sim
