#!/usr/bin/env python3
"""rostest node: the seed's `rostopic pub -r 10 /cmd_vel ...` (run as a process) drives a counter-clockwise arc
of radius about v / w, seen on odom."""
import math
import subprocess
import sys
import unittest

import rospy
import rostest
from nav_msgs.msg import Odometry

from bringup_support import Collector, interrupt, yaw


class DriveArc(unittest.TestCase):
    def test_seed_command_drives_a_counter_clockwise_arc(self):
        linear = rospy.get_param("~linear", 0.5)
        angular = rospy.get_param("~angular", 0.5)
        tolerance = rospy.get_param("~radius_tolerance", 0.15)
        odometry = Collector("odom", Odometry)
        odometry.wait_for(lambda m: m, 60, "the first odom")
        command = subprocess.Popen(
            ["rostopic", "pub", "-r", "10", "/cmd_vel", "geometry_msgs/Twist",
             "{linear: {x: %s, y: 0, z: 0}, angular: {x: 0, y: 0, z: %s}}" % (linear, angular)],
            stdout=subprocess.DEVNULL)
        try:
            start = odometry.messages[-1].header.stamp.to_sec()
            seconds = 5.0
            messages = odometry.wait_for(
                lambda m: m[-1].header.stamp.to_sec() >= start + seconds, 120, "%.0f s of driving" % seconds)
        finally:
            interrupt(command, 10)  # as Ctrl-C: rostopic once outlived a SIGTERM by 30 s
        # Steady state: skip the first second of spin-up.
        steady = [m for m in messages if m.header.stamp.to_sec() >= start + 1.0]
        turned = 0.0
        travelled = 0.0
        for before, after in zip(steady, steady[1:]):
            turned += math.remainder(yaw(after.pose.pose.orientation) - yaw(before.pose.pose.orientation), 2 * math.pi)
            travelled += math.hypot(after.pose.pose.position.x - before.pose.pose.position.x,
                                    after.pose.pose.position.y - before.pose.pose.position.y)
        self.assertGreater(turned, 0.2, "+angular.z must turn counter-clockwise")
        if tolerance > 0:
            self.assertAlmostEqual(travelled / turned, linear / angular, delta=tolerance * linear / angular,
                                   msg="arc radius (path %.3f m / turn %.3f rad)" % (travelled, turned))


if __name__ == "__main__":
    rospy.init_node("drive_arc")
    rostest.rosrun("bullet_sim_bringup", "drive_arc", DriveArc, sys.argv)
