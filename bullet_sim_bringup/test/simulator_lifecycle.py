#!/usr/bin/env python3
"""Test node: the simulator's life, each run against a ROS master of its own on a free port. `rosrun bullet_sim
simulator` registers as /gazebo; SIGINT ends it within 2 s whether it waits for the master, steps, is paused or
is importing a large mesh; a ~threads it cannot take, or a parameter of the wrong type, ends it with the value
named (ackermann_joint_commander's too); and when the master restarts, it exits with a message, so that
respawn="true" restarts it."""
import os
import re
import shutil
import signal
import socket
import struct
import subprocess
import sys
import tempfile
import threading
import time
import unittest

import rosgraph
import rospy
import rostest

EXIT_AFTER_SIGINT = 2.0  # [s] the bound


def free_port():
    with socket.socket() as s:
        s.bind(("localhost", 0))
        return s.getsockname()[1]


class Output:
    """Collects a process's merged stdout and stderr; wait_for() blocks until a pattern shows or a deadline."""

    def __init__(self, process):
        self.text = ""
        self._changed = threading.Condition()
        self._thread = threading.Thread(target=self._read, args=(process.stdout,), daemon=True)
        self._thread.start()

    def _read(self, stream):
        for line in iter(stream.readline, ""):
            with self._changed:
                self.text += line
                self._changed.notify_all()

    def wait_for(self, pattern, timeout):
        deadline = time.monotonic() + timeout
        with self._changed:
            while not re.search(pattern, self.text):
                remaining = deadline - time.monotonic()
                if remaining <= 0:
                    raise AssertionError("timed out after %.0f s waiting for [%s] in:\n%s" % (timeout, pattern, self.text))
                self._changed.wait(remaining)


