#include "model/tag_node_xml.h"

#include <cmath>
#include <sstream>

namespace bullet_sim {

const TagNode* TagNode::child(const std::string& tag) const {
  for (const auto& node : children) {
    if (node.name == tag) return &node;
  }
  return nullptr;
}

const TagNode* TagNode::find(std::initializer_list<const char*> path) const {
  const TagNode* node = this;
  for (const char* tag : path) {
    node = node->child(tag);
    if (!node) return nullptr;
  }
  return node;
}

std::string TagNode::attribute(const std::string& key) const {
  const auto found = attributes.find(key);
  return found == attributes.end() ? "" : found->second;
}

TagNode readTagNode(const tinyxml2::XMLElement& element) {
  TagNode node;
  node.name = element.Name();
  node.line = element.GetLineNum();
  const std::string text = element.GetText() ? element.GetText() : "";
  const auto first = text.find_first_not_of(" \t\n\r");
  const auto last = text.find_last_not_of(" \t\n\r");
  if (first != std::string::npos) node.text = text.substr(first, last - first + 1);
  for (auto* attribute = element.FirstAttribute(); attribute; attribute = attribute->Next())
    node.attributes[attribute->Name()] = attribute->Value();
  for (auto* child = element.FirstChildElement(); child; child = child->NextSiblingElement())
    node.children.push_back(readTagNode(*child));
  return node;
}

PluginTags::PluginTags(const TagNode* element, std::string where, Diagnostics& diagnostics)
    : element_(element), where_(std::move(where)), diagnostics_(diagnostics) {}

const TagNode* PluginTags::find(const std::string& tag) {
  read_.insert(tag);
  return element_ ? element_->child(tag) : nullptr;
}

bool PluginTags::has(const std::string& tag) const { return element_ && element_->child(tag); }

namespace {

bool endsWith(const std::string& text, const std::string& end) {
  return text.size() >= end.size() && text.compare(text.size() - end.size(), end.size(), end) == 0;
}

bool isTopicTag(const std::string& tag) {
  return tag == "topicName" || endsWith(tag, "Topic") || endsWith(tag, "TopicName") ||
         endsWith(tag, "_topic");
}

}  // namespace

std::string PluginTags::text(const std::string& tag, const std::string& fallback) {
  const TagNode* node = find(tag);
  if (!node) return fallback;
  if (node->text.empty() && isTopicTag(tag)) {
    diagnostics_.error(where_ + " <" + tag + "> is empty: give it a topic name" +
                       (fallback.empty() ? "" : " such as [" + fallback + "] (the default)") +
                       ", or leave the tag out");
  }
  return node->text;
}

std::string PluginTags::frame(const std::string& tag, const std::string& fallback, bool gazebo_drops_slash) {
  const std::string value = text(tag, fallback);
  const auto start = value.find_first_not_of('/');
  if (!has(tag) || start == 0 || value.empty()) return value;
  const std::string bare = start == std::string::npos ? "" : value.substr(start);
  if (!gazebo_drops_slash) {
    diagnostics_.warning(where_ + " <" + tag + "> [" + value + "] is read as [" + bare +
                         "]: tf2 frame ids have no leading / (Gazebo's plugin keeps it)");
  }
  return bare;
}

double PluginTags::number(const std::string& tag, double fallback) {
  const TagNode* node = find(tag);
  if (!node) return fallback;
  std::istringstream in(node->text);
  double parsed;
  if (!(in >> parsed) || !std::isfinite(parsed)) {
    diagnostics_.error(where_ + " <" + tag + "> must be a number, not [" + node->text + "]");
    return fallback;
  }
  return parsed;
}

double PluginTags::positive(const std::string& tag, double fallback, bool allow_zero) {
  const double value = number(tag, fallback);
  if (value < 0 || (!allow_zero && value == 0)) {
    std::ostringstream message;
    message << where_ << " <" << tag << "> must be " << (allow_zero ? ">= 0" : "> 0") << ", not " << value;
    diagnostics_.error(message.str());
    return fallback;
  }
  return value;
}

double PluginTags::capped(const std::string& tag, double fallback, double limit, const char* limit_name,
                          const std::string& unit) {
  const double value = positive(tag, fallback);
  if (value <= limit) return value;
  std::ostringstream message;
  message << where_ << " <" << tag << "> " << value << " " << unit << " is above the limit of " << limit
          << " " << unit << " (" << limit_name << "): " << limit << " " << unit << " is used";
  diagnostics_.warning(message.str());
  return limit;
}

bool PluginTags::flag(const std::string& tag, bool fallback) {
  const TagNode* node = find(tag);
  if (!node) return fallback;
  if (node->text == "true" || node->text == "1") return true;
  if (node->text == "false" || node->text == "0") return false;
  diagnostics_.error(where_ + " <" + tag + "> must be true or false, not [" + node->text + "]");
  return fallback;
}

std::vector<std::string> PluginTags::list(const std::string& tag) {
  std::string value = text(tag, "");
  for (char& c : value) {
    if (c == ',') c = ' ';
  }
  std::istringstream in(value);
  std::vector<std::string> items;
  for (std::string item; in >> item;) items.push_back(item);
  return items;
}

void PluginTags::accept(std::initializer_list<const char*> tags) {
  for (const char* tag : tags) read_.insert(tag);
}

void PluginTags::finish() {
  if (!element_) return;
  for (const auto& node : element_->children) {
    if (read_.insert(node.name).second) {  // one warning per tag
      diagnostics_.warning(where_ + " <" + node.name + "> is not a tag this plugin knows: ignored");
    }
  }
}

}  // namespace bullet_sim
