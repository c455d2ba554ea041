#!/usr/bin/env python3
"""rostest node: spawned facing the wall x = ~wall_x of test_room.world, the beam nearest 0 rad, averaged over
~scans scans with the sensor's noise on, reads the distance tf gives from the lidar to that wall, within 1 cm."""
import math
import sys
import unittest

import rospy
import rostest
import tf2_ros
from sensor_msgs.msg import LaserScan

from bringup_support import Collector, yaw


class WallDistance(unittest.TestCase):
    def test_beam_ahead_reads_the_wall_distance(self):
        wall_x = rospy.get_param("~wall_x", 3.0)
        count = rospy.get_param("~scans", 25)
        scans = Collector("scan", LaserScan).wait_for(lambda m: len(m) >= count, 120, "%d scans" % count)[:count]
        frame = scans[0].header.frame_id
        buffer = tf2_ros.Buffer()
        tf2_ros.TransformListener(buffer)
        sensor = buffer.lookup_transform("odom", frame, rospy.Time(0), rospy.Duration(30)).transform
        heading = yaw(sensor.rotation)
        index = min(range(len(scans[0].ranges)),
                    key=lambda i: abs(scans[0].angle_min + i * scans[0].angle_increment))
        angle = heading + scans[0].angle_min + index * scans[0].angle_increment
        expected = (wall_x - sensor.translation.x) / math.cos(angle)
        readings = [scan.ranges[index] for scan in scans]
        self.assertTrue(all(math.isfinite(r) for r in readings), readings)
        self.assertAlmostEqual(sum(readings) / len(readings), expected, delta=0.01)


if __name__ == "__main__":
    rospy.init_node("wall_distance")
    rostest.rosrun("bullet_sim_bringup", "wall_distance", WallDistance, sys.argv)
