#!/usr/bin/env python3
"""rostest node: gazebo_ros's spawn_model turns each of its flags into the service calls Gazebo's makes. A
stand-in simulator under /fake_gazebo records every request (bullet_sim's spawn_urdf and gazebo_msgs'
spawn_urdf_model, spawn_sdf_model, set_model_configuration, unpause_physics, delete_model) and publishes
model_states."""
import os
import signal
import subprocess
import sys
import tempfile
import threading
import time
import unittest
import xml.etree.ElementTree as ET

import roslib.packages
import rospkg
import rospy
import rostest
from bullet_sim.srv import SpawnModel as BulletSimSpawn, SpawnModelResponse as BulletSimSpawnResponse
from gazebo_msgs.msg import ModelStates
from gazebo_msgs.srv import (DeleteModel, DeleteModelResponse, SetModelConfiguration,
                             SetModelConfigurationResponse, SpawnModel, SpawnModelResponse)
from std_srvs.srv import Empty, EmptyResponse
from tf.transformations import quaternion_from_euler

GAZEBO = "/fake_gazebo"
TIMEOUT = 30.0  # [s] for one spawn_model run

ROBOT = """<robot name="box_bot">
  <link name="base_link">
    <visual><geometry><mesh filename="package://bullet_sim/models/construction_cone/meshes/construction_cone.stl"/></geometry></visual>
  </link>
  <gazebo><plugin name="drive" filename="libgazebo_ros_diff_drive.so"><commandTopic>cmd_vel</commandTopic></plugin></gazebo>
  <gazebo><plugin name="truth" filename="libgazebo_ros_p3d.so"><robotNamespace>/own</robotNamespace></plugin></gazebo>
</robot>"""
SDF = """<sdf version="1.6"><model name="crate"><static>true</static><link name="link">
  <collision name="c"><geometry><box><size>1 1 1</size></box></geometry></collision></link></model></sdf>"""


class FakeGazebo:
    """Records the requests of each service; spawns of a model named `refused` fail."""

    def __init__(self):
        self.requests = {}
        self.changed = threading.Condition()
        self.models = ["ground_plane"]
        self.servers = [
            rospy.Service(GAZEBO + "/spawn_urdf", BulletSimSpawn, self.recorder(
                "spawn_urdf", lambda r: BulletSimSpawnResponse(r.model_name != "refused", "refused by the test"))),
            rospy.Service(GAZEBO + "/spawn_urdf_model", SpawnModel, self.recorder(
                "spawn_urdf_model", lambda r: SpawnModelResponse(True, "ok"))),
            rospy.Service(GAZEBO + "/spawn_sdf_model", SpawnModel, self.recorder(
                "spawn_sdf_model", lambda r: SpawnModelResponse(True, "ok"))),
            rospy.Service(GAZEBO + "/set_model_configuration", SetModelConfiguration, self.recorder(
                "set_model_configuration", lambda r: SetModelConfigurationResponse(True, "ok"))),
            rospy.Service(GAZEBO + "/unpause_physics", Empty, self.recorder(
                "unpause_physics", lambda r: EmptyResponse())),
            rospy.Service(GAZEBO + "/delete_model", DeleteModel, self.recorder(
                "delete_model", lambda r: DeleteModelResponse(True, "ok"))),
        ]
        self.states = rospy.Publisher(GAZEBO + "/model_states", ModelStates, queue_size=1)
        self.timer = rospy.Timer(rospy.Duration(0.05), lambda _: self.states.publish(ModelStates(name=self.models)))

    def recorder(self, service, respond):
        def handle(request):
            with self.changed:
                self.requests.setdefault(service, []).append((time.monotonic(), request))
                self.changed.notify_all()
            return respond(request)
        return handle

    def wait_for(self, service, timeout=TIMEOUT):
        """The first request to `service`, waiting up to `timeout` seconds for it."""
        deadline = time.monotonic() + timeout
        with self.changed:
            while service not in self.requests:
                remaining = deadline - time.monotonic()
                if remaining <= 0:
                    raise AssertionError("no call to %s within %.0f s" % (service, timeout))
                self.changed.wait(remaining)
            return self.requests[service][0]

    def clear(self):
        with self.changed:
            self.requests.clear()


def command(*flags):
    """spawn_model's command line against the fake simulator, its executable found as roslaunch finds it."""
    return roslib.packages.find_node("gazebo_ros", "spawn_model")[:1] + ["-gazebo_namespace", GAZEBO] + list(flags)


