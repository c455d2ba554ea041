// SIGINT and SIGTERM end the simulator promptly in every state: the node shuts down between steps, and if it
// is still busy (a long step, a spawn, a render) after a grace period, the process exits anyway.
#pragma once

#include <memory>

namespace bullet_sim {

class ExitGuard {
 public:
  /// Installs the handlers of SIGINT and SIGTERM; initialise ROS with ros::init_options::NoSigintHandler
  /// first. One guard per process.
  explicit ExitGuard(double grace_seconds);
  /// Restores the default handlers.
  ~ExitGuard();
  ExitGuard(const ExitGuard&) = delete;
  ExitGuard& operator=(const ExitGuard&) = delete;

 private:
  struct Watch;
  std::shared_ptr<Watch> watch_;  ///< shared with its thread, which may outlive the guard by the grace
};

}  // namespace bullet_sim
