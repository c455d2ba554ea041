#!/usr/bin/env python3
"""rostest node: four threads call the world API at once for CALL_SECONDS (get_model_state, apply_body_wrench,
set_model_configuration, get_link_state), each with its own proxies, as four RL workers would. Every call must be
answered, with success, and no transport error; afterwards the clock goes on and the wheelchair still answers and
drives."""
import math
import threading
import time
import traceback
import unittest

import rospy
import rostest
from gazebo_msgs.srv import (ApplyBodyWrench, GetLinkState, GetModelProperties, GetModelState,
                             SetModelConfiguration)
from geometry_msgs.msg import Point, Twist, Vector3, Wrench
from nav_msgs.msg import Odometry

from bringup_support import Collector

CALL_SECONDS = 30.0  # [wall s] each thread calls for this long
THREADS = ("get_model_state", "apply_body_wrench", "set_model_configuration", "get_link_state")
FEWEST_CALLS = 20  # per thread: fewer means the services stalled
CALL_TIMEOUT = 10.0  # [wall s] a call that takes longer is lost


def proxy(name, service_type, persistent=False):
    rospy.wait_for_service("/gazebo/" + name, timeout=60)
    return rospy.ServiceProxy("/gazebo/" + name, service_type, persistent=persistent)


class Caller(threading.Thread):
    """Calls one service in a loop until `deadline`, with a proxy of its own (a rospy proxy is not thread-safe,
    ros_comm #2078); keeps the count, the refusals and the errors."""

    def __init__(self, kind, call, deadline):
        super().__init__(name=kind, daemon=True)
        self.kind, self.call, self.deadline = kind, call, deadline
        self.calls, self.refused, self.errors, self.slowest = 0, [], [], 0.0

    def run(self):
        while time.monotonic() < self.deadline:
            began = time.monotonic()
            try:
                answer = self.call()
            except Exception:  # a transport error, or anything else: every one is a lost call
                self.errors.append(traceback.format_exc(limit=1).strip().splitlines()[-1])
                continue
            finally:
                self.calls += 1
                self.slowest = max(self.slowest, time.monotonic() - began)
            if not answer.success:
                self.refused.append(answer.status_message)


class WorldApiConcurrency(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("world_api_concurrency")
        cls.odometry = Collector("/odom", Odometry)
        cls.cmd_vel = rospy.Publisher("/cmd_vel", Twist, queue_size=1)
        properties = proxy("get_model_properties", GetModelProperties)("wheelchair")
        assert properties.success, properties.status_message
        cls.link = "wheelchair::" + properties.body_names[0]
        cls.joints = [j for j in properties.joint_names][:2]
        assert cls.joints, "the wheelchair has no joints"

    def callers(self, deadline):
        """One caller per service, each with its own persistent proxy: one connection per thread, as a client
        calling hundreds of times a second keeps. (A connection per call, at about 800 a second, comes back to
        loopback ports still in TIME_WAIT within 30 s: a reset no server can answer, and a lost call.)"""
        get_model_state = proxy("get_model_state", GetModelState, persistent=True)
        apply_body_wrench = proxy("apply_body_wrench", ApplyBodyWrench, persistent=True)
        set_configuration = proxy("set_model_configuration", SetModelConfiguration, persistent=True)
        get_link_state = proxy("get_link_state", GetLinkState, persistent=True)
        calls = {
            "get_model_state": lambda: get_model_state("wheelchair", ""),
            "apply_body_wrench": lambda: apply_body_wrench(self.link, "", Point(), Wrench(Vector3(0, 0, 1), Vector3()),
                                                           rospy.Time(), rospy.Duration(0.001)),
            "set_model_configuration": lambda: set_configuration("wheelchair", "", self.joints,
                                                                 [0.0] * len(self.joints)),
            "get_link_state": lambda: get_link_state(self.link, ""),
        }
        return [Caller(kind, calls[kind], deadline) for kind in THREADS]

    def test_four_threads_get_every_answer(self):
        deadline = time.monotonic() + CALL_SECONDS
        callers = self.callers(deadline)
        for caller in callers:
            caller.start()
        for caller in callers:
            caller.join(CALL_SECONDS + CALL_TIMEOUT)
            self.assertFalse(caller.is_alive(), "a %s call never came back" % caller.kind)
        report = ", ".join("%s %d calls (slowest %.2f s)" % (c.kind, c.calls, c.slowest) for c in callers)
        rospy.loginfo("world_api_concurrency: %s", report)
        for caller in callers:
            self.assertEqual(caller.errors, [], "%s lost calls: %s" % (caller.kind, report))
            self.assertEqual(caller.refused, [], "%s refused calls: %s" % (caller.kind, report))
            self.assertGreaterEqual(caller.calls, FEWEST_CALLS, report)
        self.expect_alive()

    def expect_alive(self):
        """The clock goes on and the wheelchair drives 0.5 s of sim time ahead."""
        start = self.odometry.wait_for(lambda m: m, 30, "odometry")[-1]
        deadline = time.monotonic() + 30
        while self.odometry.messages[-1].header.stamp.to_sec() < start.header.stamp.to_sec() + 0.5:
            self.assertLess(time.monotonic(), deadline, "the clock stopped")
            self.cmd_vel.publish(Twist(Vector3(0.5, 0, 0), Vector3()))
            time.sleep(0.02)
        self.cmd_vel.publish(Twist())
        end = self.odometry.messages[-1].pose.pose.position
        moved = math.hypot(end.x - start.pose.pose.position.x, end.y - start.pose.pose.position.y)
        self.assertGreater(moved, 0.02, "the wheelchair did not drive")


if __name__ == "__main__":
    rostest.rosrun("bullet_sim_bringup", "world_api_concurrency", WorldApiConcurrency)
