#include "model/tag_node_xml.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

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

const char* tagTypeName(TagType type) {
  switch (type) {
    case TagType::kText: return "text";
    case TagType::kTopic: return "topic";
    case TagType::kFrame: return "frame";
    case TagType::kNumber: return "number";
    case TagType::kPositive: return "number >= 0";
    case TagType::kRate: return "number (< 0: as 0)";
    case TagType::kDeviation: return "number (< 0: as its absolute value)";
    case TagType::kFlag: return "true/false";
    case TagType::kList: return "list";
    case TagType::kIgnored: return "ignored";
  }
  return "";
}

const TagRow* TagTable::row(const std::string& name) const {
  const auto found =
      std::find_if(rows_.begin(), rows_.end(), [&](const TagRow& row) { return row.name == name; });
  return found == rows_.end() ? nullptr : &*found;
}

void TagTable::add(TagRow row) {
  const auto same =
      std::find_if(rows_.begin(), rows_.end(), [&](const TagRow& known) { return known.name == row.name; });
  if (same != rows_.end()) {
    *same = std::move(row);
  } else {
    rows_.push_back(std::move(row));
  }
}

PluginTags::PluginTags(const TagNode* element, std::string where, Diagnostics& diagnostics)
    : element_(element), where_(std::move(where)), diagnostics_(diagnostics) {}

void PluginTags::useTable(const TagTable* table) {
  table_ = table;
  if (!table_) return;
  for (const TagRow& row : table_->rows()) {
    if (row.type == TagType::kIgnored) read_.insert(row.name);
  }
}

const TagNode* PluginTags::find(const std::string& tag) {
  read_.insert(tag);
  return element_ ? element_->child(tag) : nullptr;
}

const TagRow* PluginTags::checkedRow(const std::string& tag, std::initializer_list<TagType> types) const {
  if (!table_) return nullptr;
  const TagRow* row = table_->row(tag);
  if (!row) throw std::logic_error(where_ + " reads <" + tag + ">, which its plugin's tag table lacks");
  if (std::find(types.begin(), types.end(), row->type) == types.end()) {
    throw std::logic_error(where_ + " reads <" + tag + "> otherwise than as its tag table's " +
                           tagTypeName(row->type));
  }
  return row;
}

double PluginTags::rowNumber(const std::string& tag, std::initializer_list<TagType> types) const {
  const TagRow* row = checkedRow(tag, types);
  if (!row) throw std::logic_error(where_ + " reads <" + tag + "> with the table's default, without a table");
  try {
    return std::stod(row->fallback);
  } catch (const std::exception&) {
    throw std::logic_error(where_ + " <" + tag + ">'s table default [" + row->fallback + "] is no number");
  }
}

bool PluginTags::has(const std::string& tag) const {
  if (table_ && !table_->row(tag))
    throw std::logic_error(where_ + " asks for <" + tag + ">, which its plugin's tag table lacks");
  return element_ && element_->child(tag);
}

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
  checkedRow(tag, {TagType::kText, TagType::kTopic});
  return rawText(tag, fallback);
}

std::string PluginTags::text(const std::string& tag) {
  const TagRow* row = checkedRow(tag, {TagType::kText, TagType::kTopic});
  return rawText(tag, row ? row->fallback : "");
}

std::string PluginTags::rawText(const std::string& tag, const std::string& fallback) {
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
  checkedRow(tag, {TagType::kFrame});
  const std::string value = rawText(tag, fallback);
  const auto start = value.find_first_not_of('/');
  if (!has(tag) || start == 0 || value.empty()) return value;
  const std::string bare = start == std::string::npos ? "" : value.substr(start);
  global_frames_.insert(bare);
  if (!gazebo_drops_slash) {
    diagnostics_.warning(where_ + " <" + tag + "> [" + value + "] is read as [" + bare +
                         "]: tf2 frame ids have no leading / (Gazebo's plugin keeps it)");
  }
  return bare;
}

double PluginTags::number(const std::string& tag, double fallback) {
  checkedRow(tag, {TagType::kNumber});
  return rawNumber(tag, fallback);
}

double PluginTags::number(const std::string& tag) {
  return rawNumber(tag, rowNumber(tag, {TagType::kNumber}));
}

