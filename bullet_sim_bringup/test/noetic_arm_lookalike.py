#!/usr/bin/env python3
"""rostest node: a look-alike of a Noetic arm runs unedited from its own launch files.

It copies fixtures/noetic_arm_lookalike (noetic_arm_description, noetic_arm_gazebo: written for these tests with
the structure of Noetic-era arm packages) to a temporary folder and runs `roslaunch noetic_arm_gazebo <~launch>`
with that folder first on ROS_PACKAGE_PATH. arm_bringup.launch loads the description through the description
package's launch file (`$(find xacro)/xacro` with the YAML files as arguments), arm.launch with `xacro` on PATH.
The description reads its joint limits and kinematics with xacro.load_yaml, angles tagged !degrees and !radians.

robot_description must be what `rosrun xacro xacro` makes of the same file; its joint limits and tool frame must
be the YAML's, converted to radians here; the arm must spawn fixed to the world, holding its zero pose, and reach
a commanded pose where forward kinematics over the YAML's lengths puts its forearm.
"""
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time
import unittest
import xml.etree.ElementTree as ET

import rospkg
import rospy
import rostest
import yaml
from gazebo_msgs.srv import GetLinkState
from sensor_msgs.msg import JointState
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

from bringup_support import Collector, interrupt

TIMEOUT = 60.0  # [s] for the launch to come up, and for each wait after that
JOINTS = ["shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint"]
TARGET = [0.5, -0.4, 0.8]  # [rad]
RADIANS = {"pi": math.pi, "pi/4": math.pi / 4}  # the !radians expressions the fixture's YAML uses


class AnglesLoader(yaml.SafeLoader):
    """The test's own reading of xacro's angle tags."""


AnglesLoader.add_constructor("!degrees", lambda loader, node: math.radians(float(loader.construct_scalar(node))))
AnglesLoader.add_constructor("!radians", lambda loader, node: RADIANS[loader.construct_scalar(node)])


def canonical(urdf):
    """The URDF without comments or indentation."""
    return ET.canonicalize(urdf, strip_text=True)


