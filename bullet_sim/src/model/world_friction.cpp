#include "model/world_friction.h"

#include <cctype>
#include <iomanip>
#include <sstream>

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

void visit(const tinyxml2::XMLElement& element, const std::string& source, std::string& text,
           std::vector<std::string>& warnings) {
  if (isSurfaceMu(element) && element.GetText()) {
    std::string value = element.GetText();
    value.erase(0, value.find_first_not_of(" \t\r\n"));
    value.erase(value.find_last_not_of(" \t\r\n") + 1);
    double number = 0;
    std::ostringstream unlimited;
    unlimited << std::setprecision(10) << SurfaceSpec::kUnlimitedMu;
    if (element.QueryDoubleText(&number) == tinyxml2::XML_SUCCESS && number < 0 &&
        replaceValue(text, lineStart(text, element.GetLineNum()), element.Name(), value, unlimited.str())) {
      warnings.push_back("[" + source + ":" + std::to_string(element.GetLineNum()) + "] <surface><friction>"
                         "<ode><" + element.Name() + "> [" + value + "] is negative: " +
                         SurfaceSpec::kNegativeMuReading);
    }
  }
  for (auto* child = element.FirstChildElement(); child; child = child->NextSiblingElement())
    visit(*child, source, text, warnings);
}

}  // namespace

std::vector<std::string> unlimitNegativeMu(const tinyxml2::XMLDocument& document, const std::string& source,
                                           std::string& text) {
  std::vector<std::string> warnings;
  if (const tinyxml2::XMLElement* root = document.RootElement()) visit(*root, source, text, warnings);
  return warnings;
}

}  // namespace bullet_sim
