#include "model/world_copies.h"

#include <cmath>
#include <map>
#include <set>
#include <sstream>

namespace bullet_sim {

namespace {

/// Prints compactly, but each element on the line it was read from (what it replaces leaves blank lines).
class LineKeepingPrinter : public tinyxml2::XMLPrinter {
 public:
  LineKeepingPrinter() : tinyxml2::XMLPrinter(nullptr, /*compact=*/true) {}

  bool VisitEnter(const tinyxml2::XMLElement& element, const tinyxml2::XMLAttribute* attribute) override {
    SealElementIfJustOpened();
    const char* text = CStr();
    for (const int size = CStrSize() - 1; counted_ < size; ++counted_) line_ += text[counted_] == '\n';
    for (; line_ < element.GetLineNum(); ++line_, ++counted_) Putc('\n');
    return tinyxml2::XMLPrinter::VisitEnter(element, attribute);
  }

 private:
  int line_ = 1;     ///< of the end of what is printed
  int counted_ = 0;  ///< characters of it whose newlines are counted
};

/// A pose as SDF writes it: x y z roll pitch yaw [m, rad], the rotation about fixed x, then y, then z.
std::optional<Eigen::Isometry3d> sdfPose(const tinyxml2::XMLElement* pose) {
  if (!pose) return Eigen::Isometry3d::Identity();
  if (pose->FirstAttribute() || pose->FirstChildElement()) return std::nullopt;  // relative_to, degrees...
  std::istringstream in(pose->GetText() ? pose->GetText() : "");
  in.imbue(std::locale::classic());
  double v[6];
  for (double& value : v) {
    if (!(in >> value) || !std::isfinite(value)) return std::nullopt;
  }
  std::string rest;
  if (in >> rest) return std::nullopt;
  Eigen::Isometry3d result = Eigen::Isometry3d::Identity();
  result.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
  result.linear() =
      (Eigen::AngleAxisd(v[5], Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(v[4], Eigen::Vector3d::UnitY()) *
       Eigen::AngleAxisd(v[3], Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  return result;
}

/// A <model> or <include> of the world that could be a copy: its name, pose, and contents without them.
struct Candidate {
  tinyxml2::XMLElement* element;
  std::string name;
  Eigen::Isometry3d pose;
  std::string contents;
};

std::optional<Candidate> candidate(tinyxml2::XMLElement& element) {
  const std::string kind = element.Name();
  const bool is_model = kind == "model";
  if (!is_model && kind != "include") return std::nullopt;
  const tinyxml2::XMLElement* name_element = element.FirstChildElement("name");
  const char* name = is_model ? element.Attribute("name") : name_element ? name_element->GetText() : nullptr;
  // A placement frame changes what the pose means; an include without a name takes its model's.
  if (!name || element.Attribute("placement_frame") || element.FirstChildElement("placement_frame"))
    return std::nullopt;
  const std::optional<Eigen::Isometry3d> pose = sdfPose(element.FirstChildElement("pose"));
  if (!pose) return std::nullopt;
  tinyxml2::XMLDocument scratch;
  tinyxml2::XMLElement* contents = element.DeepClone(&scratch)->ToElement();
  contents->DeleteAttribute("name");
  for (const char* tag : {"name", "pose"}) {
    if (tinyxml2::XMLElement* child = contents->FirstChildElement(tag);
        child && (tag != std::string("name") || !is_model))
      contents->DeleteChild(child);
  }
  tinyxml2::XMLPrinter printer(nullptr, /*compact=*/true);
  contents->Accept(&printer);
  return Candidate{&element, name, *pose, printer.CStr()};
}

}  // namespace

std::optional<WorldCopies> findCopies(tinyxml2::XMLDocument& document) {
  tinyxml2::XMLElement* sdf = document.RootElement();
  tinyxml2::XMLElement* world = sdf ? sdf->FirstChildElement("world") : nullptr;
  if (!world || world->NextSiblingElement("world")) return std::nullopt;
  std::set<std::string> names;
  std::map<std::string, std::string> first_of;            // contents -> the name of the first model with them
  std::vector<std::pair<Candidate, std::string>> copies;  // with the name of the model they repeat
  for (tinyxml2::XMLElement* child = world->FirstChildElement(); child; child = child->NextSiblingElement()) {
    std::optional<Candidate> found = candidate(*child);
    if (!found) continue;
    if (!names.insert(found->name).second) return std::nullopt;
    const auto [first, is_new] = first_of.emplace(found->contents, found->name);
    if (!is_new) copies.emplace_back(std::move(*found), first->second);
  }
  if (copies.empty()) return std::nullopt;
  WorldCopies result;
  for (auto& [copy, original] : copies) {
    result.copies.push_back({copy.name, original, copy.pose, copy.element->GetLineNum()});
    world->DeleteChild(copy.element);
  }
  LineKeepingPrinter printer;
  document.Accept(&printer);
  result.reduced_text = printer.CStr();
  return result;
}

void addCopies(const WorldCopies& copies, const Limits& limits, WorldSpec& world, Diagnostics& diagnostics) {
  std::map<std::string, size_t> index;
  for (size_t i = 0; i < world.models.size(); ++i) index[world.models[i].name] = i;
  world.models.reserve(world.models.size() + copies.copies.size());
  std::map<std::string, std::vector<std::string>> left_out;  // original -> its copies, when it is not loaded
  for (const WorldCopies::Copy& copy : copies.copies) {
    const auto original = index.find(copy.original);
    if (original == index.end()) {  // refused (the file is then read again in full) or skipped with a warning
      left_out[copy.original].push_back(copy.name);
      continue;
    }
    const Eigen::Vector3d position = copy.pose.translation();
    if (position.cwiseAbs().maxCoeff() > limits.max_length) {
      std::ostringstream message;
      message << "[" << world.source << ":" << copy.line << "] model [" << copy.name << "]: its position ["
              << position.transpose() << "] m is beyond the limit of " << limits.max_length
              << " m (max_length)";
      diagnostics.error(message.str());
      continue;
    }
    WorldModelSpec model = world.models[original->second];
    const std::string scope = model.name + "::";  // of its collisions' Gazebo names
    for (Collision& collision : model.collisions) {
      if (collision.name.rfind(scope, 0) == 0)
        collision.name = copy.name + "::" + collision.name.substr(scope.size());
    }
    model.name = copy.name;
    model.pose = copy.pose;
    world.models.push_back(std::move(model));
  }
  for (const auto& [original, names] : left_out) {
    std::string list;
    for (const auto& name : names) list += (list.empty() ? "[" : ", [") + name + "]";
    diagnostics.warning("models " + list + " repeat [" + original +
                        "], which is skipped: they are skipped too");
  }
  size_t shapes = 0, triangles = 0;
  for (const WorldModelSpec& model : world.models) {
    shapes += model.collisions.size() + model.visuals.size();
    for (const Collision& collision : model.collisions)
      triangles += collision.shape.mesh ? collision.shape.mesh->triangles.size() : 0;
    for (const Visual& visual : model.visuals)
      triangles += visual.shape.mesh ? visual.shape.mesh->triangles.size() : 0;
  }
  if (shapes > limits.max_world_shapes) {
    diagnostics.error(
        "the world has more than " + std::to_string(limits.max_world_shapes) +
        " collisions and visuals, the limit (max_world_shapes): is it generated by mistake? Raise "
        "the limit if it is meant");
  }
  if (triangles > limits.max_triangles) {
    diagnostics.error("the world's meshes have " + std::to_string(triangles) +
                      " triangles, above the limit of " + std::to_string(limits.max_triangles) +
                      " (max_triangles)");
  }
}

}  // namespace bullet_sim
