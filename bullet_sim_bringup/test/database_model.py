#!/usr/bin/env python3
"""rostest node: the model that spawn_model -database found on GAZEBO_MODEL_PATH is in the world: its lidar,
0.3 m up at x = -2 facing +x, sees the shapes world's 1 m cube (faces at x = +-0.5) straight ahead."""
import sys
import unittest

import rospy
import rostest
from sensor_msgs.msg import LaserScan

from bringup_support import Collector


class DatabaseModel(unittest.TestCase):
    def test_the_database_model_sees_the_cube(self):
        scan = Collector("scan", LaserScan).wait_for(lambda m: m, 60, "the lidar box's scan")[0]
        ahead = round((0 - scan.angle_min) / scan.angle_increment)
        self.assertAlmostEqual(scan.ranges[ahead], 1.5, delta=0.01, msg="from x = -2 to the cube's face at -0.5")


if __name__ == "__main__":
    rospy.init_node("database_model")
    rostest.rosrun("bullet_sim_bringup", "database_model", DatabaseModel, sys.argv)
