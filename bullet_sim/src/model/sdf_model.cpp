#include "bullet_sim/model/sdf_model.h"

#include <algorithm>
#include <deque>
#include <map>
#include <sstream>

#include "bullet_sim/common/diagnostics.h"
#include "bullet_sim/model/model_geometry.h"
#include "model/urdf_values.h"

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

constexpr char kWorld[] = "world";  // the parent of a joint to the world, and then the model's root link

/// The model's links as a tree from its root: `kWorld` when a joint ties the model to the world, else its
/// first link that is no joint's child.
struct Tree {
  std::string root;
  std::vector<std::string> order;                           ///< parents before children
  std::map<std::string, const WorldJointSpec*> joint_into;  ///< per link but the root and the welded
  std::vector<std::string> welded;  ///< other links joined to nothing, welded to the root
};

const WorldLinkSpec* findLink(const WorldModelSpec& model, const std::string& name) {
  for (const auto& link : model.links) {
    if (link.name == name) return &link;
  }
  return nullptr;
}

/// The joints, checked: parent -> children.
std::map<std::string, std::vector<std::string>> readJoints(const WorldModelSpec& model, Tree& tree,
                                                           Diagnostics& diagnostics) {
  std::vector<std::string> links;
  for (const auto& link : model.links) links.push_back(link.name);
  std::map<std::string, std::vector<std::string>> children;
  for (const auto& joint : model.joints) {
    bool known = true;
    for (const std::string& link : {joint.parent, joint.child}) {
      if (!findLink(model, link) && !(link == kWorld && link == joint.parent)) {
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

/// The roots of the model's tree: its links that are no joint's child, after `kWorld` when a joint ties
/// the model to it. Links joined to nothing but the first root are welded to it when `weld` allows, with a
/// warning when the model is not static; else they are an error.
std::vector<std::string> findRoots(const WorldModelSpec& model, const Tree& tree, bool is_static, bool weld,
                                   std::vector<std::string>& root_children, Diagnostics& diagnostics) {
  std::vector<std::string> roots;
  if (!root_children.empty()) roots.push_back(kWorld);  // children of kWorld
  for (const auto& link : model.links) {
    if (!tree.joint_into.count(link.name)) roots.push_back(link.name);
  }
  if (roots.size() <= 1 || is_static) return roots;
  const std::vector<std::string> loose(roots.begin() + 1, roots.end());
  if (weld) {
    diagnostics.warning("links " + listOf(loose) +
                        " are joined to nothing: Gazebo moves each on its own, "
                        "bullet_sim welds them to [" +
                        roots.front() + "] as one rigid body");
  } else {
    const bool to_world = roots.front() == kWorld;  // then the rest are joined to nothing
    diagnostics.error("links " + listOf(to_world ? loose : roots) + " of model [" + model.name +
                      "] are joined to nothing: bullet_sim simulates a model's links as one tree; join them "
                      "with joints (a fixed one for a rigid part), or make the model <static>");
  }
  return roots;
}

Tree buildTree(const WorldModelSpec& model, bool is_static, bool weld_unjoined, Diagnostics& diagnostics) {
  Tree tree;
  std::map<std::string, std::vector<std::string>> children = readJoints(model, tree, diagnostics);
  const std::vector<std::string> roots =
      findRoots(model, tree, is_static, weld_unjoined, children[kWorld], diagnostics);
  if (roots.empty()) {
    diagnostics.error("model [" + model.name +
                      "] has no link that is no joint's child: its joints form a loop");
    return {};
  }
  tree.root = roots.front();
  if (is_static || weld_unjoined) {
    tree.welded.assign(roots.begin() + 1, roots.end());
    children[tree.root].insert(children[tree.root].end(), tree.welded.begin(), tree.welded.end());
  }
  for (std::deque<std::string> next{tree.root}; !next.empty(); next.pop_front()) {
    tree.order.push_back(next.front());
    for (const auto& child : children[next.front()]) next.push_back(child);
  }
  if (roots.size() == 1 || is_static || weld_unjoined) {
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
                      const Limits& limits, bool weld_unjoined) {
  ModelSpec spec;
  spec.name = model.name;
  spec.source = diagnostics.source();
  spec.is_static = model.is_static;
  spec.allow_auto_disable = model.allow_auto_disable;
  spec.placement = model.pose;
  spec.names_from_sdf = true;
  const Tree tree = buildTree(model, spec.is_static, weld_unjoined, diagnostics);
  if (tree.root.empty()) return spec;
  std::map<std::string, Eigen::Isometry3d> frames;
  for (const std::string& name : tree.order) {
    const auto joint = tree.joint_into.find(name);
    frames[name] = name == kWorld
                       ? Eigen::Isometry3d::Identity()  // the world's link: at the model frame
                       : frameOf(*findLink(model, name),
                                 joint == tree.joint_into.end() ? nullptr : joint->second, diagnostics);
  }
  spec.root = tree.root;
  spec.root_in_model = frames.at(tree.root);
  for (const std::string& name : tree.order) {
    spec.links.push_back(name == kWorld ? LinkSpec{kWorld}
                                        : makeLink(model, *findLink(model, name), frames.at(name)));
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
  Diagnostics diagnostics(source);
  if (!checkSdfCounts(sdf_xml, limits, diagnostics)) diagnostics.throwIfErrors();  // before the long read
  std::vector<std::string> read_warnings;
  const WorldModelSpec model = readSdfModel(sdf_xml, source, resolver, &read_warnings, limits);
  for (const auto& warning : read_warnings) diagnostics.warning(warning);
  ModelSpec spec = toModelSpec(model, plugins, diagnostics, limits);
  if (warnings)
    warnings->insert(warnings->end(), diagnostics.warnings().begin(), diagnostics.warnings().end());
  diagnostics.throwIfErrors();
  return spec;
}

}  // namespace bullet_sim
