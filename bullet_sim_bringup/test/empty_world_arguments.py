#!/usr/bin/env python3
"""rostest node: gazebo_ros's empty_world.launch hands its arguments to bullet_sim's simulator (node gazebo):
the world, the pause (the clock stands still until unpause_physics), the seed and /clock's rate, in sim time."""
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

    def test_the_clock_comes_at_pub_clock_frequency_in_sim_time(self):
        # Gazebo's rule: /clock once every 1/pub_clock_frequency s of sim time (50 Hz: 20 ms), whatever the
        # pace; at the test's half real time, 50 wall Hz would give 10 ms.
        clock = Collector("/clock", Clock)
        rospy.wait_for_service("/gazebo/unpause_physics", TIMEOUT)
        rospy.ServiceProxy("/gazebo/unpause_physics", Empty)()
        ticks = clock.wait_for(lambda m: len({t.clock for t in m}) >= 12, TIMEOUT, "12 ticks of /clock")
        times = sorted({m.clock.to_sec() for m in ticks})[1:]  # the first may be the paused one
        steps = [round((b - a) * 1000) for a, b in zip(times, times[1:])]
        self.assertTrue(all(step >= 20 for step in steps), steps)
        self.assertEqual(sorted(steps)[len(steps) // 2], 20, steps)


if __name__ == "__main__":
    rospy.init_node("empty_world_arguments")
    rostest.rosrun("bullet_sim_bringup", "empty_world_arguments", EmptyWorldArguments, sys.argv)
