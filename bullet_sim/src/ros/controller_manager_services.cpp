#include "controller_manager_services.h"

#include <controller_manager_msgs/ListControllerTypes.h>
#include <controller_manager_msgs/ListControllers.h>
#include <controller_manager_msgs/LoadController.h>
#include <controller_manager_msgs/ReloadControllerLibraries.h>
#include <controller_manager_msgs/SwitchController.h>
#include <controller_manager_msgs/UnloadController.h>

#include <stdexcept>

namespace bullet_sim {

namespace {

template <class Reply>
void logWarnings(const Reply& reply, const std::string& robot) {
  if constexpr (std::is_same_v<Reply, LoadControllerRequest::Reply> ||
                std::is_same_v<Reply, SwitchControllerRequest::Reply>) {
    for (const auto& warning : reply.warnings) ROS_WARN("[%s] %s", robot.c_str(), warning.c_str());
  }
}

/// A service whose response is `bool ok`: the request converted by `convert`, its refusal logged.
template <class Service, class Request, class Convert>
ros::ServiceServer serveOk(ros::NodeHandle& handle, const std::string& name, ServiceHandler<Request> handler,
                           const std::string& robot, Convert convert) {
  return handle.advertiseService<typename Service::Request, typename Service::Response>(
      name, [handler, robot, convert, name](typename Service::Request& request,
                                            typename Service::Response& response) {
        typename Request::Reply reply;
        std::string refused;
        try {
          refused = handler(convert(request), reply);
        } catch (const std::exception& e) {  // answered, not thrown into roscpp
          refused = name + ": " + e.what();
        }
        logWarnings(reply, robot);
        if (!refused.empty()) ROS_ERROR("[%s] %s", robot.c_str(), refused.c_str());
        response.ok = refused.empty();
        return true;
      });
}

ros::ServiceServer serveList(ros::NodeHandle& handle, const std::string& name,
                             ServiceHandler<ListControllersRequest> handler) {
  using Service = controller_manager_msgs::ListControllers;
  return handle.advertiseService<Service::Request, Service::Response>(
      name, [handler](Service::Request&, Service::Response& response) {
        ListControllersRequest::Reply reply;
        handler({}, reply);
        for (const auto& status : reply.controllers) {
          controller_manager_msgs::ControllerState state;
          state.name = status.name;
          state.state = status.state;
          state.type = status.type;
          for (const auto& claims : status.claimed_resources) {
            controller_manager_msgs::HardwareInterfaceResources resources;
            resources.hardware_interface = claims.hardware_interface;
            resources.resources = claims.resources;
            state.claimed_resources.push_back(resources);
          }
          response.controller.push_back(state);
        }
        return true;
      });
}

ros::ServiceServer serveTypes(ros::NodeHandle& handle, const std::string& name,
                              ServiceHandler<ListControllerTypesRequest> handler) {
  using Service = controller_manager_msgs::ListControllerTypes;
  return handle.advertiseService<Service::Request, Service::Response>(
      name, [handler](Service::Request&, Service::Response& response) {
        ListControllerTypesRequest::Reply reply;
        handler({}, reply);
        response.types = reply.types;
        response.base_classes = reply.base_classes;
        return true;
      });
}

SwitchControllerRequest toSwitch(const controller_manager_msgs::SwitchController::Request& request) {
  SwitchControllerRequest converted;
  converted.start = request.start_controllers;
  converted.stop = request.stop_controllers;
  converted.strictness = request.strictness;
  converted.start_asap = request.start_asap;
  converted.timeout = request.timeout;
  return converted;
}

}  // namespace

ros::ServiceServer serveControllerManager(ros::NodeHandle& handle, const std::string& name,
                                          const ServiceSink& handler, const std::string& robot) {
  using namespace controller_manager_msgs;
  return std::visit(
      [&](const auto& typed) -> ros::ServiceServer {
        using Handler = std::decay_t<decltype(typed)>;
        if constexpr (std::is_same_v<Handler, ServiceHandler<LoadControllerRequest>>) {
          return serveOk<LoadController>(
              handle, name, typed, robot,
              [](const LoadController::Request& request) { return LoadControllerRequest{request.name}; });
        } else if constexpr (std::is_same_v<Handler, ServiceHandler<UnloadControllerRequest>>) {
          return serveOk<UnloadController>(
              handle, name, typed, robot,
              [](const UnloadController::Request& request) { return UnloadControllerRequest{request.name}; });
        } else if constexpr (std::is_same_v<Handler, ServiceHandler<SwitchControllerRequest>>) {
          return serveOk<SwitchController>(handle, name, typed, robot, toSwitch);
        } else if constexpr (std::is_same_v<Handler, ServiceHandler<ReloadControllerLibrariesRequest>>) {
          return serveOk<ReloadControllerLibraries>(
              handle, name, typed, robot, [](const ReloadControllerLibraries::Request& request) {
                return ReloadControllerLibrariesRequest{static_cast<bool>(request.force_kill)};
              });
        } else if constexpr (std::is_same_v<Handler, ServiceHandler<ListControllersRequest>>) {
          return serveList(handle, name, typed);
        } else if constexpr (std::is_same_v<Handler, ServiceHandler<ListControllerTypesRequest>>) {
          return serveTypes(handle, name, typed);
        } else {
          throw std::logic_error("service [" + name + "] is not one of the controller manager's");
        }
      },
      handler);
}

}  // namespace bullet_sim
