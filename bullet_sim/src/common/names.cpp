#include "bullet_sim/common/names.h"

namespace bullet_sim {

std::string withoutSlashes(std::string text) {
  while (!text.empty() && text.front() == '/') text.erase(text.begin());
  while (!text.empty() && text.back() == '/') text.pop_back();
  return text;
}

}  // namespace bullet_sim
