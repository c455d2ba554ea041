#!/usr/bin/env python3
"""rostest node: the multi-sensor robot's bumper publishes gazebo_msgs/ContactsState with no states while it
stands free; `rostopic pub -r 10 /cmd_vel` drives it into the east wall, and then the states name its bumper
collision (as Gazebo names it after lumping) and the wall's."""
import subprocess
import sys
import unittest

import rospy
import rostest
from gazebo_msgs.msg import ContactsState

from bringup_support import Collector, interrupt

BUMPER = "multi::base_footprint::base_footprint_fixed_joint_lump__bumper_link_collision_1"


class BumperContact(unittest.TestCase):
    def test_the_wall_is_reported_on_the_bumper(self):
        contacts = Collector("bumper_states", ContactsState)
        free = contacts.wait_for(lambda m: len(m) >= 10, 60, "10 bumper messages")
        self.assertEqual(free[0].header.frame_id, "world")
        self.assertEqual([m.states for m in free[:10]], [[]] * 10, "nothing touches the bumper yet")
        command = subprocess.Popen(
            ["rostopic", "pub", "-r", "10", "/cmd_vel", "geometry_msgs/Twist",
             "{linear: {x: 0.3, y: 0, z: 0}, angular: {x: 0, y: 0, z: 0}}"], stdout=subprocess.DEVNULL)
        try:
            # 0.78 m to the wall at 0.3 m/s.
            touching = contacts.wait_for(lambda m: m[-1].states, 90, "the bumper touching the wall")[-1]
        finally:
            interrupt(command, 10)  # as Ctrl-C: rostopic once outlived a SIGTERM by 30 s
        self.assertEqual(len(touching.states), 1)
        state = touching.states[0]
        self.assertEqual(state.collision1_name, BUMPER)
        self.assertEqual(state.collision2_name, "room::wall_east::collision")
        self.assertTrue(state.contact_positions)
        for position, normal in zip(state.contact_positions, state.contact_normals):
            self.assertAlmostEqual(position.x, 3.0, delta=0.01)
            self.assertAlmostEqual(normal.x, -1.0, delta=1e-3)


if __name__ == "__main__":
    rospy.init_node("bumper_contact")
    rostest.rosrun("bullet_sim_bringup", "bumper_contact", BumperContact, sys.argv)
