#!/usr/bin/env python3
"""rostest node: the simulator under bad input. A NaN or inf in cmd_vel is ignored (the robot stays put, the node
keeps stepping); the drive's commandTimeout stops the robot when commands stop; a malformed and an empty robot
description, or a flag that is unknown or not a number, make spawn_model exit non-zero with the reason, while the
simulator keeps running; spawn_model -wait spawns once the model it names is in. Every case of bullet_sim's
test/fixtures/bad_input/cases.yaml, spawn poses that are not finite and an SDF model of absurd mass through the
world API are refused with their message while the wheelchair drives on."""
import math
import os
import shutil
import subprocess
import sys
import tempfile
import threading
import unittest

import rospkg
import rospy
import rostest
import yaml
from bullet_sim.srv import SpawnModel, SpawnModelRequest
from gazebo_msgs.srv import DeleteModel, GetWorldProperties, SpawnModel as GazeboSpawnModel
from geometry_msgs.msg import Pose
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Clock
from std_srvs.srv import Empty

from bringup_support import Collector


class Commander:
    """Publishes one Twist on /cmd_vel at 10 Hz (as `rostopic pub -r 10` does) until stop()."""

    def __init__(self, linear, angular):
        self._publisher = rospy.Publisher("/cmd_vel", Twist, queue_size=1)
        self._twist = Twist()
        self._twist.linear.x = linear
        self._twist.angular.z = angular
        self._stopped = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    def _run(self):
        while not self._stopped.wait(0.1) and not rospy.is_shutdown():
            self._publisher.publish(self._twist)

    def stop(self):
        self._stopped.set()
        self._thread.join(timeout=5)
        self._publisher.unregister()


def revolute_chain(links):
    inertial = ('<inertial><mass value="0.1"/><inertia ixx="1e-4" iyy="1e-4" izz="1e-4" ixy="0" ixz="0" iyz="0"/>'
                '</inertial><collision><geometry><box size="0.05 0.05 0.05"/></geometry></collision>')
    text = ['<robot name="chain">']
    text += ['<link name="l%d">%s</link>' % (i, inertial) for i in range(links)]
    text += ['<joint name="j%d" type="revolute"><parent link="l%d"/><child link="l%d"/><origin xyz="0 0 0.06"/>'
             '<axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>' % (i, i - 1, i)
             for i in range(1, links)]
    return "\n".join(text + ["</robot>"])


def mesh_robot(mesh):
    return ('<robot name="mesh"><link name="base"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" '
            'izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial><visual><geometry><mesh filename="file://%s"/>'
            '</geometry></visual></link></robot>' % mesh)


def urdf_of(case, fixtures, folder):
    """The URDF of a case of cases.yaml, its files written into `folder` when it is generated."""
    if "file" in case:
        with open(os.path.join(fixtures, case["file"])) as urdf:
            return urdf.read()
    kind = case["generate"]
    if kind == "revolute_chain":
        return revolute_chain(case["links"])
    if kind == "fifo_mesh":
        os.mkfifo(os.path.join(folder, "mesh.stl"))
        return mesh_robot(os.path.join(folder, "mesh.stl"))
    if kind == "obj_naming_fifo":
        with open(os.path.join(folder, "mesh.obj"), "w") as obj:
            obj.write("mtllib mesh.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n")
        os.mkfifo(os.path.join(folder, "mesh.mtl"))
        return mesh_robot(os.path.join(folder, "mesh.obj"))
    if kind == "sparse_mesh":
        with open(os.path.join(folder, "mesh.stl"), "w") as mesh:
            mesh.truncate(300 << 20)
        return mesh_robot(os.path.join(folder, "mesh.stl"))
    raise AssertionError("cases.yaml: unknown generate [%s]" % kind)


def travelled(messages, start, end):
    """Distance [m] between the odometry poses stamped nearest after sim times `start` and `end` [s]."""
    first = next(m for m in messages if m.header.stamp.to_sec() >= start).pose.pose.position
    last = next(m for m in messages if m.header.stamp.to_sec() >= end).pose.pose.position
    return math.hypot(last.x - first.x, last.y - first.y)


