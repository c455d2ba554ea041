#!/usr/bin/env python3
"""rostest node: /clock advances; pause_physics freezes it while it keeps being published; reset_simulation
brings back the spawn pose, with time restarting at the first step."""
import math
import subprocess
import sys
import unittest

import rospy
import rostest
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Clock
from std_srvs.srv import Empty

from bringup_support import Collector, interrupt


def service(name):
    rospy.wait_for_service(name, timeout=60)
    return rospy.ServiceProxy(name, Empty)


class ClockAndServices(unittest.TestCase):
    def setUp(self):
        self.clock = Collector("/clock", Clock)
        self.odometry = Collector("odom", Odometry)

    def test_clock_advances_and_is_never_zero(self):
        ticks = self.clock.wait_for(lambda m: len(m) >= 10, 60, "10 clock messages")
        times = [m.clock.to_sec() for m in ticks]
        self.assertGreater(min(times), 0)
        self.assertEqual(times, sorted(times))
        self.assertGreater(times[-1], times[0])

    def test_pause_freezes_the_clock_while_it_keeps_being_published(self):
        self.clock.wait_for(lambda m: m, 60, "a clock message")
        service("/gazebo/pause_physics")()
        paused_at = len(self.clock.wait_for(lambda m: m, 10, "a clock message"))
        ticks = self.clock.wait_for(lambda m: len(m) >= paused_at + 20, 30, "20 clock messages while paused")
        frozen = [m.clock.to_sec() for m in ticks[paused_at + 1:]]
        self.assertEqual(len(set(frozen)), 1, "the clock moved while paused")
        service("/gazebo/unpause_physics")()
        self.clock.wait_for(lambda m: m[-1].clock.to_sec() > frozen[-1], 30, "the clock to move again")

    def test_reset_simulation_restores_the_spawn_pose_and_restarts_time(self):
        spawn = self.odometry.wait_for(lambda m: m, 60, "the first odom")[0].pose.pose.position
        command = subprocess.Popen(["rostopic", "pub", "-r", "10", "/cmd_vel", "geometry_msgs/Twist",
                                    "{linear: {x: 0.5, y: 0, z: 0}, angular: {x: 0, y: 0, z: 0.5}}"],
                                   stdout=subprocess.DEVNULL)
        try:
            self.odometry.wait_for(
                lambda m: math.hypot(m[-1].pose.pose.position.x - spawn.x, m[-1].pose.pose.position.y - spawn.y) > 0.3,
                120, "the robot to move 0.3 m")
        finally:
            interrupt(command, 10)  # as Ctrl-C: rostopic once outlived a SIGTERM by 30 s
        before_reset = self.clock.messages[-1].clock.to_sec()
        seen = len(self.clock.messages)
        # An odom published just before the reset may still be in flight: the first one after it is stamped
        # earlier than the last one before it, since time restarted.
        seen_odometry = len(self.odometry.messages)
        last_stamp = self.odometry.messages[-1].header.stamp
        service("/gazebo/reset_simulation")()
        clocks = self.clock.wait_for(lambda m: any(c.clock.to_sec() < before_reset for c in m[seen:]), 30,
                                     "the clock to restart")
        restarted = next(c.clock.to_sec() for c in clocks[seen:] if c.clock.to_sec() < before_reset)
        self.assertGreater(restarted, 0)
        self.assertLess(restarted, 0.5)
        after_reset = lambda m: [o for o in m[seen_odometry:] if o.header.stamp < last_stamp]
        odometry = after_reset(self.odometry.wait_for(after_reset, 30, "odom after the reset"))[0]
        # The robot is back where it spawned; the command stopped, and its timeout stops the drive.
        self.assertAlmostEqual(odometry.pose.pose.position.x, spawn.x, delta=0.01)
        self.assertAlmostEqual(odometry.pose.pose.position.y, spawn.y, delta=0.01)


if __name__ == "__main__":
    rospy.init_node("clock_and_services")
    rostest.rosrun("bullet_sim_bringup", "clock_and_services", ClockAndServices, sys.argv)