double PluginTags::rawNumber(const std::string& tag, double fallback) {
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

double PluginTags::positive(const std::string& tag) {
  return positive(tag, rowNumber(tag, {TagType::kPositive}));
}

double PluginTags::nonNegative(const std::string& tag) {
  return positive(tag, rowNumber(tag, {TagType::kPositive}), /*allow_zero=*/true);
}

double PluginTags::positive(const std::string& tag, double fallback, bool allow_zero) {
  checkedRow(tag, {TagType::kPositive});
  const double value = rawNumber(tag, fallback);
  if (value < 0 || (!allow_zero && value == 0)) {
    std::ostringstream message;
    message << where_ << " <" << tag << "> must be " << (allow_zero ? ">= 0" : "> 0") << ", not " << value;
    diagnostics_.error(message.str());
    return fallback;
  }
  return value;
}

double PluginTags::rate(const std::string& tag) { return rate(tag, rowNumber(tag, {TagType::kRate})); }

double PluginTags::rate(const std::string& tag, double fallback) {
  checkedRow(tag, {TagType::kRate});
  const double value = rawNumber(tag, fallback);
  if (!(value < 0)) return value;
  std::ostringstream message;
  message << where_ << " <" << tag << "> " << value
          << " is below 0: read as 0, every update, as Gazebo's plugin reads it";
  diagnostics_.warning(message.str());
  return 0;
}

double PluginTags::deviation(const std::string& tag) {
  return deviation(tag, rowNumber(tag, {TagType::kDeviation}));
}

double PluginTags::deviation(const std::string& tag, double fallback) {
  checkedRow(tag, {TagType::kDeviation});
  const double value = rawNumber(tag, fallback);
  if (!(value < 0)) return value;
  std::ostringstream message;
  message << where_ << " <" << tag << "> " << value << " is negative: read as " << -value
          << ", as Gazebo's Gaussian noise takes it";
  diagnostics_.warning(message.str());
  return -value;
}

double PluginTags::capped(const std::string& tag, double fallback, double limit, const char* limit_name,
                          const std::string& unit) {
  return cap(tag, positive(tag, fallback), limit, limit_name, unit);
}

double PluginTags::motorLimit(const std::string& tag, double fallback, double limit, const char* limit_name,
                              const std::string& unit) {
  checkedRow(tag, {TagType::kPositive});
  const double value = rawNumber(tag, fallback);
  if (value > 0) return cap(tag, value, limit, limit_name, unit);
  std::ostringstream message;
  message << where_ << " <" << tag << "> " << value << " " << unit
          << " is not above 0: its motors give none, as in Gazebo, whose ODE drives no motor whose limit is "
             "not above 0";
  diagnostics_.warning(message.str());
  return 0;
}

double PluginTags::cap(const std::string& tag, double value, double limit, const char* limit_name,
                       const std::string& unit) {
  if (value <= limit) return value;
  std::ostringstream message;
  message << where_ << " <" << tag << "> " << value << " " << unit << " is above the limit of " << limit
          << " " << unit << " (" << limit_name << "): " << limit << " " << unit << " is used";
  diagnostics_.warning(message.str());
  return limit;
}

bool PluginTags::flag(const std::string& tag) {
  const TagRow* row = checkedRow(tag, {TagType::kFlag});
  if (!row || (row->fallback != "true" && row->fallback != "false"))
    throw std::logic_error(where_ + " <" + tag + "> has no true/false default in its tag table");
  return flag(tag, row->fallback == "true");
}

bool PluginTags::flag(const std::string& tag, bool fallback) {
  checkedRow(tag, {TagType::kFlag});
  const TagNode* node = find(tag);
  if (!node) return fallback;
  if (node->text == "true" || node->text == "1") return true;
  if (node->text == "false" || node->text == "0") return false;
  diagnostics_.error(where_ + " <" + tag + "> must be true or false, not [" + node->text + "]");
  return fallback;
}

std::vector<std::string> PluginTags::list(const std::string& tag) {
  checkedRow(tag, {TagType::kList});
  std::string value = rawText(tag, "");
  for (char& c : value) {
    if (c == ',') c = ' ';
  }
  std::istringstream in(value);
  std::vector<std::string> items;
  for (std::string item; in >> item;) items.push_back(item);
  return items;
}

void PluginTags::accept(std::initializer_list<const char*> tags) {
  for (const char* tag : tags) {
    checkedRow(tag, {TagType::kIgnored});
    read_.insert(tag);
  }
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
