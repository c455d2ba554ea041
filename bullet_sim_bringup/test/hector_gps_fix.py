#!/usr/bin/env python3
"""rostest node: hector's GPS on the multi-sensor robot spawned 100 m north (+x) of its reference (49.9 N, 8.9 E)
publishes a fix whose latitude is 100 m / the WGS84 meridian radius further north, and a velocity at rest."""
import math
import sys
import unittest

import rospy
import rostest
from geometry_msgs.msg import Vector3Stamped
from sensor_msgs.msg import NavSatFix, NavSatStatus

from bringup_support import Collector

A = 6378137.0
E2 = 6.69437999014e-3


def meridian_radius(latitude):
    return A * (1 - E2) / (1 - E2 * math.sin(math.radians(latitude)) ** 2) ** 1.5


class HectorGpsFix(unittest.TestCase):
    def test_fix_and_velocity(self):
        fix = Collector("navsat/fix", NavSatFix).wait_for(lambda m: m, 60, "a fix")[0]
        self.assertEqual(fix.header.frame_id, "gps_link")
        self.assertEqual(fix.status.status, NavSatStatus.STATUS_FIX)
        self.assertEqual(fix.position_covariance_type, NavSatFix.COVARIANCE_TYPE_DIAGONAL_KNOWN)
        # The drift (0.0001 m) is far below the tolerance.
        self.assertAlmostEqual(fix.latitude, 49.9 + math.degrees(100 / meridian_radius(49.9)), delta=1e-7)
        self.assertAlmostEqual(fix.longitude, 8.9, delta=1e-7)
        velocity = Collector("navsat/vel", Vector3Stamped).wait_for(lambda m: m, 30, "a velocity")[0]
        self.assertEqual(velocity.header.frame_id, "gps_link")
        self.assertLess(math.hypot(velocity.vector.x, velocity.vector.y), 0.01)


if __name__ == "__main__":
    rospy.init_node("hector_gps_fix")
    rostest.rosrun("bullet_sim_bringup", "hector_gps_fix", HectorGpsFix, sys.argv)
