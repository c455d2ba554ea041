#!/usr/bin/env python3
"""rostest node: `rostopic pub -r 10 /cmd_vel` with x, y and a turn rate, run as a process, moves a holonomic
robot: its odom (nav_msgs/Odometry, odom -> base_footprint) reports the commanded body velocities, turns
counter-clockwise, and the tf odom -> base_footprint agrees with it."""
import math
import subprocess
import sys
import unittest

import rospy
import rostest
import tf2_ros
from nav_msgs.msg import Odometry

from bringup_support import Collector, interrupt, yaw


class HolonomicDrive(unittest.TestCase):
    def test_cmd_vel_moves_the_robot_sideways_and_turning(self):
        odometry = Collector("odom", Odometry)
        odometry.wait_for(lambda m: m, 60, "the first odom")
        buffer = tf2_ros.Buffer()
        tf2_ros.TransformListener(buffer)
        command = subprocess.Popen(
            ["rostopic", "pub", "-r", "10", "/cmd_vel", "geometry_msgs/Twist",
             "{linear: {x: 0.3, y: 0.2, z: 0}, angular: {x: 0, y: 0, z: 0.5}}"], stdout=subprocess.DEVNULL)
        try:
            first = odometry.messages[-1]
            start = first.header.stamp.to_sec()
            messages = odometry.wait_for(lambda m: m[-1].header.stamp.to_sec() >= start + 3.0, 90, "3 s of driving")
        finally:
            interrupt(command, 10)  # as Ctrl-C: rostopic once outlived a SIGTERM by 30 s
        last = messages[-1]
        self.assertEqual(last.header.frame_id, "odom")
        self.assertEqual(last.child_frame_id, "base_footprint")
        self.assertAlmostEqual(last.twist.twist.linear.x, 0.3, delta=0.01)
        self.assertAlmostEqual(last.twist.twist.linear.y, 0.2, delta=0.01)
        self.assertAlmostEqual(last.twist.twist.angular.z, 0.5, delta=0.01)
        turned = math.remainder(yaw(last.pose.pose.orientation) - yaw(first.pose.pose.orientation), 2 * math.pi)
        self.assertGreater(turned, 0.5, "+angular.z turns counter-clockwise")
        moved = math.hypot(last.pose.pose.position.x - first.pose.pose.position.x,
                           last.pose.pose.position.y - first.pose.pose.position.y)
        self.assertGreater(moved, 0.3)
        tf = buffer.lookup_transform("odom", "base_footprint", last.header.stamp, rospy.Duration(30)).transform
        self.assertAlmostEqual(tf.translation.x, last.pose.pose.position.x, delta=1e-6)
        self.assertAlmostEqual(tf.translation.y, last.pose.pose.position.y, delta=1e-6)
        self.assertAlmostEqual(yaw(tf.rotation), yaw(last.pose.pose.orientation), delta=1e-6)


if __name__ == "__main__":
    rospy.init_node("holonomic_drive")
    rostest.rosrun("bullet_sim_bringup", "holonomic_drive", HolonomicDrive, sys.argv)
