#include "plugins/ros_control/controller_manager.h"

#include <algorithm>
#include <map>
#include <regex>

#include "bullet_sim/common/diagnostics.h"
#include "bullet_sim/common/names.h"
#include "plugins/ros_control/controller_registry.h"

namespace bullet_sim {

namespace {

/// A ROS graph name made of relative parts ("arm/gripper_controller"): what a controller's topics can live
/// under.
bool isGraphName(const std::string& name) {
  static const std::regex kName("[A-Za-z][A-Za-z0-9_]*(/[A-Za-z][A-Za-z0-9_]*)*");
  return std::regex_match(name, kName);
}

/// The controller's ports with inputs that do nothing, and services and actions that refuse, once the
/// controller is gone: a message or a call already queued for it may still arrive after its unload.
PluginPorts guardedPorts(const std::shared_ptr<Controller>& controller) {
  PluginPorts ports = controller->ports();
  const std::weak_ptr<Controller> alive = controller;
  const std::string gone = "controller [" + controller->name() + "] is unloaded";
  for (auto& input : ports.inputs) {
    input.sink = std::visit(
        [&](const auto& handler) -> InputSink {
          using Handler = std::decay_t<decltype(handler)>;
          return Handler([alive, handler](const auto& value, double sim_time) -> std::string {
            return alive.expired() ? std::string() : handler(value, sim_time);
          });
        },
        input.sink);
  }
  for (auto& service : ports.services) {
    service.handler = std::visit(
        [&](const auto& handler) -> ServiceSink {
          using Handler = std::decay_t<decltype(handler)>;
          return Handler([alive, handler, gone](const auto& request, auto& reply) -> std::string {
            return alive.expired() ? gone : handler(request, reply);
          });
        },
        service.handler);
  }
  for (auto& action : ports.actions) {
    std::visit(
        [&](auto& handlers) {
          using Decision = decltype(handlers.goal(0, {}, 0));
          handlers.goal = [alive, goal = handlers.goal, gone](GoalId id, const auto& request,
                                                              double sim_time) {
            return alive.expired() ? Decision{false, {-1, gone}} : goal(id, request, sim_time);
          };
          handlers.cancel = [alive, cancel = handlers.cancel](GoalId id, double sim_time) {
            if (!alive.expired()) cancel(id, sim_time);
          };
        },
        action.sink);
  }
  return ports;
}

}  // namespace

ControllerManager::ControllerManager(RobotHardware& hardware, const ControllerRegistry& types,
                                     const ParameterSource* parameters, std::string robot_namespace,
                                     const ModelSpec& model)
    : hardware_(hardware), types_(types), parameters_(parameters), model_(model) {
  while (!robot_namespace.empty() && robot_namespace.back() == '/') robot_namespace.pop_back();
  while (!robot_namespace.empty() && robot_namespace.front() == '/') robot_namespace.erase(0, 1);
  namespace_ = "/" + robot_namespace;
}

ControllerManager::~ControllerManager() = default;

std::string ControllerManager::parameterNamespace(const std::string& name) const {
  return (namespace_ == "/" ? "" : namespace_) + "/" + name;
}

std::string ControllerManager::load(const std::string& name, std::vector<std::string>* warnings) {
  const std::string head = "could not load controller [" + name + "]: ";
  if (!isGraphName(name)) return head + "its name must be a ROS name (letters, digits, _ and /)";
  if (find(name)) return head + "a controller of that name is loaded already";
  const std::string ns = parameterNamespace(name);
  try {
    const ParameterTree parameters = parameters_ ? parameters_->fetch(ns) : ParameterTree();
    if (!parameters.has("type")) {
      return head +
             "its type is not set: did you load the controller configuration onto the parameter server (" +
             ns + "/type)?";
    }
    const std::string type = parameters.text("type", "");
    const ControllerType* found = types_.find(type);
    if (!found) {
      return head + "type [" + type + "] is not a controller type bullet_sim has" +
             didYouMean(type, types_.names()) + "; it has " + joinedNames(types_.names());
    }
    std::vector<std::string> load_warnings;
    const ControllerSetup setup{name, type, parameters, hardware_, model_, load_warnings};
    std::shared_ptr<Controller> controller = found->create(setup);
    controllers_.push_back({next_id_++, controller, guardedPorts(controller)});
    ++revision_;
    if (warnings) warnings->insert(warnings->end(), load_warnings.begin(), load_warnings.end());
    return "";
  } catch (const std::exception& e) {
    return head + e.what();
  }
}

std::string ControllerManager::unload(const std::string& name) {
  const auto found = std::find_if(controllers_.begin(), controllers_.end(),
                                  [&](const Loaded& loaded) { return loaded.controller->name() == name; });
  const std::string head = "could not unload controller [" + name + "]: ";
  if (found == controllers_.end()) return head + "no controller of that name is loaded";
  if (found->controller->running()) return head + "it is still running: stop it first";
  controllers_.erase(found);
  ++revision_;
  return "";
}

std::string ControllerManager::switchControllers(const SwitchControllerRequest& request, double time,
                                                 std::vector<std::string>* warnings) {
  int strictness = request.strictness;
  if (strictness != SwitchControllerRequest::kStrict && strictness != SwitchControllerRequest::kBestEffort) {
    if (warnings) {
      warnings->push_back("switch_controller: strictness " + std::to_string(strictness) +
                          " is neither STRICT (2) nor BEST_EFFORT (1): BEST_EFFORT is used");
    }
    strictness = SwitchControllerRequest::kBestEffort;
  }
  std::vector<Controller*> stop, start;
  if (const std::string refused = resolveSwitch(request, strictness, &stop, &start); !refused.empty())
    return refused;
  std::vector<Controller*> running;
  for (const auto& loaded : controllers_) {
    Controller* controller = loaded.controller.get();
    const bool stops = std::count(stop.begin(), stop.end(), controller) > 0;
    const bool starts = std::count(start.begin(), start.end(), controller) > 0;
    if (starts || (controller->running() && !stops)) running.push_back(controller);
  }
  if (const std::string refused = conflict(running); !refused.empty()) return refused;
  for (Controller* controller : stop) controller->stop(time);
  for (Controller* controller : start) {
    try {
      controller->start(time);
    } catch (const std::exception& e) {
      // it stays as it was; those stopped above stay stopped, as in ros_control
      return "could not start controller [" + controller->name() + "]: " + e.what();
    }
  }
  return "";
}

std::string ControllerManager::resolveSwitch(const SwitchControllerRequest& request, int strictness,
                                             std::vector<Controller*>* stop,
                                             std::vector<Controller*>* start) const {
  const bool strict = strictness == SwitchControllerRequest::kStrict;
  for (const auto& [names, list, verb] : {std::make_tuple(&request.stop, stop, "stop"),
                                          std::make_tuple(&request.start, start, "start")}) {
    for (const auto& name : *names) {
      Controller* controller = find(name);
      if (!controller && strict)
        return "could not " + std::string(verb) + " controller [" + name +
               "]: no controller of that name is loaded";
      if (controller) list->push_back(controller);
    }
  }
  // BEST_EFFORT leaves out what cannot be done; STRICT refuses it.
  const auto refuse = [&](std::vector<Controller*>* list, bool running,
                          const std::string& why) -> std::string {
    for (auto it = list->begin(); it != list->end();) {
      if ((*it)->running() != running) {
        ++it;
      } else if (strict) {
        return "controller [" + (*it)->name() + "] " + why;
      } else {
        it = list->erase(it);
      }
    }
    return "";
  };
  if (std::string refused = refuse(stop, false, "is not running, so it cannot stop"); !refused.empty())
    return refused;
  for (Controller* controller : *stop) {
    if (std::count(start->begin(), start->end(), controller))
      return "could not switch controller [" + controller->name() +
             "]: it is asked both to start and to stop";
  }
  return refuse(start, true, "is running already");
}

std::string ControllerManager::conflict(const std::vector<Controller*>& running) const {
  std::map<std::string, std::vector<std::string>> claimants;
  for (const Controller* controller : running) {
    for (const auto& joint : controller->claims().resources) claimants[joint].push_back(controller->name());
  }
  for (const auto& [joint, names] : claimants) {
    if (names.size() > 1)
      return "could not switch controllers: joint [" + joint + "] would be claimed by " + joinedNames(names);
  }
  return "";
}

std::vector<ControllerStatus> ControllerManager::list() const {
  std::vector<ControllerStatus> statuses;
  for (const auto& loaded : controllers_) {
    const Controller& controller = *loaded.controller;
    statuses.push_back(
        {controller.name(), stateName(controller.state()), controller.type(), {controller.claims()}});
  }
  return statuses;
}

ListControllerTypesRequest::Reply ControllerManager::listTypes() const {
  ListControllerTypesRequest::Reply reply;
  reply.types = types_.names();
  reply.base_classes.assign(reply.types.size(), "controller_interface::ControllerBase");
  return reply;
}

std::string ControllerManager::reloadLibraries(bool force_kill, double time) {
  if (controllers_.empty()) return "";
  if (!force_kill) {
    return "cannot reload controller libraries: " + std::to_string(controllers_.size()) +
           " controllers are still loaded (force_kill stops and unloads them)";
  }
  for (auto& loaded : controllers_) {
    if (loaded.controller->running()) loaded.controller->stop(time);
  }
  controllers_.clear();
  ++revision_;
  return "";
}

void ControllerManager::update(double time, double period, bool restart_running) {
  for (auto& loaded : controllers_) {
    Controller& controller = *loaded.controller;
    if (restart_running && controller.running()) {
      controller.stop(time);
      controller.start(time);
    }
    controller.update(time, period);
  }
}

void ControllerManager::restart(double time) {
  for (auto& loaded : controllers_) loaded.controller->restart(time);
}

std::vector<std::string> ControllerManager::startUnupdatedAgain(double time) {
  std::vector<std::string> warnings;
  for (auto& loaded : controllers_) {
    Controller& controller = *loaded.controller;
    if (!controller.awaitsFirstUpdate()) continue;
    const std::string dropped = controller.following();
    controller.stop(time);
    controller.start(time);
    if (!dropped.empty()) {
      warnings.push_back("controller [" + controller.name() +
                         "] had not updated since it started, so it starts again from the joints set now, "
                         "and its " + dropped + " is canceled");
    }
  }
  return warnings;
}

Controller* ControllerManager::find(const std::string& name) const {
  for (const auto& loaded : controllers_) {
    if (loaded.controller->name() == name) return loaded.controller.get();
  }
  return nullptr;
}

std::vector<PortGroup> ControllerManager::portGroups() const {
  std::vector<PortGroup> groups;
  for (const auto& loaded : controllers_)
    groups.push_back({loaded.id, "controller [" + loaded.controller->name() + "]", &loaded.ports});
  return groups;
}

}  // namespace bullet_sim
