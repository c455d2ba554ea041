#include "model/sdf9_values.h"

#include <Eigen/Core>

#include <cctype>
#include <iomanip>
#include <optional>
#include <sstream>
#include <utility>

#include "bullet_sim/model/model.h"

namespace bullet_sim {

namespace {

/// Whether `element` is a <mu> or <mu2> of a <surface><friction><ode>.
bool isSurfaceMu(const tinyxml2::XMLElement& element) {
  const std::string name = element.Name();
  if (name != "mu" && name != "mu2") return false;
  const tinyxml2::XMLNode* node = &element;
  for (const char* parent : {"ode", "friction", "surface"}) {
    node = node->Parent();
    const tinyxml2::XMLElement* above = node ? node->ToElement() : nullptr;
    if (!above || std::string(above->Name()) != parent) return false;
  }
  return true;
}

/// The offset in `text` where line `line` (from 1) starts, or npos.
size_t lineStart(const std::string& text, int line) {
  size_t offset = 0;
  for (int i = 1; i < line && offset != std::string::npos; ++i) {
    offset = text.find('\n', offset);
    if (offset != std::string::npos) ++offset;
  }
  return offset;
}

/// Replaces the value `value` of the first <`name`> at or after `from` in `text` with `replacement`.
/// Returns whether it found it.
bool replaceValue(std::string& text, size_t from, const std::string& name, const std::string& value,
                  const std::string& replacement) {
  for (size_t tag = text.find("<" + name, from); tag != std::string::npos;
       tag = text.find("<" + name, tag + 1)) {
    const char after = text[tag + 1 + name.size()];
    if (after != '>' && !std::isspace(static_cast<unsigned char>(after))) continue;
    size_t start = text.find('>', tag);
    if (start == std::string::npos) return false;
    ++start;
    while (start < text.size() && std::isspace(static_cast<unsigned char>(text[start]))) ++start;
    if (text.compare(start, value.size(), value) != 0) continue;
    text.replace(start, value.size(), replacement);
    return true;
  }
  return false;
}

/// Whether `element` is the <xyz> of a joint's <axis> or <axis2>.
bool isAxisXyz(const tinyxml2::XMLElement& element) {
  const tinyxml2::XMLElement* axis = element.Parent() ? element.Parent()->ToElement() : nullptr;
  const tinyxml2::XMLElement* joint = axis && axis->Parent() ? axis->Parent()->ToElement() : nullptr;
  return std::string(element.Name()) == "xyz" && joint && std::string(joint->Name()) == "joint" &&
         (std::string(axis->Name()) == "axis" || std::string(axis->Name()) == "axis2");
}

std::string numbersText(const Eigen::Vector3d& v, int precision = 6) {
  std::ostringstream out;
  out << std::setprecision(precision) << v.x() << " " << v.y() << " " << v.z();
  return out.str();
}

/// What a negative mu is rewritten as, and what the warning says of it; nullopt for any other value.
std::optional<std::pair<std::string, std::string>> unlimitedMu(const tinyxml2::XMLElement& element,
                                                               const std::string& value) {
  double number = 0;
  if (!isSurfaceMu(element) || element.QueryDoubleText(&number) != tinyxml2::XML_SUCCESS || !(number < 0))
    return std::nullopt;
  std::ostringstream unlimited;
  unlimited << std::setprecision(10) << SurfaceSpec::kUnlimitedMu;
  const std::string tag = "<surface><friction><ode><" + std::string(element.Name()) + ">";
  return std::pair{unlimited.str(), tag + " [" + value + "] is negative: " + SurfaceSpec::kNegativeMuReading};
}

/// What a tiny axis is rewritten as, and what the warning says of it; nullopt for any other value.
std::optional<std::pair<std::string, std::string>> directedAxis(const tinyxml2::XMLElement& element,
                                                                const std::string& value) {
  Eigen::Vector3d axis;
  std::istringstream in(value);
  if (!isAxisXyz(element) || !(in >> axis.x() >> axis.y() >> axis.z())) return std::nullopt;
  const double length = axis.stableNorm();
  if (!(length > 0 && length <= kShortestAxis)) return std::nullopt;
  axis.stableNormalize();
  const tinyxml2::XMLElement& joint = *element.Parent()->Parent()->ToElement();
  std::ostringstream warning;
  warning << "joint [" << (joint.Attribute("name") ? joint.Attribute("name") : "") << "] <"
          << element.Parent()->ToElement()->Name() << "><xyz> [" << value << "] is " << length
          << " long, which sdformat 12 calls zero: read as its direction, " << numbersText(axis)
          << ", as Gazebo's ODE normalizes it";
  return std::pair{numbersText(axis, 17), warning.str()};
}

void visit(const tinyxml2::XMLElement& element, const std::string& source, std::string& text,
           std::vector<std::string>& warnings) {
  if (element.GetText()) {
    std::string value = element.GetText();
    value.erase(0, value.find_first_not_of(" \t\r\n"));
    value.erase(value.find_last_not_of(" \t\r\n") + 1);
    auto rewrite = unlimitedMu(element, value);
    if (!rewrite) rewrite = directedAxis(element, value);
    if (rewrite &&
        replaceValue(text, lineStart(text, element.GetLineNum()), element.Name(), value, rewrite->first)) {
      warnings.push_back("[" + source + ":" + std::to_string(element.GetLineNum()) + "] " + rewrite->second);
    }
  }
  for (auto* child = element.FirstChildElement(); child; child = child->NextSiblingElement())
    visit(*child, source, text, warnings);
}

}  // namespace

std::vector<std::string> rewriteSdf9Values(const tinyxml2::XMLDocument& document, const std::string& source,
                                           std::string& text) {
  std::vector<std::string> warnings;
  if (const tinyxml2::XMLElement* root = document.RootElement()) visit(*root, source, text, warnings);
  return warnings;
}

}  // namespace bullet_sim
