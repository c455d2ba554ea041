"""Calls on a controller manager's services (controller_manager_msgs), under the function names of ros_control's
controller_manager.controller_manager_interface. The service names are relative, so the node's namespace
(ROS_NAMESPACE, or a launch file's ns) says which controller manager is meant."""

from __future__ import print_function

import rospy
from controller_manager_msgs.srv import (ListControllers, ListControllerTypes, LoadController,
                                         ReloadControllerLibraries, SwitchController, SwitchControllerRequest,
                                         UnloadController)

SERVICES = "controller_manager/"


def _call(name, service_type, *args):
    """Waits for the service `name` of the controller manager, then calls it with `args`."""
    rospy.wait_for_service(SERVICES + name)
    return rospy.ServiceProxy(SERVICES + name, service_type)(*args)


def list_controller_types():
    for controller_type, base_class in zip(*_types()):
        print(controller_type, base_class)


def _types():
    response = _call("list_controller_types", ListControllerTypes)
    return response.types, response.base_classes


def list_controllers():
    controllers = _call("list_controllers", ListControllers).controller
    if not controllers:
        print("No controllers are loaded")
    for controller in controllers:
        interfaces = sorted(set(claim.hardware_interface for claim in controller.claimed_resources))
        print("'%s' - '%s' ( %s )" % (controller.name, "+".join(interfaces), controller.state))
    return controllers


def load_controller(name):
    ok = _call("load_controller", LoadController, name).ok
    print(("Loaded '%s'" if ok else "Error when loading '%s'") % name)
    return ok


def unload_controller(name):
    ok = _call("unload_controller", UnloadController, name).ok
    print(("Unloaded '%s'" if ok else "Error when unloading '%s'") % name)
    return ok


def start_stop_controllers(start_controllers=(), stop_controllers=()):
    ok = _call("switch_controller", SwitchController, list(start_controllers), list(stop_controllers),
               SwitchControllerRequest.STRICT, False, 0.0).ok
    if ok:
        if start_controllers:
            print("Started %s" % list(start_controllers))
        if stop_controllers:
            print("Stopped %s" % list(stop_controllers))
    else:
        print("Error when starting %s and stopping %s" % (list(start_controllers), list(stop_controllers)))
    return ok


def start_controller(name):
    return start_stop_controllers(start_controllers=[name])


def start_controllers(names):
    return start_stop_controllers(start_controllers=names)


def stop_controller(name):
    return start_stop_controllers(stop_controllers=[name])


def stop_controllers(names):
    return start_stop_controllers(stop_controllers=names)


def reload_libraries(force_kill, restore=False):
    """Reloads the controller libraries; with `restore`, loads and starts again the controllers there were."""
    before = _call("list_controllers", ListControllers).controller if restore else []
    ok = _call("reload_controller_libraries", ReloadControllerLibraries, force_kill).ok
    print("Reloaded the controller libraries" if ok else
          "Could not reload the controller libraries: are controllers still loaded? (--force-kill unloads them)")
    if restore:
        for controller in before:
            _call("load_controller", LoadController, controller.name)
        running = [controller.name for controller in before if controller.state == "running"]
        _call("switch_controller", SwitchController, running, [], SwitchControllerRequest.BEST_EFFORT, False, 0.0)
        print("Restored the controllers")
    return ok
