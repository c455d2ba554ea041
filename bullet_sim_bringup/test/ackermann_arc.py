#!/usr/bin/env python3
"""rostest node: the Tianracer through ros_control, as its launch file starts it. cmd_vel (v 1.0, w 0.5) at 10 Hz
turns it, once it has gathered speed, at w and v on the ground truth (/gazebo/model_states), within 5 %."""
import math
import time
import unittest

import rospy
import rostest
from gazebo_msgs.msg import ModelStates
from geometry_msgs.msg import Twist

from bringup_support import Collector, yaw

V, W = 1.0, 0.5


class AckermannArc(unittest.TestCase):
    def test_cmd_vel_turns_it_at_v_and_w(self):
        states = Collector("/gazebo/model_states", ModelStates)
        states.wait_for(lambda m: m and "tianracer" in m[-1].name, 60, "the tianracer in model_states")
        command = rospy.Publisher("/cmd_vel", Twist, queue_size=1)
        twist = Twist()
        twist.linear.x, twist.angular.z = V, W
        deadline = time.monotonic() + 60
        samples = []
        sampling_from = None  # one second after the first command: the car gathers speed
        while len(samples) < 2 or samples[-1][0] - samples[0][0] < 2.0:
            self.assertLess(time.monotonic(), deadline, "2 s of driving within 60 s")
            command.publish(twist)
            rospy.sleep(0.1)
            now = rospy.get_time()
            last = states.messages[-1]
            pose = last.pose[last.name.index("tianracer")]
            if sampling_from is None:
                sampling_from = now + 1.0
            if now >= sampling_from:
                samples.append((now, pose.position.x, pose.position.y, yaw(pose.orientation)))
        (t0, x0, y0, h0), (t1, x1, y1, h1) = samples[0], samples[-1]
        turn_rate = math.remainder(h1 - h0, 2 * math.pi) / (t1 - t0)
        self.assertAlmostEqual(turn_rate, W, delta=0.05 * W)
        # The chord of an arc of radius R over angle a is 2 R sin(a / 2), for base_footprint as for the rear axle.
        chord = math.hypot(x1 - x0, y1 - y0)
        angle = h1 - h0
        radius = math.hypot(V / W, 0.136)  # base_footprint is 0.136 m ahead of the rear axle
        self.assertAlmostEqual(chord, 2 * radius * math.sin(angle / 2), delta=0.05 * chord)
        twist.linear.x = twist.angular.z = 0.0
        command.publish(twist)


if __name__ == "__main__":
    rospy.init_node("ackermann_arc")
    rostest.rosrun("bullet_sim_bringup", "ackermann_arc", AckermannArc)