class NoeticArmLookAlike(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.folder = tempfile.mkdtemp(prefix="noetic_arm_lookalike_")
        fixture = os.path.join(rospkg.RosPack().get_path("bullet_sim_bringup"), "test", "fixtures",
                               "noetic_arm_lookalike")
        shutil.copytree(fixture, cls.folder, ignore=shutil.ignore_patterns("CATKIN_IGNORE"), dirs_exist_ok=True)
        cls.description = os.path.join(cls.folder, "noetic_arm_description")
        cls.env = dict(os.environ, ROS_PACKAGE_PATH=cls.folder + ":" + os.environ.get("ROS_PACKAGE_PATH", ""))
        cls.joint_states = Collector("/joint_states", JointState)
        cls.log = open(os.path.join(cls.folder, "roslaunch.log"), "w")
        cls.launch = subprocess.Popen(["roslaunch", "noetic_arm_gazebo", rospy.get_param("~launch")], env=cls.env,
                                      stdout=cls.log, stderr=subprocess.STDOUT)

    @classmethod
    def tearDownClass(cls):
        interrupt(cls.launch, TIMEOUT)
        cls.log.close()
        shutil.rmtree(cls.folder, ignore_errors=True)

    def yaml_file(self, name):
        with open(os.path.join(self.description, "config", name)) as f:
            return yaml.load(f, Loader=AnglesLoader)

    def robot_description(self):
        deadline = time.monotonic() + TIMEOUT
        while not rospy.has_param("/robot_description"):
            self.assertIsNone(self.launch.poll(), "roslaunch exited before setting robot_description")
            self.assertLess(time.monotonic(), deadline, "no robot_description")
            time.sleep(0.1)
        return rospy.get_param("/robot_description")

    def test_description_spawns_and_moves(self):
        description = self.robot_description()
        rosrun = subprocess.run(["rosrun", "xacro", "xacro", os.path.join(self.description, "urdf", "arm.urdf.xacro")],
                                env=self.env, capture_output=True, text=True, timeout=TIMEOUT)
        self.assertEqual(rosrun.returncode, 0, rosrun.stderr)
        self.assertEqual(canonical(description), canonical(rosrun.stdout),
                         "roslaunch's robot_description differs from rosrun xacro xacro's expansion")
        self.check_limits_and_tool(ET.fromstring(description))

        at_rest = self.joint_states.wait_for(lambda m: any(JOINTS[0] in s.name for s in m), TIMEOUT,
                                             "joint_states from the arm's joint_state_controller")[-1]
        for joint in JOINTS:
            self.assertAlmostEqual(at_rest.position[at_rest.name.index(joint)], 0.0, delta=0.05, msg=joint)

        reached = self.move_to(TARGET)
        self.check_forearm([reached.position[reached.name.index(joint)] for joint in JOINTS])

    def check_limits_and_tool(self, urdf):
        limits = self.yaml_file("joint_limits.yaml")["joint_limits"]
        for joint in JOINTS:
            limit = urdf.find("joint[@name='%s']/limit" % joint)
            expected = limits[joint[:-len("_joint")]]
            for attribute, key in [("lower", "min_position"), ("upper", "max_position"),
                                   ("velocity", "max_velocity"), ("effort", "max_effort")]:
                self.assertAlmostEqual(float(limit.get(attribute)), expected[key], places=12,
                                       msg="%s %s" % (joint, attribute))
        tool = self.yaml_file("kinematics.yaml")["kinematics"]["tool"]
        rpy = [float(v) for v in urdf.find("joint[@name='tool0_fixed_joint']/origin").get("rpy").split()]
        for value, key in zip(rpy, ["roll", "pitch", "yaw"]):
            self.assertAlmostEqual(value, tool[key], places=12, msg="tool0 " + key)

    def move_to(self, target):
        """Commands `target` through arm_controller's command topic; the first joint_states within 0.02 rad of it."""
        commands = rospy.Publisher("/arm_controller/command", JointTrajectory, queue_size=1, latch=True)
        trajectory = JointTrajectory(joint_names=JOINTS)
        trajectory.points.append(JointTrajectoryPoint(positions=target, time_from_start=rospy.Duration(1.5)))
        commands.publish(trajectory)

        def reached(messages):
            state = messages[-1]
            return all(abs(state.position[state.name.index(j)] - q) < 0.02 for j, q in zip(JOINTS, target))

        return self.joint_states.wait_for(reached, TIMEOUT, "the arm at %s" % target)[-1]

    def check_forearm(self, q):
        """The forearm link's origin (the elbow) where forward kinematics at joint positions `q` over the YAML's
        lengths puts it."""
        kinematics = self.yaml_file("kinematics.yaml")["kinematics"]
        pan, lift = q[0], q[1]
        shoulder_height = kinematics["shoulder"]["z"] + kinematics["upper_arm"]["z"]
        reach = kinematics["forearm"]["x"]  # a rotation by `lift` about y takes x to (cos, 0, -sin)
        expected = (reach * math.cos(lift) * math.cos(pan), reach * math.cos(lift) * math.sin(pan),
                    shoulder_height - reach * math.sin(lift))
        rospy.wait_for_service("/gazebo/get_link_state", TIMEOUT)
        state = rospy.ServiceProxy("/gazebo/get_link_state", GetLinkState)("noetic_arm::forearm_link", "world")
        self.assertTrue(state.success, state.status_message)
        position = state.link_state.pose.position
        for value, want, axis in zip((position.x, position.y, position.z), expected, "xyz"):
            self.assertAlmostEqual(value, want, delta=0.005, msg="forearm " + axis)


if __name__ == "__main__":
    rospy.init_node("noetic_arm_lookalike")
    rostest.rosrun("bullet_sim_bringup", "noetic_arm_lookalike", NoeticArmLookAlike, sys.argv)
