#include "bullet_sim/description/sdf_model.h"

#include <algorithm>
#include <deque>
#include <map>
#include <sstream>

#include "bullet_sim/description/diagnostics.h"
#include "bullet_sim/description/model_geometry.h"
#include "description/urdf_values.h"

namespace bullet_sim {

namespace {

constexpr double kSamePoint = 1e-9;  // [m] a joint's frame this close to its child link's origin is at it

std::string listOf(const std::vector<std::string>& names) {
  std::string list;
  for (const auto& name : names) list += (list.empty() ? "[" : ", [") + name + "]";
  return list;
}

std::string text(const Eigen::Vector3d& v) {
  std::ostringstream out;
  out << v.x() << " " << v.y() << " " << v.z();
  return out.str();
}

/// The model's links as a tree from its root (its first link that is no joint's child).
struct Tree {
  std::string root;
  std::vector<std::string> order;                           ///< parents before children
  std::map<std::string, const WorldJointSpec*> joint_into;  ///< per link but the root and the welded
  std::vector<std::string> welded;  ///< a static model's other unjoined links, welded to the root
};

const WorldLinkSpec* findLink(const WorldModelSpec& model, const std::string& name) {
  for (const auto& link : model.links) {
    if (link.name == name) return &link;
  }
  return nullptr;
}

/// The joints between links, checked; joints to the world are the caller's.
std::map<std::string, std::vector<std::string>> readJoints(const WorldModelSpec& model, Tree& tree,
                                                           Diagnostics& diagnostics) {
  std::vector<std::string> links;
  for (const auto& link : model.links) links.push_back(link.name);
  std::map<std::string, std::vector<std::string>> children;
  for (const auto& joint : model.joints) {
    if (joint.parent == "world") continue;
    bool known = true;
    for (const std::string& link : {joint.parent, joint.child}) {
      if (!findLink(model, link)) {
        diagnostics.error("joint [" + joint.name + "] names link [" + link + "], which model [" + model.name +
                          "] does not have" + didYouMean(link, links));
        known = false;
      }
    }
    if (!known) continue;
    if (tree.joint_into.count(joint.child)) {
      diagnostics.error("link [" + joint.child + "] is the child of joints [" +
                        tree.joint_into[joint.child]->name + "] and [" + joint.name +
                        "]: a model's joints must form a tree");
      continue;
    }
    tree.joint_into[joint.child] = &joint;
    children[joint.parent].push_back(joint.child);
  }
  return children;
}

Tree buildTree(const WorldModelSpec& model, bool is_static, Diagnostics& diagnostics) {
  Tree tree;
  std::map<std::string, std::vector<std::string>> children = readJoints(model, tree, diagnostics);
  std::vector<std::string> roots;
  for (const auto& link : model.links) {
    if (!tree.joint_into.count(link.name)) roots.push_back(link.name);
  }
  if (roots.empty()) {
    diagnostics.error("model [" + model.name +
                      "] has no link that is no joint's child: its joints form a loop");
    return {};
  }
  tree.root = roots.front();
  if (roots.size() > 1 && is_static) {
    tree.welded.assign(roots.begin() + 1, roots.end());
    children[tree.root].insert(children[tree.root].end(), tree.welded.begin(), tree.welded.end());
  } else if (roots.size() > 1) {
    diagnostics.error("links " + listOf(roots) + " of model [" + model.name +
                      "] are joined to nothing: bullet_sim simulates a model's links as one tree; join them "
                      "with joints (a fixed one for a rigid part), or make the model <static>");
  }
  for (std::deque<std::string> next{tree.root}; !next.empty(); next.pop_front()) {
    tree.order.push_back(next.front());
    for (const auto& child : children[next.front()]) next.push_back(child);
  }
  if (roots.size() == 1 || is_static) {
    std::vector<std::string> unreached;
    for (const auto& link : model.links) {
      if (std::find(tree.order.begin(), tree.order.end(), link.name) == tree.order.end()) {
        unreached.push_back(link.name);
      }
    }
    if (!unreached.empty()) {
      diagnostics.error("the joints of links " + listOf(unreached) + " of model [" + model.name +
                        "] form a loop: a model's joints must form a tree");
    }
  }
  return tree;
}

/// Where the ModelSpec puts a link's frame: the SDF link's, moved to its joint's origin when the joint turns
/// about another point (a URDF joint turns its child about the child's origin).
Eigen::Isometry3d frameOf(const WorldLinkSpec& link, const WorldJointSpec* joint, Diagnostics& diagnostics) {
  if (!joint || (joint->pose.translation() - link.pose.translation()).norm() <= kSamePoint) return link.pose;
  const Eigen::Vector3d offset = link.pose.inverse() * joint->pose.translation();
  diagnostics.warning(
      "joint [" + joint->name + "] turns link [" + link.name + "] about a point [" + text(offset) +
      "] m from the link's origin: bullet_sim puts the link's frame there, so its link states are "
      "given there");
  Eigen::Isometry3d frame = link.pose;
  frame.translation() = joint->pose.translation();
  return frame;
}

LinkSpec makeLink(const WorldModelSpec& model, const WorldLinkSpec& link, const Eigen::Isometry3d& frame) {
  LinkSpec spec;
  spec.name = link.name;
  const Eigen::Isometry3d from_model = frame.inverse();
  const Eigen::Isometry3d from_link = from_model * link.pose;
  if (link.inertial) {
    spec.inertial =
        InertialSpec{link.inertial->mass, from_link * link.inertial->com,
                     from_link.linear() * link.inertial->inertia * from_link.linear().transpose()};
  }
  for (size_t index : link.collision_indices) {
    Collision collision = model.collisions[index];
    collision.origin = from_model * collision.origin;
    collision.name = collision.name.substr(collision.name.rfind("::") + 2);  // as a URDF's: the bare name
    spec.collisions.push_back(std::move(collision));
  }
  for (size_t index : link.visual_indices) {
    Visual visual = model.visuals[index];
    visual.origin = from_model * visual.origin;
    spec.visuals.push_back(std::move(visual));
  }
  spec.surface = link.surface;
  spec.self_collide = link.self_collide;
  spec.gravity = link.gravity;
  return spec;
}

JointSpec makeJoint(const WorldJointSpec& joint, const Eigen::Isometry3d& parent,
                    const Eigen::Isometry3d& child) {
  JointSpec spec;
  spec.name = joint.name;
  spec.type = joint.type;
  spec.parent = joint.parent;
  spec.child = joint.child;
  spec.origin = parent.inverse() * child;
  spec.axis = child.linear().transpose() * joint.axis;
  if (joint.type != JointSpec::Type::kContinuous) {
    spec.lower = joint.lower;
    spec.upper = joint.upper;
  }
  spec.effort = joint.effort;
  spec.velocity = joint.velocity;
  spec.damping = joint.damping;
  spec.friction = joint.friction;
  return spec;
}

}  // namespace

ModelSpec toModelSpec(const WorldModelSpec& model, const PluginParsers& plugins, Diagnostics& diagnostics,
                      const Limits& limits) {
  ModelSpec spec;
  spec.name = model.name;
  spec.source = diagnostics.source();
  spec.is_static = model.is_static;
  spec.placement = model.pose;
  for (const auto& joint : model.joints) {
    if (joint.parent != "world") continue;
    if (joint.type == JointSpec::Type::kFixed) {
      spec.is_static = true;  // fixed to the world: it never moves
    } else {
      diagnostics.error(
          "joint [" + joint.name + "] moves link [" + joint.child +
          "] against the world: bullet_sim fixes a model to the world only rigidly; make the joint "
          "fixed, or the model <static>");
    }
  }
  const Tree tree = buildTree(model, spec.is_static, diagnostics);
  if (tree.root.empty()) return spec;
  std::map<std::string, Eigen::Isometry3d> frames;
  for (const std::string& name : tree.order) {
    const auto joint = tree.joint_into.find(name);
    frames[name] = frameOf(*findLink(model, name), joint == tree.joint_into.end() ? nullptr : joint->second,
                           diagnostics);
  }
  spec.root = tree.root;
  spec.root_in_model = frames.at(tree.root);
  for (const std::string& name : tree.order) {
    spec.links.push_back(makeLink(model, *findLink(model, name), frames.at(name)));
    if (name == tree.root) continue;
    const auto joint = tree.joint_into.find(name);
    WorldJointSpec weld{"__weld_" + name, JointSpec::Type::kFixed, tree.root, name};
    const WorldJointSpec& into = joint == tree.joint_into.end() ? weld : *joint->second;
    spec.joints.push_back(makeJoint(into, frames.at(into.parent), frames.at(name)));
  }
  std::vector<PluginElement> elements = model.plugins;
  for (PluginElement& element : elements) {  // a sensor's pose is in its link's SDF frame
    if (element.sensor && frames.count(element.sensor->link)) {
      element.sensor->pose = frames.at(element.sensor->link).inverse() *
                             findLink(model, element.sensor->link)->pose * element.sensor->pose;
    }
  }
  checkModelValues(spec, limits, diagnostics);
  declarePlugins(elements, plugins, spec, diagnostics, limits);
  repairBodyInertias(spec, diagnostics);
  return spec;
}

ModelSpec parseSdfModel(const std::string& sdf_xml, const std::string& source,
                        const PackageResolver& resolver, const PluginParsers& plugins,
                        std::vector<std::string>* warnings, const Limits& limits) {
  std::vector<std::string> read_warnings;
  const WorldModelSpec model = readSdfModel(sdf_xml, source, resolver, &read_warnings, limits);
  Diagnostics diagnostics(source);
  for (const auto& warning : read_warnings) diagnostics.warning(warning);
  ModelSpec spec = toModelSpec(model, plugins, diagnostics, limits);
  if (warnings)
    warnings->insert(warnings->end(), diagnostics.warnings().begin(), diagnostics.warnings().end());
  diagnostics.throwIfErrors();
  return spec;
}

}  // namespace bullet_sim
