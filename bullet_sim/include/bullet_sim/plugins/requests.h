// What plugins' services take and answer, in ROS service terms but without ROS: each request type holds the
// request's fields and a Reply with the response's. The node maps each to its service type once.
#pragma once

#include <string>
#include <vector>

namespace bullet_sim {

/// std_srvs/Empty: the service does its one thing (hector's calibrate, ...).
struct EmptyRequest {
  struct Reply {};
};

// The controller manager's services (controller_manager_msgs). Whether a request succeeded is the handler's
// "" (ok) or its reason (not ok, and logged, as the real controller manager logs it).

/// controller_manager_msgs/LoadController.
struct LoadControllerRequest {
  std::string name;
  struct Reply {
    std::vector<std::string> warnings;  ///< about the controller's parameters, for the log
  };
};

/// controller_manager_msgs/UnloadController.
struct UnloadControllerRequest {
  std::string name;
  struct Reply {};
};

/// controller_manager_msgs/SwitchController.
struct SwitchControllerRequest {
  static constexpr int kBestEffort = 1;  ///< BEST_EFFORT
  static constexpr int kStrict = 2;      ///< STRICT
  std::vector<std::string> start;
  std::vector<std::string> stop;
  int strictness = kBestEffort;  ///< 0 is taken as BEST_EFFORT, with a warning, as ros_control takes it
  bool start_asap = false;       ///< accepted: controllers switch at once here
  double timeout = 0;            ///< [s]; accepted, as switching never waits here
  struct Reply {
    std::vector<std::string> warnings;
  };
};

/// controller_manager_msgs/HardwareInterfaceResources: the joints a controller claims through an interface.
struct ClaimedResources {
  std::string hardware_interface;  ///< e.g. hardware_interface::VelocityJointInterface
  std::vector<std::string> resources;
};

/// controller_manager_msgs/ControllerState.
struct ControllerStatus {
  std::string name;
  std::string state;  ///< initialized, running or stopped
  std::string type;
  std::vector<ClaimedResources> claimed_resources;
};

/// controller_manager_msgs/ListControllers.
struct ListControllersRequest {
  struct Reply {
    std::vector<ControllerStatus> controllers;
  };
};

/// controller_manager_msgs/ListControllerTypes.
struct ListControllerTypesRequest {
  struct Reply {
    std::vector<std::string> types;
    std::vector<std::string> base_classes;
  };
};

/// controller_manager_msgs/ReloadControllerLibraries.
struct ReloadControllerLibrariesRequest {
  bool force_kill = false;
  struct Reply {};
};

/// control_msgs/QueryTrajectoryState: where a trajectory controller wants its joints at `time`.
struct QueryTrajectoryStateRequest {
  double time = 0;  ///< [s] sim time
  struct Reply {
    std::vector<std::string> name;
    std::vector<double> position;
    std::vector<double> velocity;
    std::vector<double> acceleration;
  };
};

}  // namespace bullet_sim
