#!/usr/bin/env python3
"""rostest node: the scan has the shape and angles the robot description's ray sensor declares (Gazebo's
angle_increment = (max - min) / (N - 1)), in the frame its plugin names."""
import sys
import unittest

import rospy
import rostest
from sensor_msgs.msg import LaserScan

from bringup_support import Collector, ray_sensor


class ScanShape(unittest.TestCase):
    def test_scan_matches_the_declared_sensor(self):
        sensor = ray_sensor(rospy.get_param("robot_description"))
        horizontal = sensor.find("ray/scan/horizontal")
        beams = round(float(horizontal.findtext("samples")) * float(horizontal.findtext("resolution", "1")))
        minimum = float(horizontal.findtext("min_angle"))
        maximum = float(horizontal.findtext("max_angle"))
        scan = Collector("scan", LaserScan).wait_for(lambda m: m, 60, "a scan")[0]
        self.assertEqual(len(scan.ranges), beams)
        self.assertAlmostEqual(scan.angle_min, minimum, places=6)
        self.assertAlmostEqual(scan.angle_max, maximum, places=6)
        self.assertAlmostEqual(scan.angle_increment, (maximum - minimum) / (beams - 1), places=9)
        self.assertAlmostEqual(scan.range_min, float(sensor.findtext("ray/range/min")), places=6)
        self.assertAlmostEqual(scan.range_max, float(sensor.findtext("ray/range/max")), places=6)
        self.assertAlmostEqual(scan.scan_time, 1.0 / float(sensor.findtext("update_rate")), places=6)
        self.assertEqual(scan.header.frame_id, sensor.findtext("plugin/frameName"))
        self.assertGreater(scan.header.stamp.to_sec(), 0)


if __name__ == "__main__":
    rospy.init_node("scan_shape")
    rostest.rosrun("bullet_sim_bringup", "scan_shape", ScanShape, sys.argv)
