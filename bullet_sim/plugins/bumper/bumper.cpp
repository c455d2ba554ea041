#include "plugins/bumper/bumper.h"

#include "bullet_sim/plugins/registry.h"

#include <algorithm>
#include <iomanip>
#include <sstream>

#include "bullet_sim/model/gazebo_names.h"

namespace bullet_sim {

namespace {

/// The collision `name` names in the link the sensor lands in (`gazebo_link`), by Gazebo's names or, with a
/// warning, by a lumped link's names before lumping; nullopt, with a warning, when it names none.
std::optional<BumperConfig::Watched> resolve(const std::string& name, const std::string& gazebo_link,
                                             const DeclarationSource& source) {
  const std::string where = source.declaration.where() + " <contact><collision> [" + name + "]";
  std::vector<std::string> known;
  for (const GazeboCollision& collision : gazeboCollisions(source.model)) {
    if (collision.gazebo_link != gazebo_link) continue;
    known.push_back(collision.name);
    if (collision.name == name) {
      return BumperConfig::Watched{{collision.link, collision.index}, gazebo_link, name};
    }
  }
  for (const GazeboCollision& collision : gazeboCollisions(source.model)) {
    if (collision.gazebo_link != gazebo_link || collision.link == gazebo_link) continue;
    const auto before = unlumpedCollisionNames(source.model, collision.link);
    if (before.at(collision.index) != name) continue;
    source.diagnostics.warning(where + " is the name of link [" + collision.link +
                               "]'s collision before Gazebo lumps that link into [" + gazebo_link +
                               "]; there it is [" + collision.name +
                               "], and Gazebo's bumper, finding no [" + name +
                               "], reports nothing: bullet_sim watches [" + collision.name + "]");
    return BumperConfig::Watched{{collision.link, collision.index}, gazebo_link, collision.name};
  }
  source.diagnostics.warning(where + " is no collision of link [" + gazebo_link + "] as Gazebo names them" +
                             didYouMean(name, known) + ": it reports nothing, as in Gazebo");
  return std::nullopt;
}

const TagTable kBumperTags = {
    {"bumperTopicName", TagType::kTopic, "bumper_states", "", "the topic of the contacts", ""},
    {"frameName", TagType::kFrame, "world", "",
     "the messages' frame_id only: contacts are in the world frame whatever it names", ""},
    {"alwaysOn", TagType::kIgnored, "", "", "not read (a tag of older gazebo_plugins)", ""},
};

}  // namespace

void parseBumper(const DeclarationSource& source, BumperConfig& config) {
  PluginTags& tags = source.tags;
  config.topic = tags.text("bumperTopicName");
  config.frame = tags.frame("frameName", kBumperTags.row("frameName")->fallback);
  if (config.frame != "world" && config.frame != "map") {
    source.diagnostics.warning(tags.where() + " <frameName> [" + config.frame +
                               "]: contacts are in the world frame whatever the name, as in Gazebo");
  }
  const std::string gazebo_link = gazeboLink(source.model, config.link);
  const TagNode* contact = source.sensor ? source.sensor->child("contact") : nullptr;
  int named = 0;
  for (const TagNode& child : contact ? contact->children : std::vector<TagNode>{}) {
    if (child.name != "collision") continue;
    ++named;
    if (auto watched = resolve(child.text, gazebo_link, source)) config.collisions.push_back(*watched);
  }
  if (named == 0) {
    source.diagnostics.warning(source.declaration.where() +
                               " has no <contact><collision>: it reports nothing, as in Gazebo");
  }
}

Bumper::Bumper(const PluginDeclaration& declaration, const BumperConfig& config, const PluginSetup& setup)
    : Plugin(declaration, setup), config_(config), robot_name_(setup.robot_name) {
  contacts_.next().frame_id = config_.frame;
  addOutput(config_.topic, contacts_);
}

ContactsSample::State Bumper::state(const BumperConfig::Watched& watched, const CollisionContact& contact,
                                    const Eigen::Vector3d& link_origin, double stamp) const {
  ContactsSample::State state;
  state.collision1 = robot_name_ + "::" + watched.gazebo_link + "::" + watched.name;
  state.collision2 = contact.other;
  std::ostringstream info;
  info << "my geom:" << state.collision1 << "   other geom:" << state.collision2
       << "         time:" << std::fixed << std::setprecision(9) << stamp << "\n";
  state.info = info.str();
  for (const ContactPoint& point : contact.points) {
    const ContactsSample::Wrench wrench{point.force, (point.position - link_origin).cross(point.force)};
    state.wrenches.push_back(wrench);
    state.total_wrench.force += wrench.force;
    state.total_wrench.torque += wrench.torque;
    state.positions.push_back(point.position);
    state.normals.push_back(point.normal);
    state.depths.push_back(point.depth);
  }
  return state;
}

void Bumper::sense(const StepTime& time, const RobotBody& body, const RayCaster&) {
  if (!timer().due(time)) return;
  ContactsSample& sample = contacts_.next();
  sample.stamp = time.sim_time;
  sample.states.clear();
  for (const auto& watched : config_.collisions) {
    const Eigen::Vector3d origin = body.linkPose(watched.gazebo_link).translation();
    for (const CollisionContact& contact : body.contacts(watched.source))
      sample.states.push_back(state(watched, contact, origin, time.sim_time));
  }
  // Gazebo's debugging text, with the state's place among them.
  for (size_t i = 0; i < sample.states.size(); ++i) {
    sample.states[i].info = "Debug:  i:(" + std::to_string(i) + "/" + std::to_string(sample.states.size()) +
                            ")     " + sample.states[i].info;
  }
  contacts_.publish();
}

BULLET_SIM_PLUGIN_FOLDER(bumper) {
  PluginType type = pluginType<Bumper>("libgazebo_ros_bumper.so", parseBumper, kBumperTags);
  type.sensor_types = {"contact"};
  type.rate = {RateRule::From::kSensor, {}, 0};
  type.tf_prefix = TfPrefixRule::kNamespaceParam;
  registrar.add(std::move(type));
}

}  // namespace bullet_sim
