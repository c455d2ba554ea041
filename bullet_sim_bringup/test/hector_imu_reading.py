#!/usr/bin/env python3
"""rostest node: hector's IMU on the multi-sensor robot at rest reads +g up and no rotation within its noise and
drift (0.005 per axis), in imu_link; it publishes its biases and serves its calibrate service."""
import sys
import unittest

import rospy
import rostest
from sensor_msgs.msg import Imu
from std_srvs.srv import Empty

from bringup_support import Collector


class HectorImuReading(unittest.TestCase):
    def test_at_rest_it_reads_gravity_up(self):
        count = 50
        samples = Collector("imu/data", Imu).wait_for(lambda m: len(m) >= count, 60, "%d IMU samples" % count)
        samples = samples[:count]
        self.assertEqual(samples[0].header.frame_id, "imu_link")
        mean = [sum(getattr(s.linear_acceleration, axis) for s in samples) / count for axis in "xyz"]
        rate = [sum(getattr(s.angular_velocity, axis) for s in samples) / count for axis in "xyz"]
        bound = 4 * 0.005 + 4 * 0.005 / count ** 0.5  # the initial drift, and the white noise's mean
        self.assertAlmostEqual(mean[0], 0, delta=bound)
        self.assertAlmostEqual(mean[1], 0, delta=bound)
        self.assertAlmostEqual(mean[2], 9.81, delta=bound)
        for axis in rate:
            self.assertAlmostEqual(axis, 0, delta=bound)
        self.assertAlmostEqual(samples[0].angular_velocity_covariance[0], 0.005 ** 2, places=9)
        bias = Collector("imu/data/bias", Imu).wait_for(lambda m: m, 30, "a bias sample")[0]
        self.assertEqual(bias.header.frame_id, "imu_link")
        rospy.wait_for_service("imu/data/calibrate", 30)
        rospy.ServiceProxy("imu/data/calibrate", Empty)()


if __name__ == "__main__":
    rospy.init_node("hector_imu_reading")
    rostest.rosrun("bullet_sim_bringup", "hector_imu_reading", HectorImuReading, sys.argv)