class BadInput(unittest.TestCase):
    def setUp(self):
        self.clock = Collector("/clock", Clock)
        self.odometry = Collector("odom", Odometry)
        self.odometry.wait_for(lambda m: m, 60, "the first odom")

    def drive_for(self, linear, angular, seconds):
        """Commands (linear, angular) for `seconds` of sim time; returns the sim time of the last command."""
        start = self.odometry.messages[-1].header.stamp.to_sec()
        commander = Commander(linear, angular)
        try:
            self.odometry.wait_for(lambda m: m[-1].header.stamp.to_sec() >= start + seconds, 60,
                                   "%.0f s of commands" % seconds)
        finally:
            commander.stop()
        return self.odometry.messages[-1].header.stamp.to_sec()

    def wait_until(self, sim_time):
        return self.odometry.wait_for(lambda m: m[-1].header.stamp.to_sec() >= sim_time, 60,
                                      "odom at %.1f s of sim time" % sim_time)

    def test_nan_and_inf_commands_are_ignored(self):
        # Let any earlier command time out (0.5 s) and the chair come to rest.
        self.wait_until(self.odometry.messages[-1].header.stamp.to_sec() + 2.0)
        start = self.odometry.messages[-1].header.stamp.to_sec()
        for linear, angular in ((float("nan"), 0.0), (0.0, float("inf")), (float("-inf"), float("nan"))):
            self.drive_for(linear, angular, 1.0)
        messages = self.wait_until(self.odometry.messages[-1].header.stamp.to_sec() + 0.5)
        self.assertLess(travelled(messages, start, messages[-1].header.stamp.to_sec()), 0.005,
                        "the chair moved on non-finite commands")
        seen = len(self.clock.messages)
        self.clock.wait_for(lambda m: len(m) > seen + 10, 30, "the clock to go on after the bad commands")
        # The drive still takes a good command afterwards.
        last = self.drive_for(0.3, 0.0, 1.5)
        self.assertGreater(travelled(self.odometry.messages, last - 0.5, last), 0.05)

    def test_command_timeout_stops_the_chair(self):
        last_command = self.drive_for(0.3, 0.0, 2.0)
        messages = self.odometry.messages
        self.assertGreater(travelled(messages, last_command - 1.0, last_command), 0.15, "the chair did not drive")
        # commandTimeout is 0.5 s and wheelAcceleration 1.8 m/s^2: stopped well within 1.5 s.
        messages = self.wait_until(last_command + 2.5)
        self.assertLess(travelled(messages, last_command + 1.5, last_command + 2.5), 0.005,
                        "the chair kept driving after the commands stopped")

    @staticmethod
    def spawn_command(*source, model="bad", x="50", timeout="30"):
        """spawn_model's command line: far from the chair, and in a namespace of its own, should it load."""
        return ["rosrun", "bullet_sim", "spawn_model", "-urdf", *source, "-model", model, "-timeout", timeout,
                "-x", x, "-robot_namespace", model]

    def spawn_model(self, *source, **options):
        return subprocess.run(self.spawn_command(*source, **options), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                              text=True, timeout=60)

    def test_a_flag_that_is_not_a_number_fails_the_spawn_with_the_reason(self):
        fixtures = os.path.join(rospkg.RosPack().get_path("bullet_sim"), "test", "fixtures", "robots")
        result = self.spawn_model("-file", os.path.join(fixtures, "minimal.urdf"), timeout="soon")
        self.assertEqual(result.returncode, 1, result.stdout + result.stderr)
        self.assertIn("-timeout must be a number, not [soon]", result.stderr)

    def test_an_unknown_flag_fails_the_spawn_naming_it(self):
        # It was taken as a value and dropped without a word.
        fixtures = os.path.join(rospkg.RosPack().get_path("bullet_sim"), "test", "fixtures", "robots")
        result = self.spawn_model("-file", os.path.join(fixtures, "minimal.urdf"), "-colour", "red")
        self.assertEqual(result.returncode, 1, result.stdout + result.stderr)
        self.assertIn("unexpected argument [-colour]", result.stderr)

    def test_wait_spawns_only_once_the_model_it_names_is_in_the_world(self):
        fixtures = os.path.join(rospkg.RosPack().get_path("bullet_sim"), "test", "fixtures", "robots")
        minimal = os.path.join(fixtures, "minimal.urdf")
        absent = self.spawn_model("-file", minimal, "-wait", "absent", timeout="1")
        self.assertEqual(absent.returncode, 1, absent.stdout + absent.stderr)
        self.assertIn("-wait absent: no model of that name in the world after 1 s (-timeout)", absent.stderr)

        # Line-buffered, so that its log line arrives when it is written, not when it exits.
        command = ["stdbuf", "-oL"] + self.spawn_command("-file", minimal, "-wait", "waited_for", model="waiter",
                                                         x="60")
        waiter = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        try:
            for line in waiter.stdout:  # ends when it does, within its -timeout
                if "Waiting for model waited_for" in line:
                    break
            self.assertIsNone(waiter.poll(), "spawn_model -wait did not wait")
            self.assertNotIn("waiter", self.world_models())
            result = self.spawn_model("-file", minimal, model="waited_for", x="70")
            self.assertEqual(result.returncode, 0, result.stdout + result.stderr)
            self.assertEqual(waiter.wait(timeout=60), 0, waiter.stderr.read())
            self.assertIn("waiter", self.world_models())
        finally:
            if waiter.poll() is None:
                waiter.kill()
            for name in ("waiter", "waited_for"):
                rospy.ServiceProxy("/gazebo/delete_model", DeleteModel)(name)

    def world_models(self):
        rospy.wait_for_service("/gazebo/get_world_properties", timeout=30)
        return rospy.ServiceProxy("/gazebo/get_world_properties", GetWorldProperties)().model_names

    def test_a_file_that_is_not_a_regular_file_fails_the_spawn_promptly(self):
        # A directory threw an uncaught exception, and /dev/zero was read for ever.
        for path, kind in (("/tmp", "directory"), ("/dev/zero", "device")):
            result = self.spawn_model("-file", path)
            self.assertEqual(result.returncode, 1, result.stdout + result.stderr)
            self.assertIn("-file [%s] is a %s, not a regular file" % (path, kind), result.stderr)

    def test_bad_descriptions_fail_the_spawn_and_the_simulator_keeps_running(self):
        fixtures = os.path.join(rospkg.RosPack().get_path("bullet_sim"), "test", "fixtures", "robots")
        malformed = self.spawn_model("-file", os.path.join(fixtures, "fail_malformed.urdf"))
        self.assertNotEqual(malformed.returncode, 0, malformed.stdout + malformed.stderr)
        self.assertIn("closed by a different tag", malformed.stderr)
        rospy.set_param("empty_description", "")
        empty = self.spawn_model("-param", "empty_description")
        self.assertNotEqual(empty.returncode, 0, empty.stdout + empty.stderr)
        self.assertIn("the robot description is empty", empty.stderr)

        for name in ("/gazebo/pause_physics", "/gazebo/unpause_physics"):
            rospy.wait_for_service(name, timeout=30)
            rospy.ServiceProxy(name, Empty)()
        latest = self.clock.wait_for(lambda m: m, 30, "a clock message")[-1].clock.to_sec()
        self.clock.wait_for(lambda m: m[-1].clock.to_sec() > latest + 0.5, 30, "the clock to advance")

    def test_every_bad_file_is_refused_with_its_message_and_the_chair_drives_on(self):
        bad_input = os.path.join(rospkg.RosPack().get_path("bullet_sim"), "test", "fixtures", "bad_input")
        with open(os.path.join(bad_input, "cases.yaml")) as cases:
            cases = yaml.safe_load(cases)
        rospy.wait_for_service("/gazebo/spawn_urdf", timeout=30)
        problems = []
        commander = Commander(0.3, 0.3)
        try:
            self.wait_until(self.odometry.messages[-1].header.stamp.to_sec() + 1.0)  # up to speed
            for case in cases:
                name = case.get("file") or "%s %s" % (case["generate"], case.get("links", ""))
                problem = self.check_case(case, bad_input)
                if problem:
                    problems.append("%s: %s" % (name, problem))
        finally:
            commander.stop()
        self.assertEqual(problems, [])

    def check_case(self, case, fixtures):
        """Spawns the case's URDF through the simulator's service, far from the chair and in a namespace of its
        own; what went wrong, or None."""
        folder = tempfile.mkdtemp(prefix="bad_input_")
        try:
            request = SpawnModelRequest(model_name="bad", model_xml=urdf_of(case, fixtures, folder),
                                        robot_namespace="bad", place_on_ground=True)
            request.initial_pose.position.x = 50
            request.initial_pose.orientation.w = 1
            start = self.odometry.messages[-1]
            response = rospy.ServiceProxy("/gazebo/spawn_urdf", SpawnModel)(request)
            message = case["message"].replace("TMP", folder)
            if case.get("loads"):
                rospy.ServiceProxy("/gazebo/delete_model", DeleteModel)("bad")
            if response.success != bool(case.get("loads")) or message not in response.message:
                return "expected %s with [%s], got success %s with [%s]" % (
                    "success" if case.get("loads") else "a refusal", message, response.success, response.message)
            return self.chair_drives_on(start)
        finally:
            shutil.rmtree(folder)

    def chair_drives_on(self, start):
        """None when the chair, commanded at 0.3 m/s all along, covers ground in the next 0.3 s of sim time."""
        t = start.header.stamp.to_sec()
        messages = self.wait_until(self.odometry.messages[-1].header.stamp.to_sec() + 0.3)
        if travelled(messages, t, messages[-1].header.stamp.to_sec()) < 0.03:
            return "the chair stopped driving"
        return None

    def test_spawn_poses_that_are_not_finite_are_refused_naming_the_value(self):
        rospy.wait_for_service("/gazebo/spawn_urdf", timeout=30)
        spawn = rospy.ServiceProxy("/gazebo/spawn_urdf", SpawnModel)
        fixtures = os.path.join(rospkg.RosPack().get_path("bullet_sim"), "test", "fixtures", "robots")
        with open(os.path.join(fixtures, "minimal.urdf")) as urdf:
            minimal = urdf.read()
        commander = Commander(0.3, 0.0)
        try:
            start = self.wait_until(self.odometry.messages[-1].header.stamp.to_sec() + 1.0)[-1]  # up to speed
            for field, value, message in (
                    ("position.x", float("nan"), "spawn position [nan   0   0] is not finite"),
                    ("orientation.w", float("inf"), "spawn orientation (x y z w) [0 0 0 inf] is not finite"),
                    ("position.y", 1e9, "spawn pose y [1e+09] m is beyond the limit of 10000 m (max_length)")):
                request = SpawnModelRequest(model_name="bad", model_xml=minimal, place_on_ground=True)
                request.initial_pose.orientation.w = 1.0
                owner, name = field.split(".")
                setattr(getattr(request.initial_pose, owner), name, value)
                response = spawn(request)
                self.assertFalse(response.success, field)
                self.assertIn(message, response.message)
            result = self.spawn_model("-file", os.path.join(fixtures, "minimal.urdf"), "-Y", "nan")
            self.assertEqual(result.returncode, 1, result.stdout + result.stderr)
            self.assertIn("is not finite", result.stderr)
            self.assertIsNone(self.chair_drives_on(start))
        finally:
            commander.stop()

    def test_spawn_sdf_model_refuses_a_model_of_absurd_mass_naming_the_value(self):
        rospy.wait_for_service("/gazebo/spawn_sdf_model", timeout=30)
        heavy = ('<sdf version="1.6"><model name="heavy"><link name="base"><inertial><mass>1e30</mass></inertial>'
                 '<collision name="c"><geometry><box><size>1 1 1</size></box></geometry></collision></link>'
                 '</model></sdf>')
        commander = Commander(0.3, 0.0)
        try:
            start = self.wait_until(self.odometry.messages[-1].header.stamp.to_sec() + 1.0)[-1]  # up to speed
            pose = Pose()
            pose.position.x = 50
            pose.orientation.w = 1
            answer = rospy.ServiceProxy("/gazebo/spawn_sdf_model", GazeboSpawnModel)("heavy", heavy, "", pose, "")
            self.assertFalse(answer.success)
            self.assertIn("link [base] <inertial> mass [1e+30] kg is beyond the limit of 1e+06 kg (max_mass)",
                          answer.status_message)
            self.assertIsNone(self.chair_drives_on(start))
        finally:
            commander.stop()


if __name__ == "__main__":
    rospy.init_node("bad_input")
    rostest.rosrun("bullet_sim_bringup", "bad_input", BadInput, sys.argv)
