#!/usr/bin/env python3
"""rostest node: a multi-channel lidar (libgazebo_ros_velodyne_laser.so) publishes sensor_msgs/PointCloud2 with
x y z intensity ring; spawned at the middle of test_room.world, its points lie inside the room."""
import sys
import unittest

import rospy
import rostest
from sensor_msgs import point_cloud2
from sensor_msgs.msg import PointCloud2

from bringup_support import Collector


class PointCloud(unittest.TestCase):
    def test_cloud_has_the_velodyne_fields_and_stays_in_the_room(self):
        cloud = Collector("points", PointCloud2).wait_for(lambda m: m, 60, "a point cloud")[0]
        self.assertEqual([f.name for f in cloud.fields], ["x", "y", "z", "intensity", "ring"])
        self.assertEqual(cloud.header.frame_id, "lidar")
        points = list(point_cloud2.read_points(cloud, field_names=("x", "y", "z", "ring")))
        self.assertGreater(len(points), 360 * 8)
        # From the room's centre the top channels clear the 1 m walls and return nothing.
        rings = {ring for _, _, _, ring in points}
        self.assertEqual(min(rings), 0)
        self.assertLessEqual(max(rings), 15)
        self.assertGreaterEqual(len(rings), 8)
        # The sensor sits 0.5 m above the room's centre, facing +x: the room spans x +-3 m, y +-2 m around it.
        for x, y, z, _ in points:
            self.assertLessEqual(abs(x), 3.001)
            self.assertLessEqual(abs(y), 2.001)
            self.assertGreaterEqual(z, -0.501)


if __name__ == "__main__":
    rospy.init_node("point_cloud")
    rostest.rosrun("bullet_sim_bringup", "point_cloud", PointCloud, sys.argv)
