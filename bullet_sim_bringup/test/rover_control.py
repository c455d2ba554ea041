#!/usr/bin/env python3
"""rostest node: the controller manager inside the simulator, as controller_manager's tools and services see it:
list_controllers shows what runs (also through the `controller_manager` script), switch_controller stops and
starts the drive, a controller of an unknown type fails with a message that names the type and the types there
are, killing a spawner unloads what it loaded, an unspawner holds a controller stopped while it runs, and a second
cmd_vel publisher brakes the drive (allow_multiple_cmd_vel_publishers false)."""
import signal
import subprocess
import sys
import unittest

import rospy
import rostest
from geometry_msgs.msg import Twist
from rosgraph_msgs.msg import Log
from sensor_msgs.msg import JointState

from bringup_support import Collector, interrupt
from rover_support import CONTROLLER, GroundTruth, controllers, load, switch, twist, wait_for_state, wait_until


def run(*command):
    return subprocess.run(list(command), stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=60,
                          universal_newlines=True)


class RoverControl(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.truth = GroundTruth()
        cls.log = Collector("/rosout", Log)
        cls.command = rospy.Publisher("/%s/cmd_vel" % CONTROLLER, Twist, queue_size=1)
        wait_for_state(CONTROLLER, "running")
        wait_for_state("joint_state_controller", "running")

    def drive(self, linear, seconds):
        """Sends `linear` at 10 Hz for `seconds` of wall time."""
        rate = rospy.Rate(10)
        end = rospy.get_time() + seconds
        while rospy.get_time() < end:
            self.command.publish(twist(linear, 0.0))
            rate.sleep()

    def test_a_second_cmd_vel_publisher_brakes_the_drive(self):
        other = subprocess.Popen(["rostopic", "pub", "-r", "10", "/%s/cmd_vel" % CONTROLLER, "geometry_msgs/Twist",
                                  "{linear: {x: 0.5}}"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        try:
            wanted = "from one of 2 publishers, with allow_multiple_cmd_vel_publishers false: braking"
            self.log.wait_for(lambda m: any(wanted in x.msg for x in m), 30, "the simulator's warning: " + wanted)
            self.drive(0.5, 1.5)
            self.assertLess(max(self.truth.speed(m) for m in self.truth.messages[-25:]), 0.01,
                            "two publishers must brake the rover")
        finally:
            interrupt(other, 10)  # rostopic pub once outlived SIGINT by 30 s in CI
        self.drive(0.5, 1.5)  # one publisher again
        self.assertAlmostEqual(max(self.truth.speed(m) for m in self.truth.messages[-25:]), 0.5, delta=0.05)
        self.truth.wait_until_stopped(30)

    def test_list_controllers_shows_what_runs(self):
        listed = controllers()
        state, controller_type, claims = listed[CONTROLLER]
        self.assertEqual((state, controller_type), ("running", "diff_drive_controller/DiffDriveController"))
        self.assertEqual(claims[0].hardware_interface, "hardware_interface::VelocityJointInterface")
        self.assertEqual(sorted(claims[0].resources),
                         ["front_left_wheel", "front_right_wheel", "rear_left_wheel", "rear_right_wheel"])
        self.assertEqual(listed["joint_state_controller"][:2],
                         ("running", "joint_state_controller/JointStateController"))
        listing = run("rosrun", "controller_manager", "controller_manager", "list")
        self.assertIn("'%s' - 'hardware_interface::VelocityJointInterface' ( running )" % CONTROLLER, listing.stdout)
        types = run("rosrun", "controller_manager", "controller_manager", "list-types")
        self.assertIn("diff_drive_controller/DiffDriveController controller_interface::ControllerBase", types.stdout)
        # The joint_state_controller the ROSbot-style include started publishes every wheel.
        states = Collector("/joint_states", JointState).wait_for(lambda m: m, 30, "joint_states")
        self.assertEqual(len(states[-1].name), 4)

    def test_switch_controller_stops_and_starts_the_drive(self):
        self.assertTrue(switch(stop=[CONTROLLER]))
        self.assertEqual(controllers()[CONTROLLER][0], "stopped")
        self.drive(0.5, 1.5)
        self.assertLess(self.truth.speed(self.truth.messages[-1]), 0.01, "a stopped drive must not move")
        self.assertFalse(switch(stop=[CONTROLLER]), "STRICT: it is not running")
        self.assertTrue(switch(start=[CONTROLLER]))
        self.drive(0.5, 1.5)
        # Its top speed over the last 0.5 s: a test publisher stalled past cmd_vel_timeout slows it for a moment.
        self.assertAlmostEqual(max(self.truth.speed(m) for m in self.truth.messages[-25:]), 0.5, delta=0.05)
        self.truth.wait_until_stopped(30)  # cmd_vel_timeout stops it

    def test_unknown_controller_type_fails_clearly(self):
        self.assertFalse(load("mystery_controller"))
        wanted = ("type [diff_drive_controller/NoSuchController] is not a controller type bullet_sim has "
                  "(did you mean [diff_drive_controller/DiffDriveController]?); it has "
                  "joint_state_controller/JointStateController, diff_drive_controller/DiffDriveController")
        self.log.wait_for(lambda m: any(wanted in x.msg and x.level == Log.ERROR for x in m), 30,
                          "the simulator's error about mystery_controller")
        self.assertNotIn("mystery_controller", controllers())

    def test_killing_the_spawner_unloads_its_controllers(self):
        spawner = subprocess.Popen(["rosrun", "controller_manager", "spawner", "extra_joint_publisher"],
                                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        try:
            wait_for_state("extra_joint_publisher", "running")
        finally:
            spawner.send_signal(signal.SIGINT)  # as roslaunch stops it
            spawner.wait(timeout=30)
        self.assertNotIn("extra_joint_publisher", controllers())

    def test_unspawner_holds_a_controller_stopped_while_it_runs(self):
        unspawner = subprocess.Popen(["rosrun", "controller_manager", "unspawner", CONTROLLER],
                                     stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        try:
            wait_for_state(CONTROLLER, "stopped")
        finally:
            unspawner.send_signal(signal.SIGINT)
            unspawner.wait(timeout=30)
        wait_until(lambda: controllers()[CONTROLLER][0] == "running", 30, "the unspawner to start it again")


if __name__ == "__main__":
    rospy.init_node("rover_control")
    rostest.rosrun("bullet_sim_bringup", "rover_control", RoverControl, sys.argv)
