#!/usr/bin/env python3
"""rostest node: the simulator under bad input. A NaN or inf in cmd_vel is ignored (the robot stays put, the node
keeps stepping); the drive's commandTimeout stops the robot when commands stop; a malformed and an empty robot
description, or a flag that is not a number, make spawn_model exit non-zero with the reason, while the simulator
keeps running."""
import math
import os
import subprocess
import sys
import threading
import unittest

import rospkg
import rospy
import rostest
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Clock
from std_srvs.srv import Empty

from bringup_support import Collector


class Commander:
    """Publishes one Twist on /cmd_vel at 10 Hz (as `rostopic pub -r 10` does) until stop()."""

    def __init__(self, linear, angular):
        self._publisher = rospy.Publisher("/cmd_vel", Twist, queue_size=1)
        self._twist = Twist()
        self._twist.linear.x = linear
        self._twist.angular.z = angular
        self._stopped = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    def _run(self):
        while not self._stopped.wait(0.1) and not rospy.is_shutdown():
            self._publisher.publish(self._twist)

    def stop(self):
        self._stopped.set()
        self._thread.join(timeout=5)
        self._publisher.unregister()


def travelled(messages, start, end):
    """Distance [m] between the odometry poses stamped nearest after sim times `start` and `end` [s]."""
    first = next(m for m in messages if m.header.stamp.to_sec() >= start).pose.pose.position
    last = next(m for m in messages if m.header.stamp.to_sec() >= end).pose.pose.position
    return math.hypot(last.x - first.x, last.y - first.y)


class BadInput(unittest.TestCase):
    def setUp(self):
        self.clock = Collector("/clock", Clock)
        self.odometry = Collector("odom", Odometry)
        self.odometry.wait_for(lambda m: m, 60, "the first odom")

    def drive_for(self, linear, angular, seconds):
        """Commands (linear, angular) for `seconds` of sim time; returns the sim time of the last command."""
        start = self.odometry.messages[-1].header.stamp.to_sec()
        commander = Commander(linear, angular)
        try:
            self.odometry.wait_for(lambda m: m[-1].header.stamp.to_sec() >= start + seconds, 60,
                                   "%.0f s of commands" % seconds)
        finally:
            commander.stop()
        return self.odometry.messages[-1].header.stamp.to_sec()

    def wait_until(self, sim_time):
        return self.odometry.wait_for(lambda m: m[-1].header.stamp.to_sec() >= sim_time, 60,
                                      "odom at %.1f s of sim time" % sim_time)

    def test_nan_and_inf_commands_are_ignored(self):
        # Let any earlier command time out (0.5 s) and the chair come to rest.
        self.wait_until(self.odometry.messages[-1].header.stamp.to_sec() + 2.0)
        start = self.odometry.messages[-1].header.stamp.to_sec()
        for linear, angular in ((float("nan"), 0.0), (0.0, float("inf")), (float("-inf"), float("nan"))):
            self.drive_for(linear, angular, 1.0)
        messages = self.wait_until(self.odometry.messages[-1].header.stamp.to_sec() + 0.5)
        self.assertLess(travelled(messages, start, messages[-1].header.stamp.to_sec()), 0.005,
                        "the chair moved on non-finite commands")
        seen = len(self.clock.messages)
        self.clock.wait_for(lambda m: len(m) > seen + 10, 30, "the clock to go on after the bad commands")
        # The drive still takes a good command afterwards.
        last = self.drive_for(0.3, 0.0, 1.5)
        self.assertGreater(travelled(self.odometry.messages, last - 0.5, last), 0.05)

    def test_command_timeout_stops_the_chair(self):
        last_command = self.drive_for(0.3, 0.0, 2.0)
        messages = self.odometry.messages
        self.assertGreater(travelled(messages, last_command - 1.0, last_command), 0.15, "the chair did not drive")
        # commandTimeout is 0.5 s and wheelAcceleration 1.8 m/s^2: stopped well within 1.5 s.
        messages = self.wait_until(last_command + 2.5)
        self.assertLess(travelled(messages, last_command + 1.5, last_command + 2.5), 0.005,
                        "the chair kept driving after the commands stopped")

    def spawn_model(self, *source):
        command = ["rosrun", "bullet_sim", "spawn_model", "-urdf", *source, "-model", "bad", "-timeout", "30"]
        return subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=60)

    def test_a_flag_that_is_not_a_number_fails_the_spawn_with_the_reason(self):
        fixtures = os.path.join(rospkg.RosPack().get_path("bullet_sim"), "test", "fixtures", "robots")
        command = ["rosrun", "bullet_sim", "spawn_model", "-urdf", "-file", os.path.join(fixtures, "minimal.urdf"),
                   "-model", "bad", "-timeout", "soon"]
        result = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=60)
        self.assertEqual(result.returncode, 1, result.stdout + result.stderr)
        self.assertIn("-timeout must be a number, not [soon]", result.stderr)

    def test_a_file_that_is_not_a_regular_file_fails_the_spawn_promptly(self):
        # A directory threw an uncaught exception, and /dev/zero was read for ever.
        for path in ("/tmp", "/dev/zero"):
            result = self.spawn_model("-file", path)
            self.assertEqual(result.returncode, 1, result.stdout + result.stderr)
            self.assertIn("-file [%s] is not a regular file" % path, result.stderr)

    def test_bad_descriptions_fail_the_spawn_and_the_simulator_keeps_running(self):
        fixtures = os.path.join(rospkg.RosPack().get_path("bullet_sim"), "test", "fixtures", "robots")
        malformed = self.spawn_model("-file", os.path.join(fixtures, "fail_malformed.urdf"))
        self.assertNotEqual(malformed.returncode, 0, malformed.stdout + malformed.stderr)
        self.assertIn("closed by a different tag", malformed.stderr)
        rospy.set_param("empty_description", "")
        empty = self.spawn_model("-param", "empty_description")
        self.assertNotEqual(empty.returncode, 0, empty.stdout + empty.stderr)
        self.assertIn("the robot description is empty", empty.stderr)

        for name in ("/gazebo/pause_physics", "/gazebo/unpause_physics"):
            rospy.wait_for_service(name, timeout=30)
            rospy.ServiceProxy(name, Empty)()
        latest = self.clock.wait_for(lambda m: m, 30, "a clock message")[-1].clock.to_sec()
        self.clock.wait_for(lambda m: m[-1].clock.to_sec() > latest + 0.5, 30, "the clock to advance")


if __name__ == "__main__":
    rospy.init_node("bad_input")
    rostest.rosrun("bullet_sim_bringup", "bad_input", BadInput, sys.argv)
