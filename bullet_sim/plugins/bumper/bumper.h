// A bumper: <sensor type="contact"> with libgazebo_ros_bumper.so publishes gazebo_msgs/ContactsState, what
// touches the sensor's collisions, at every sensor update (empty while nothing touches).
//
// Sensor tags (SDF's): update_rate [0 = every step], contact/collision (one or more), named as Gazebo names
//   them once it has lumped fixed joints (model/gazebo_names.h), within the link the sensor lands in.
//   A name written for the link before lumping ("bumper_link_collision" for a lumped bumper_link), which
//   Gazebo never finds (its bumper stays silent), is taken to mean that collision, with a warning that gives
//   Gazebo's name; a name matching nothing is a warning with a suggestion, and reports nothing, as in Gazebo.
// Plugin tags (gazebo_plugins'): bumperTopicName [bumper_states], frameName [world: only the header's label;
//   positions, normals and wrenches are in the world frame, as Gazebo reports them], robotNamespace.
// One state per pair of touching collisions: collision1 is the sensor's, collision2 what it touches, both as
// model::link::collision; per point its position, the normal pushing collision1, the depth and the wrench
// on collision1 (the torque about the origin of collision1's link), and their total.
#pragma once

#include <string>
#include <vector>

#include "bullet_sim/plugins/outputs.h"
#include "bullet_sim/plugins/plugin.h"

namespace bullet_sim {

struct BumperConfig : PluginConfig {
  /// A collision the sensor watches.
  struct Watched {
    CollisionSource source;
    std::string gazebo_link;  ///< the link it lands in
    std::string name;         ///< its Gazebo name there
  };
  std::vector<Watched> collisions;
  std::string topic = "bumper_states";
  std::string frame = "world";
};

void parseBumper(const DeclarationSource& source, BumperConfig& config);

class Bumper : public Plugin {
 public:
  Bumper(const PluginDeclaration& declaration, const BumperConfig& config, const PluginSetup& setup);

  void sense(const StepTime& time, const RobotBody& body, const RayCaster& rays) override;

  const BumperConfig& config() const { return config_; }
  const ContactsSample& contacts() const { return contacts_.latest(); }
  uint64_t contactsCount() const { return contacts_.count(); }

 private:
  /// One state for `watched` touching `contact`.
  ContactsSample::State state(const BumperConfig::Watched& watched, const CollisionContact& contact,
                              const Eigen::Vector3d& link_origin, double stamp) const;

  BumperConfig config_;
  std::string robot_name_;
  Stream<ContactsSample> contacts_;
};

}  // namespace bullet_sim
