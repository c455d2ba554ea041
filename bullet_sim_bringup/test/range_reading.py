#!/usr/bin/env python3
"""rostest node: the multi-sensor robot's rangers (libgazebo_ros_range.so) publish sensor_msgs/Range in their
frames, with their radiation and field of view, and read the distance tf gives to the wall x = 3."""
import sys
import unittest

import rospy
import rostest
import tf2_ros
from sensor_msgs.msg import Range

from bringup_support import Collector


class RangeReading(unittest.TestCase):
    def test_rangers_read_the_wall_ahead(self):
        buffer = tf2_ros.Buffer()
        tf2_ros.TransformListener(buffer)
        for topic, frame, radiation, fov in (("range/ir", "ir_link", Range.INFRARED, 0.01),
                                             ("range/sonar", "sonar_link", Range.ULTRASOUND, 1.0)):
            reading = Collector(topic, Range).wait_for(lambda m: m, 60, "a range on " + topic)[0]
            self.assertEqual(reading.header.frame_id, frame)
            self.assertEqual(reading.radiation_type, radiation)
            self.assertAlmostEqual(reading.field_of_view, fov, places=6)
            self.assertAlmostEqual(reading.min_range, 0.02, places=6)
            self.assertAlmostEqual(reading.max_range, 4.0, places=6)
            sensor = buffer.lookup_transform("odom", frame, rospy.Time(0), rospy.Duration(30)).transform
            # Both look straight at the wall; the cone's nearest rays are the middle ones.
            self.assertAlmostEqual(reading.range, 3.0 - sensor.translation.x, delta=0.005)


if __name__ == "__main__":
    rospy.init_node("range_reading")
    rostest.rosrun("bullet_sim_bringup", "range_reading", RangeReading, sys.argv)
