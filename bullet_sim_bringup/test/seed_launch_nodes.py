#!/usr/bin/env python3
"""rostest node: the other nodes of seed 000's gazebo.launch run too: tf's static_transform_publisher puts
base_link -> base_footprint on /tf (tf1 republishes it every 40 ms), and rostopic latches true on /calibrated."""
import sys
import unittest

import rospy
import rostest
from std_msgs.msg import Bool
from tf2_msgs.msg import TFMessage

from bringup_support import Collector


class SeedLaunchNodes(unittest.TestCase):
    def test_static_transform_publisher_runs(self):
        transforms = Collector("/tf", TFMessage)
        transforms.wait_for(
            lambda messages: any(t.header.frame_id == "base_link" and t.child_frame_id == "base_footprint"
                                 for m in messages for t in m.transforms),
            60, "the seed's static base_link -> base_footprint on /tf")

    def test_calibrated_is_published(self):
        calibrated = Collector("/calibrated", Bool).wait_for(lambda m: m, 60, "/calibrated")
        self.assertTrue(calibrated[0].data)


if __name__ == "__main__":
    rospy.init_node("seed_launch_nodes")
    rostest.rosrun("bullet_sim_bringup", "seed_launch_nodes", SeedLaunchNodes, sys.argv)