def binary_stl(path, triangles):
    """A binary STL of `triangles` small triangles in a row: a large mesh that takes assimp seconds."""
    with open(path, "wb") as stl:
        stl.write(b"\0" * 80 + struct.pack("<I", triangles))
        row = bytearray()
        for i in range(triangles):
            x = (i % 1000) * 1e-3
            y = (i // 1000) * 1e-3
            row += struct.pack("<12fH", 0, 0, 1, x, y, 0, x + 1e-3, y, 0, x, y + 1e-3, 0, 0)
            if len(row) > 1 << 20:
                stl.write(row)
                row = bytearray()
        stl.write(row)


class SimulatorLifecycle(unittest.TestCase):
    def setUp(self):
        self.folder = tempfile.mkdtemp(prefix="simulator_lifecycle_")
        self.port = free_port()
        self.env = dict(os.environ, ROS_MASTER_URI="http://localhost:%d" % self.port, ROS_HOME=self.folder,
                        ROSCONSOLE_STDOUT_LINE_BUFFERED="1")
        self.processes = []

    def tearDown(self):
        for process in self.processes:
            if process.poll() is None:
                process.kill()
                process.wait(timeout=10)
        shutil.rmtree(self.folder)

    def start(self, *command):
        process = subprocess.Popen(list(command), env=self.env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                   text=True)
        self.processes.append(process)
        return process, Output(process)

    def start_master(self):
        master, _ = self.start("rosmaster", "--core", "-p", str(self.port))
        master_api = rosgraph.Master("/simulator_lifecycle", master_uri=self.env["ROS_MASTER_URI"])
        deadline = time.monotonic() + 30
        while not master_api.is_online():
            self.assertLess(time.monotonic(), deadline, "the master did not come up")
            time.sleep(0.05)  # polling a server that is starting: nothing to wait on instead
        return master, master_api

    def start_simulator(self, *args):
        return self.start("rosrun", "bullet_sim", "simulator", *args)

    def wait_registered(self, master_api, service="/gazebo/spawn_urdf", timeout=60):
        deadline = time.monotonic() + timeout
        while True:
            try:
                return master_api.lookupService(service)
            except rosgraph.MasterError:
                self.assertLess(time.monotonic(), deadline, "%s was never advertised" % service)
                time.sleep(0.05)

    def assert_sigint_ends_it(self, simulator, output):
        started = time.monotonic()
        simulator.send_signal(signal.SIGINT)
        try:
            simulator.wait(timeout=EXIT_AFTER_SIGINT)
        except subprocess.TimeoutExpired:
            self.fail("the simulator was still running %.1f s after SIGINT:\n%s" % (EXIT_AFTER_SIGINT, output.text))
        return time.monotonic() - started

    def test_it_registers_as_gazebo_by_default(self):
        _, master_api = self.start_master()
        self.start_simulator()
        self.wait_registered(master_api)
        self.assertTrue(master_api.lookupNode("/gazebo"))

    def test_sigint_ends_it_while_it_waits_for_the_master(self):
        simulator, output = self.start_simulator()
        output.wait_for(r"Failed to contact master", 60)
        self.assert_sigint_ends_it(simulator, output)

    def test_sigint_ends_it_while_it_steps_and_while_it_is_paused(self):
        _, master_api = self.start_master()
        for args in (["_real_time_factor:=0"], ["_paused:=true"]):
            simulator, output = self.start_simulator(*args)
            self.wait_registered(master_api)
            self.assert_sigint_ends_it(simulator, output)
            services = [service for service, _ in master_api.getSystemState()[2]]
            self.assertNotIn("/gazebo/spawn_urdf", services, "it did not shut down cleanly")

    def test_sigint_ends_it_while_it_imports_a_large_mesh(self):
        _, master_api = self.start_master()
        simulator, output = self.start_simulator()
        self.wait_registered(master_api)
        mesh = os.path.join(self.folder, "large.stl")
        binary_stl(mesh, 2000000)  # 100 MB: assimp takes seconds
        urdf = os.path.join(self.folder, "large.urdf")
        with open(urdf, "w") as robot:
            robot.write('<robot name="large"><link name="base"><inertial><mass value="1"/><inertia ixx="0.01" '
                        'iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial><visual><geometry><mesh '
                        'filename="file://%s"/></geometry></visual></link></robot>' % mesh)
        self.start("rosrun", "bullet_sim", "spawn_model", "-urdf", "-file", urdf, "-model", "large")
        output.wait_for(r"spawning model \[large\]", 60)
        self.assert_sigint_ends_it(simulator, output)
        self.assertIn("still busy after SIGINT", output.text)  # it was in the import, not between steps

    def test_threads_is_taken_and_a_bad_count_ends_it_naming_the_value(self):
        _, master_api = self.start_master()
        for bad, named in (("two", '"two"'), ("-1", "-1"), ("65", "65"), ("1.5", "1.5"), ("true", "true")):
            simulator, output = self.start_simulator("_threads:=" + bad)
            try:
                status = simulator.wait(timeout=60)
            except subprocess.TimeoutExpired:
                self.fail("the simulator ran on with ~threads %s:\n%s" % (bad, output.text))
            self.assertEqual(status, 1, output.text)
            output.wait_for(r"~threads must be a whole number from 0 .* to 64, not %s\n" % re.escape(named), 10)
        self.start_simulator("_threads:=2.0")  # a whole number, written as a double
        self.wait_registered(master_api)

    def test_a_parameter_of_the_wrong_type_ends_it_naming_the_value(self):
        _, master_api = self.start_master()
        for given, named in (("_paused:=yes", r'~paused must be true or false, not "yes" \(/gazebo/paused\)'),
                             ("_step_size:=fast", r'~step_size must be a number, not "fast"'),
                             ("_world:=3", r"~world must be a string, not 3"),
                             ("_seed:=1.5", r"~seed must be a whole number, not 1.5"),
                             ("_limits/max_links:=many", r'~limits/max_links must be a number, not "many"')):
            simulator, output = self.start_simulator(given)
            try:
                status = simulator.wait(timeout=60)
            except subprocess.TimeoutExpired:
                self.fail("the simulator ran on with %s:\n%s" % (given, output.text))
            self.assertEqual(status, 1, output.text)
            output.wait_for(named, 10)
            master_api.deleteParam("/gazebo/" + given[1:].split(":=")[0])  # the master keeps it for the next run
        # roscpp would have taken 1 as "not set", and run unpaused; it is taken as true, with a warning.
        _, output = self.start_simulator("_paused:=1")
        self.wait_registered(master_api)
        output.wait_for(r"~paused: 1 taken as true; write true or false", 10)
        properties = subprocess.run(["rosservice", "call", "/gazebo/get_physics_properties"], env=self.env,
                                    capture_output=True, text=True, timeout=30)
        self.assertRegex(properties.stdout, r"pause: True", properties.stdout + properties.stderr)

    def test_a_negative_seed_is_taken_with_a_warning(self):
        _, master_api = self.start_master()
        _, output = self.start_simulator("_seed:=-3")  # gzserver --seed takes it too
        self.wait_registered(master_api)
        output.wait_for(r"~seed -3 is negative: taken as the unsigned seed 18446744073709551613", 10)

    def test_the_ackermann_commander_too_names_a_parameter_of_the_wrong_type(self):
        self.start_master()
        joints = ["_%s:=%s" % (name, name) for name in ("left_steering_joint", "right_steering_joint",
                                                       "front_left_joint", "front_right_joint",
                                                       "rear_left_joint", "rear_right_joint")]
        commander, output = self.start("rosrun", "bullet_sim", "ackermann_joint_commander", "_max_steer:=wide",
                                       *joints)
        try:
            status = commander.wait(timeout=60)
        except subprocess.TimeoutExpired:
            self.fail("the commander ran on with ~max_steer wide:\n" + output.text)
        self.assertEqual(status, 1, output.text)
        output.wait_for(r'~max_steer must be a number, not "wide" \(/ackermann_joint_commander/max_steer\)', 10)

    def test_it_exits_with_a_message_when_the_master_restarts(self):
        master, master_api = self.start_master()
        simulator, output = self.start_simulator()
        self.wait_registered(master_api)
        master.send_signal(signal.SIGINT)
        master.wait(timeout=30)
        self.start_master()
        try:
            status = simulator.wait(timeout=30)
        except subprocess.TimeoutExpired:
            self.fail("the simulator did not notice the master restart:\n" + output.text)
        self.assertEqual(status, 1, output.text)
        self.assertRegex(output.text, r"the ROS master at http://localhost:%d/? (restarted|has not answered)" % self.port)
        self.assertIn('respawn="true"', output.text)


if __name__ == "__main__":
    rospy.init_node("simulator_lifecycle")
    rostest.rosrun("bullet_sim_bringup", "simulator_lifecycle", SimulatorLifecycle, sys.argv)
