#!/usr/bin/env python3
"""rostest node: gazebo_ros's empty_world.launch hands its arguments to bullet_sim's simulator (node gazebo):
the world, the pause (the clock stands still until unpause_physics), the seed and /clock's rate."""
import sys
import unittest

import rospy
import rostest
from rosgraph_msgs.msg import Clock
from std_srvs.srv import Empty

from bringup_support import Collector

TIMEOUT = 60.0  # [s]


class EmptyWorldArguments(unittest.TestCase):
    def test_the_simulator_gets_the_arguments(self):
        rospy.wait_for_service("/gazebo/unpause_physics", TIMEOUT)
        self.assertIs(rospy.get_param("/use_sim_time"), True)
        self.assertEqual(rospy.get_param("/gazebo/world"), "worlds/shapes.world")
        self.assertEqual(rospy.get_param("/gazebo/seed"), 5)
        self.assertEqual(rospy.get_param("/gazebo/pub_clock_frequency"), 50)
        self.assertIs(rospy.get_param("/gazebo/paused"), True)

    def test_paused_holds_the_clock_until_unpaused(self):
        clock = Collector("/clock", Clock)
        paused = clock.wait_for(lambda m: len(m) >= 5, TIMEOUT, "five /clock messages")[:5]
        self.assertEqual(len({m.clock for m in paused}), 1, "the clock moved while paused")
        rospy.wait_for_service("/gazebo/unpause_physics", TIMEOUT)
        rospy.ServiceProxy("/gazebo/unpause_physics", Empty)()
        clock.wait_for(lambda m: m[-1].clock > paused[0].clock, TIMEOUT, "the clock to move after unpause")


if __name__ == "__main__":
    rospy.init_node("empty_world_arguments")
    rostest.rosrun("bullet_sim_bringup", "empty_world_arguments", EmptyWorldArguments, sys.argv)