def spawn_model(*flags, stdin=None, env=None):
    """Runs spawn_model with `flags` against the fake simulator; its exit status and stderr."""
    run = subprocess.run(command(*flags),
                         input=stdin, capture_output=True, text=True, timeout=TIMEOUT,
                         env=dict(os.environ, **(env or {})))
    return run.returncode, run.stderr


class SpawnModelFlags(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.gazebo = FakeGazebo()
        cls.folder = tempfile.mkdtemp(prefix="spawn_model_flags_")
        cls.urdf = os.path.join(cls.folder, "robot.urdf")
        with open(cls.urdf, "w") as out:
            out.write(ROBOT)
        cls.sdf = os.path.join(cls.folder, "crate.sdf")
        with open(cls.sdf, "w") as out:
            out.write(SDF)

    def setUp(self):
        self.gazebo.clear()

    def spawned(self, service, *flags, **kwargs):
        status, errors = spawn_model(*flags, **kwargs)
        self.assertEqual(status, 0, errors)
        return self.gazebo.wait_for(service)[1]

    def test_urdf_in_the_world_frame_goes_to_bullet_sims_spawn_resting_on_the_ground(self):
        request = self.spawned("spawn_urdf", "-urdf", "-file", self.urdf, "-model", "bot", "-x", "1", "-y", "2",
                               "-R", "0.1", "-P", "0.2", "-Y", "0.3")
        self.assertEqual(request.model_name, "bot")
        self.assertTrue(request.place_on_ground, "no -z: the robot rests on the ground")
        self.assertEqual((request.initial_pose.position.x, request.initial_pose.position.y), (1.0, 2.0))
        q = request.initial_pose.orientation
        for got, expected in zip((q.x, q.y, q.z, q.w), quaternion_from_euler(0.1, 0.2, 0.3)):
            self.assertAlmostEqual(got, expected, places=9)
        # Gazebo's rule: plugins that name no namespace get spawn_model's (here "/"); the others keep theirs.
        self.assertEqual(request.robot_namespace, "")
        plugins = {p.get("name"): p.findtext("robotNamespace") for p in ET.fromstring(request.model_xml).iter("plugin")}
        self.assertEqual(plugins, {"drive": "/", "truth": "/own"})

    def test_z_places_the_model_exactly(self):
        request = self.spawned("spawn_urdf", "-urdf", "-file", self.urdf, "-model", "bot", "-z", "0.5")
        self.assertFalse(request.place_on_ground)
        self.assertEqual(request.initial_pose.position.z, 0.5)

    def test_robot_namespace_goes_to_the_plugins_without_one(self):
        request = self.spawned("spawn_urdf", "-urdf", "-file", self.urdf, "-model", "bot", "-robot_namespace", "/r1")
        plugins = {p.get("name"): p.findtext("robotNamespace") for p in ET.fromstring(request.model_xml).iter("plugin")}
        self.assertEqual(plugins, {"drive": "/r1", "truth": "/own"})

    def test_reference_frame_goes_to_spawn_urdf_model(self):
        request = self.spawned("spawn_urdf_model", "-urdf", "-file", self.urdf, "-model", "bot",
                               "-reference_frame", "table", "-x", "0.5")
        self.assertEqual((request.model_name, request.reference_frame), ("bot", "table"))
        self.assertEqual(request.initial_pose.position.x, 0.5)
        self.assertNotIn("spawn_urdf", self.gazebo.requests)

    def test_sdf_goes_to_spawn_sdf_model(self):
        request = self.spawned("spawn_sdf_model", "-sdf", "-file", self.sdf, "-model", "crate", "-z", "2")
        self.assertEqual(request.model_name, "crate")
        self.assertEqual(ET.fromstring(request.model_xml).find("model").get("name"), "crate")
        self.assertEqual(request.initial_pose.position.z, 2.0)

    def test_joints_go_through_set_model_configuration_and_unpause_follows(self):
        self.spawned("spawn_urdf", "-urdf", "-file", self.urdf, "-model", "bot", "-J", "pan", "0.5",
                     "-J", "tilt", "-1", "-unpause")
        configuration = self.gazebo.wait_for("set_model_configuration")[1]
        self.assertEqual(configuration.model_name, "bot")
        self.assertEqual(list(configuration.joint_names), ["pan", "tilt"])
        self.assertEqual(list(configuration.joint_positions), [0.5, -1.0])
        self.gazebo.wait_for("unpause_physics")

    def test_package_to_model_rewrites_mesh_uris(self):
        request = self.spawned("spawn_urdf", "-urdf", "-file", self.urdf, "-model", "bot", "-package_to_model")
        mesh = ET.fromstring(request.model_xml).find("link/visual/geometry/mesh")
        self.assertEqual(mesh.get("filename"), "model://bullet_sim/models/construction_cone/meshes/construction_cone.stl")

    def test_stdin_and_param_are_sources(self):
        self.assertEqual(self.spawned("spawn_urdf", "-urdf", "-stdin", "-model", "piped", stdin=ROBOT).model_name,
                         "piped")
        self.gazebo.clear()
        rospy.set_param("/flags_test/description", ROBOT)
        self.assertEqual(self.spawned("spawn_urdf", "-urdf", "-param", "/flags_test/description",
                                      "-model", "from_param").model_name, "from_param")

    def test_database_finds_the_model_on_gazebo_model_path(self):
        models = os.path.join(rospkg.RosPack().get_path("bullet_sim_bringup"), "test", "fixtures", "models")
        request = self.spawned("spawn_sdf_model", "-sdf", "-database", "marker_post", "-model", "post",
                               env={"GAZEBO_MODEL_PATH": models})
        uri = ET.fromstring(request.model_xml).find(".//mesh/uri").text
        self.assertEqual(uri, os.path.join(models, "marker_post", "meshes", "post.stl"),
                         "relative URIs of the model become absolute")

    def test_wait_spawns_only_once_the_model_exists(self):
        self.gazebo.models = ["ground_plane"]
        process = subprocess.Popen(command("-urdf", "-file", self.urdf, "-model", "second", "-wait", "first"))
        try:
            deadline = time.monotonic() + TIMEOUT
            while self.gazebo.states.get_num_connections() == 0:  # spawn_model is listening
                self.assertLess(time.monotonic(), deadline, "spawn_model never subscribed to model_states")
                time.sleep(0.05)
            added = time.monotonic()
            self.gazebo.models = ["ground_plane", "first"]
            called, request = self.gazebo.wait_for("spawn_urdf")
            self.assertGreater(called, added, "spawned before [first] existed")
            self.assertEqual(request.model_name, "second")
            self.assertEqual(process.wait(timeout=TIMEOUT), 0)
        finally:
            process.kill()
            self.gazebo.models = ["ground_plane"]

    def test_bond_deletes_the_model_when_spawn_model_stops(self):
        process = subprocess.Popen(command("-urdf", "-file", self.urdf, "-model", "bonded", "-b"),
                                   stdout=subprocess.PIPE, text=True)
        try:
            self.gazebo.wait_for("spawn_urdf")
            # The spawn's answer has arrived once spawn_model says it waits.
            said = threading.Event()

            def read():
                for line in process.stdout:
                    if "Waiting for shutdown to delete model bonded" in line:
                        said.set()
            threading.Thread(target=read, daemon=True).start()
            self.assertTrue(said.wait(TIMEOUT), "spawn_model never said it waits to delete the model")
            self.assertIsNone(process.poll(), "with -b, spawn_model stays up")
            process.send_signal(signal.SIGINT)
            self.assertEqual(self.gazebo.wait_for("delete_model")[1].model_name, "bonded")
            process.wait(timeout=TIMEOUT)
        finally:
            process.kill()
            process.stdout.close()

    def test_failures_exit_non_zero_with_the_reason(self):
        status, errors = spawn_model("-urdf", "-file", self.urdf, "-model", "refused")
        self.assertEqual(status, 1)
        self.assertIn("refused by the test", errors)
        status, errors = spawn_model("-urdf", "-file", os.path.join(self.folder, "missing.urdf"), "-model", "m")
        self.assertEqual(status, 1)
        self.assertIn("missing.urdf] does not exist", errors)
        status, errors = spawn_model("-urdf", "-stdin", "-model", "m", stdin="<robot name='x'><link")
        self.assertEqual(status, 1)
        self.assertIn("Invalid XML", errors)
        status, errors = spawn_model("-urdf", "-param", "/no/such/param", "-model", "m")
        self.assertEqual(status, 1)
        self.assertIn("no parameter [/no/such/param]", errors)
        status, errors = spawn_model("-urdf", "-file", self.urdf, "-model", "m", "-J", "pan", "half")
        self.assertEqual(status, 2, "a bad command line is argparse's usage error")
        self.assertIn("-J takes a joint name and a number", errors)
        self.assertEqual(spawn_model("-urdf", "-file", self.urdf)[0], 2, "-model is required")


if __name__ == "__main__":
    rospy.init_node("spawn_model_flags")
    rostest.rosrun("bullet_sim_bringup", "spawn_model_flags", SpawnModelFlags, sys.argv)
