#include "bullet_sim/common/names.h"

namespace bullet_sim {

std::string withoutSlashes(std::string text) {
  while (!text.empty() && text.front() == '/') text.erase(text.begin());
  while (!text.empty() && text.back() == '/') text.pop_back();
  return text;
}

std::string joinedNames(const std::vector<std::string>& names, const std::string& none) {
  const std::string text = joined(names, ", ");
  return text.empty() ? none : text;
}

std::string joined(const std::vector<std::string>& items, const std::string& separator) {
  std::string text;
  for (size_t k = 0; k < items.size(); ++k) text += (k == 0 ? "" : separator) + items[k];
  return text;
}

}  // namespace bullet_sim
