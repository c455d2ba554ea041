#!/usr/bin/env python3
"""rostest node: the rover's diff_drive_controller clips a step command to its limits (control.yaml's linear/x
and angular/z) exactly as ros_controllers' speed limiter does: from rest, each update adds at most max_acceleration
* dt until max_velocity (the closed form below, checked on every cmd_vel_out the controller publishes), and a
command older than cmd_vel_timeout stops the rover."""
import sys
import unittest

import rospy
import rostest
from geometry_msgs.msg import Twist, TwistStamped
from nav_msgs.msg import Odometry

from bringup_support import Collector
from rover_support import CONTROLLER, GroundTruth, twist, wait_for_state



class RoverLimits(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.truth = GroundTruth()
        cls.command = rospy.Publisher("/%s/cmd_vel" % CONTROLLER, Twist, queue_size=1)
        wait_for_state(CONTROLLER, "running")

    def drive(self, linear, angular, seconds):
        """Sends the command at 10 Hz for `seconds`; the sim time of the last one."""
        rate = rospy.Rate(10)
        end = rospy.get_time() + seconds
        while True:
            self.command.publish(twist(linear, angular))
            sent = rospy.get_time()
            if sent >= end:
                return sent
            rate.sleep()

    def test_limits_clip_a_step_command(self):
        self.truth.wait_until_stopped(30)
        applied = Collector("/%s/cmd_vel_out" % CONTROLLER, TwistStamped)
        odometry = Collector("/%s/odom" % CONTROLLER, Odometry)
        self.drive(2.0, 3.0, 2.0)  # above max_velocity 1 m/s and 2 rad/s
        ramp = [m for m in applied.messages if m.twist.linear.x > 0]
        self.assertTrue(ramp, "the limited command on cmd_vel_out")
        # Both ramps start at one update, t0; a message may be missed, so t0 comes from the first one seen.
        t0 = ramp[0].header.stamp.to_sec() - ramp[0].twist.linear.x / 3.0
        checked = 0
        for message in ramp:
            t = message.header.stamp.to_sec() - t0
            if t > 1.0:
                break
            self.assertAlmostEqual(message.twist.linear.x, min(1.0, 3.0 * t), delta=1e-6, msg="at %.3f s" % t)
            self.assertAlmostEqual(message.twist.angular.z, min(2.0, 6.0 * t), delta=1e-6, msg="at %.3f s" % t)
            checked += 1
        self.assertGreater(checked, 100, "limited commands seen during the ramp")
        self.assertAlmostEqual(odometry.messages[-1].twist.twist.linear.x, 1.0, delta=0.02)
        self.assertAlmostEqual(odometry.messages[-1].twist.twist.angular.z, 2.0, delta=0.04)
        self.truth.wait_until_stopped(30)

    def test_cmd_vel_timeout_stops_the_rover(self):
        self.truth.wait_until_stopped(30)
        last = self.drive(0.5, 0.0, 2.0)
        # The last command holds for cmd_vel_timeout (0.25 s), then the command is 0, reached at -3 m/s^2.
        self.truth.wait_for(lambda m: m[-1].header.stamp.to_sec() > last + 1.0, 30, "1 s after the last command")
        self.assertGreater(self.truth.speed(self.truth.at(last + 0.2)), 0.45)  # within the timeout
        self.assertLess(self.truth.speed(self.truth.at(last + 0.25 + 0.5 / 3.0 + 0.2)), 0.01)
        self.assertLess(self.truth.speed(self.truth.at(last + 1.0)), 0.01)


if __name__ == "__main__":
    rospy.init_node("rover_limits")
    rostest.rosrun("bullet_sim_bringup", "rover_limits", RoverLimits, sys.argv)
