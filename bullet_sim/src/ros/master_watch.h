// Notices when the ROS master restarts or stops answering. A restarted master has forgotten every
// registration of the node, which would go on publishing to nobody, so the node shuts down instead: a launch
// file's respawn="true" then starts a fresh simulator, which registers with the new master.
#pragma once

#include <memory>
#include <optional>
#include <string>

namespace bullet_sim {

class MasterWatch {
 public:
  /// Asks the master for its process id every `period_seconds`; when the id changes, or the master has not
  /// answered for `silence_seconds`, records why and asks ROS to shut down. Call after ros::init.
  MasterWatch(double period_seconds, double silence_seconds);
  ~MasterWatch();
  MasterWatch(const MasterWatch&) = delete;
  MasterWatch& operator=(const MasterWatch&) = delete;

  /// Why the master was lost, once it was.
  std::optional<std::string> lost() const;

 private:
  struct State;
  std::shared_ptr<State> state_;  ///< shared with its thread, which may be inside a call to the master
};

}  // namespace bullet_sim
