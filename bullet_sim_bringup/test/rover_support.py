"""Helpers for the rover's rostest nodes: its controller manager's services, bounded waits on its ground truth,
and the unicycle."""
import math
import time

import rospy
from controller_manager_msgs.srv import ListControllers, LoadController, SwitchController, SwitchControllerRequest
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry

from bringup_support import Collector, yaw

CONTROLLER = "rover_velocity_controller"


def call(service, service_type, *args):
    rospy.wait_for_service(service, timeout=60)
    return rospy.ServiceProxy(service, service_type)(*args)


def controllers():
    """The controller manager's controllers by name: (state, type, claimed resources)."""
    listed = call("/controller_manager/list_controllers", ListControllers).controller
    return {c.name: (c.state, c.type, c.claimed_resources) for c in listed}


def wait_until(condition, timeout, what):
    deadline = time.monotonic() + timeout
    while not condition():
        if time.monotonic() > deadline:
            raise AssertionError("timed out after %.0f s waiting for %s" % (timeout, what))
        time.sleep(0.05)


def wait_for_state(name, state, timeout=60):
    wait_until(lambda: controllers().get(name, ("",))[0] == state, timeout, "%s to be %s" % (name, state))


def switch(start=(), stop=()):
    return call("/controller_manager/switch_controller", SwitchController, list(start), list(stop),
                SwitchControllerRequest.STRICT, False, 0.0).ok


def load(name):
    return call("/controller_manager/load_controller", LoadController, name).ok


def twist(linear, angular):
    message = Twist()
    message.linear.x = linear
    message.angular.z = angular
    return message


class GroundTruth(Collector):
    """The rover's ground truth (libgazebo_ros_p3d.so on ground_truth/state)."""

    def __init__(self):
        Collector.__init__(self, "/ground_truth/state", Odometry)

    def speed(self, message):
        velocity = message.twist.twist.linear
        return math.hypot(velocity.x, velocity.y)

    def wait_until_stopped(self, timeout):
        """Returns once the last 0.5 s of ground truth (25 messages at 50 Hz) stood still."""
        self.wait_for(lambda m: len(m) >= 25 and all(self.speed(x) < 0.01 for x in m[-25:]), timeout,
                      "the rover to stand still")

    def at(self, stamp):
        """The message nearest to `stamp` [s], which must be within a period (20 ms) of it."""
        nearest = min(self.messages, key=lambda m: abs(m.header.stamp.to_sec() - stamp))
        gap = abs(nearest.header.stamp.to_sec() - stamp)
        if gap > 0.021:
            raise AssertionError("no ground truth within %.3f s of %.3f s" % (gap, stamp))
        return nearest


def pose2d(message):
    p = message.pose.pose
    return p.position.x, p.position.y, yaw(p.orientation)


def unicycle(start, linear, angular, seconds):
    """Where a unicycle from `start` (x, y, yaw) ends after `seconds` at `linear` [m/s] and `angular` [rad/s]."""
    x, y, heading = start
    if abs(angular) < 1e-9:
        return x + linear * seconds * math.cos(heading), y + linear * seconds * math.sin(heading), heading
    radius = linear / angular
    end = heading + angular * seconds
    return x + radius * (math.sin(end) - math.sin(heading)), y - radius * (math.cos(end) - math.cos(heading)), end


def unicycle_of(commands, start, begin, end):
    """Where a unicycle from `start` at `begin` [s] is at `end` [s], following `commands` (TwistStamped, in time
    order), each held until the next."""
    pose = start
    held = None
    t = begin
    for command in commands:
        stamp = command.header.stamp.to_sec()
        if stamp > t and held is not None:
            pose = unicycle(pose, held.twist.linear.x, held.twist.angular.z, min(stamp, end) - t)
            t = min(stamp, end)
        if stamp >= end:
            break
        held = command
    if held is not None and t < end:
        pose = unicycle(pose, held.twist.linear.x, held.twist.angular.z, end - t)
    return pose


def angle_between(a, b):
    return abs(math.remainder(a - b, 2 * math.pi))
