#include "bullet_sim/common/names.h"

namespace bullet_sim {

std::string withoutSlashes(std::string text) {
  while (!text.empty() && text.front() == '/') text.erase(text.begin());
  while (!text.empty() && text.back() == '/') text.pop_back();
  return text;
}

std::string joinedNames(const std::vector<std::string>& names, const std::string& none) {
  std::string text;
  for (const auto& name : names) text += (text.empty() ? "" : ", ") + name;
  return text.empty() ? none : text;
}

}  // namespace bullet_sim
