#!/usr/bin/env python3
"""rostest node: the rover, driven through ros_control as its launch file starts it (Husky's form), follows
`rostopic pub -r 10 /rover_velocity_controller/cmd_vel` (run as a process): after the spin-up, a 5 s arc at
v 0.5 m/s and w 0.3 rad/s ends, on the ground truth, within 5 cm and 0.05 rad of the unicycle that follows the
command as the controller applied it (cmd_vel_out: a publisher that stalls past cmd_vel_timeout on a loaded
machine stops the rover for a moment, and the oracle with it); the controller's odometry and tf agree with the
ground truth as closely; /joint_states has every wheel."""
import subprocess
import sys
import unittest

import rospy
import rostest
import tf2_ros
from geometry_msgs.msg import TwistStamped
from nav_msgs.msg import Odometry
from sensor_msgs.msg import JointState

from bringup_support import Collector, interrupt, yaw
from rover_support import CONTROLLER, GroundTruth, angle_between, pose2d, unicycle_of, wait_for_state

WHEELS = ["front_left_wheel", "front_right_wheel", "rear_left_wheel", "rear_right_wheel"]


class RoverDrive(unittest.TestCase):
    def test_drives_the_unicycles_arc(self):
        truth = GroundTruth()
        odometry = Collector("/%s/odom" % CONTROLLER, Odometry)
        joints = Collector("/joint_states", JointState)
        applied = Collector("/%s/cmd_vel_out" % CONTROLLER, TwistStamped)
        tf = tf2_ros.Buffer(cache_time=rospy.Duration(60))
        tf2_ros.TransformListener(tf)
        wait_for_state(CONTROLLER, "running")
        truth.wait_for(lambda m: m, 60, "the ground truth")
        command = subprocess.Popen(
            ["rostopic", "pub", "-r", "10", "/%s/cmd_vel" % CONTROLLER, "geometry_msgs/Twist",
             "{linear: {x: 0.5, y: 0, z: 0}, angular: {x: 0, y: 0, z: 0.3}}"], stdout=subprocess.DEVNULL)
        try:
            moving = odometry.wait_for(lambda m: m and m[-1].twist.twist.linear.x > 0.01, 60, "the rover to move")
            start = moving[-1].header.stamp.to_sec() + 1.0  # after 1 s of spin-up
            end = start + 5.0
            truth.wait_for(lambda m: m[-1].header.stamp.to_sec() >= end, 120, "5 s of driving after the spin-up")
            odometry.wait_for(lambda m: m[-1].header.stamp.to_sec() >= end, 30, "the odometry at the end")
        finally:
            interrupt(command, 10)  # as Ctrl-C: rostopic once outlived a SIGTERM by 30 s

        first, last = truth.at(start), truth.at(end)
        commands = [m for m in applied.messages if m.twist.linear.x > 0.499]
        self.assertGreater(len(commands), 1000, "the command the controller applied, on cmd_vel_out")
        expected = unicycle_of(applied.messages, pose2d(first), first.header.stamp.to_sec(), last.header.stamp.to_sec())
        actual = pose2d(last)
        rospy.loginfo("ground truth %s, unicycle %s", actual, expected)
        self.assertLess(((actual[0] - expected[0]) ** 2 + (actual[1] - expected[1]) ** 2) ** 0.5, 0.05,
                        "ground truth %s, unicycle %s" % (actual, expected))
        self.assertLess(angle_between(actual[2], expected[2]), 0.05)

        # The odometry's frame is where the rover was spawned: the world's origin.
        odom = min(odometry.messages, key=lambda m: abs(m.header.stamp.to_sec() - end))
        truth_then = truth.at(odom.header.stamp.to_sec())
        for name, estimate in (("odometry", pose2d(odom)), ("tf", self.tf_pose(tf, odom.header.stamp))):
            reference = pose2d(truth_then)
            self.assertLess(((estimate[0] - reference[0]) ** 2 + (estimate[1] - reference[1]) ** 2) ** 0.5, 0.05,
                            "%s %s, ground truth %s" % (name, estimate, reference))
            self.assertLess(angle_between(estimate[2], reference[2]), 0.05, name)

        self.assertEqual(sorted(joints.messages[-1].name), WHEELS)
        self.assertEqual(len(joints.messages[-1].position), 4)

    def tf_pose(self, tf, stamp):
        transform = tf.lookup_transform("odom", "base_link", stamp, rospy.Duration(10)).transform
        return transform.translation.x, transform.translation.y, yaw(transform.rotation)


if __name__ == "__main__":
    rospy.init_node("rover_drive")
    rostest.rosrun("bullet_sim_bringup", "rover_drive", RoverDrive, sys.argv)
