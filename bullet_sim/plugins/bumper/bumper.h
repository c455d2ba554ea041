// A bumper: <sensor type="contact"> with libgazebo_ros_bumper.so publishes gazebo_msgs/ContactsState, what
// touches the sensor's collisions, at every sensor update (empty while nothing touches). Its plugin tags are
// kBumperTags in bumper.cpp; README.md describes the sensor's <contact> block (collisions named as Gazebo
// names them once it has lumped fixed joints, model/gazebo_names.h) and the states.
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
  std::string topic;
  std::string frame;
};

void parseBumper(const DeclarationSource& source, BumperConfig& config);

class Bumper : public Plugin {
 public:
  Bumper(const PluginDeclaration& declaration, const BumperConfig& config, const PluginSetup& setup);

  void sense(const StepTime& time, const RobotBody& body, const RayCaster& rays) override;

  const BumperConfig& config() const { return config_; }

 private:
  /// One state for `watched` touching `contact`.
  ContactsSample::State state(const BumperConfig::Watched& watched, const CollisionContact& contact,
                              const Eigen::Vector3d& link_origin, double stamp) const;

  BumperConfig config_;
  std::string robot_name_;
  Stream<ContactsSample> contacts_;
};

}  // namespace bullet_sim
