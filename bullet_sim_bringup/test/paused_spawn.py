#!/usr/bin/env python3
"""rostest node (paused_spawn.test): the steps of a paused spawn with -J, in the order that lost the -J pose
before (Kinova Gen3, survey blocker B10). Into the paused world: spawn the arm, load and start its controllers
(each call answers at once, the world still paused), then what Noetic's spawn_model -J ... -unpause does:
set_model_configuration, then unpause_physics. From the unpause on, the controller holds every joint within
0.01 rad of its -J value."""
import time
import unittest

import rospy
import rostest
from control_msgs.msg import JointTrajectoryControllerState
from controller_manager_msgs.srv import ListControllers, LoadController, SwitchController
from gazebo_msgs.srv import GetPhysicsProperties, SetModelConfiguration, SpawnModel
from geometry_msgs.msg import Pose, Quaternion
from std_srvs.srv import Empty

from bringup_support import Collector

INITIAL = {"joint_1": 1.57, "joint_2": 0.35, "joint_3": -1.2}  # spawn_model -J joint_1 1.57 -J joint_2 ...
CONTROLLERS = ["joint_state_controller", "arm_controller"]
TOLERANCE = 0.01  # [rad]
WATCHED = 1.0  # [s] of sim time after the unpause
PROMPT = 5.0  # [s] of wall time within which a call answers while paused


def service(name, service_type):
    rospy.wait_for_service(name, timeout=30)
    return rospy.ServiceProxy(name, service_type)


class PausedSpawn(unittest.TestCase):
    def paused(self):
        return service("/gazebo/get_physics_properties", GetPhysicsProperties)().pause

    def promptly(self, what, call, *args):
        """`call(*args)`, which must answer within PROMPT s of wall time."""
        start = time.monotonic()
        answer = call(*args)
        self.assertLess(time.monotonic() - start, PROMPT, "%s took longer than %.0f s while paused" % (what, PROMPT))
        return answer

    def test_the_controller_holds_the_minus_j_pose_from_the_unpause(self):
        rospy.init_node("paused_spawn")
        self.assertTrue(self.paused(), "empty_world.launch paused:=true left the world running")
        spawn = service("/gazebo/spawn_urdf_model", SpawnModel)
        answer = spawn("arm", rospy.get_param("/arm_description"), "/my_arm",
                       Pose(orientation=Quaternion(0, 0, 0, 1)), "")
        self.assertTrue(answer.success, answer.status_message)

        load = service("/my_arm/controller_manager/load_controller", LoadController)
        for name in CONTROLLERS:
            self.assertTrue(self.promptly("load_controller " + name, load, name).ok, "load_controller " + name)
        switch = service("/my_arm/controller_manager/switch_controller", SwitchController)
        self.assertTrue(self.promptly("switch_controller", switch, CONTROLLERS, [], 2, False, 0.0).ok)
        listed = service("/my_arm/controller_manager/list_controllers", ListControllers)().controller
        self.assertEqual(sorted((c.name, c.state) for c in listed), sorted((n, "running") for n in CONTROLLERS))
        self.assertTrue(self.paused(), "the world ran before the unpause")

        states = Collector("/my_arm/arm_controller/state", JointTrajectoryControllerState)
        states.wait_for_publisher(10)  # the first states come at the first steps
        configure = service("/gazebo/set_model_configuration", SetModelConfiguration)
        answer = configure("arm", "", list(INITIAL), list(INITIAL.values()))
        self.assertTrue(answer.success, answer.status_message)
        service("/gazebo/unpause_physics", Empty)()

        watched = states.wait_for(lambda m: m and m[-1].header.stamp.to_sec() >= WATCHED, 30,
                                  "%.1f s of the controller's state after the unpause" % WATCHED)
        self.assertLess(watched[0].header.stamp.to_sec(), 0.01, "the first state came late: %s" % watched[0].header)
        for state in watched:
            for joint, desired, actual in zip(state.joint_names, state.desired.positions, state.actual.positions):
                at = "%s at %.3f s" % (joint, state.header.stamp.to_sec())
                self.assertAlmostEqual(desired, INITIAL[joint], delta=1e-9, msg="the hold point of " + at)
                self.assertAlmostEqual(actual, INITIAL[joint], delta=TOLERANCE, msg=at)


if __name__ == "__main__":
    rostest.rosrun("bullet_sim_bringup", "paused_spawn", PausedSpawn)
