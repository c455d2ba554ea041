// ros_control's controller types, which load_controller builds by ros_controllers' type names.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "plugins/ros_control/controller.h"

namespace bullet_sim {

using ControllerFactory = std::function<std::unique_ptr<Controller>(const ControllerSetup& setup)>;

struct ControllerType {
  std::string name;  ///< ros_controllers' type name, e.g. diff_drive_controller/DiffDriveController
  ControllerFactory create;
};

/// A controller type built as Behaviour(setup, args...).
template <class Behaviour, class... Args>
ControllerType controllerType(std::string name, Args... args) {
  return {std::move(name), [args...](const ControllerSetup& setup) -> std::unique_ptr<Controller> {
            return std::make_unique<Behaviour>(setup, args...);
          }};
}

class ControllerRegistry {
 public:
  /// Every controller type bullet_sim ships.
  static const ControllerRegistry& builtin();

  /// Adds a type; one of the same name is replaced.
  void add(ControllerType type);
  /// The type of that name, or nullptr.
  const ControllerType* find(const std::string& name) const;
  /// Every type's name, in the table's order.
  std::vector<std::string> names() const;

 private:
  std::vector<ControllerType> types_;
};

}  // namespace bullet_sim
