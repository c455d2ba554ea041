#!/usr/bin/env python3
"""rostest node: gazebo_ros's node types on bullet_sim. gzserver maps gzserver's command line onto the
simulator's parameters, falls back on the empty world when the world cannot be found, and skips an unknown
model with one warning (an error with ~strict_models); gzclient says there is no window and stays up; gazebo
and debug run the simulator too."""
import os
import subprocess
import sys
import threading
import time
import unittest

import roslib.packages
import rospkg
import rospy
import rostest

from bringup_support import interrupt

TIMEOUT = 60.0  # [s] for a simulator to come up or go down


def node_type(name):
    """The executable of a gazebo_ros node type, as roslaunch finds it."""
    return roslib.packages.find_node("gazebo_ros", name)[0]


class Started:
    """A gazebo_ros node type run with `arguments`; stopped with SIGINT (then killed) when the block ends."""

    def __init__(self, name, *arguments):
        # rosconsole flushes stdout (INFO) line by line only when asked to.
        self.process = subprocess.Popen([node_type(name)] + list(arguments), stdout=subprocess.PIPE,
                                        stderr=subprocess.PIPE, text=True,
                                        env=dict(os.environ, ROSCONSOLE_STDOUT_LINE_BUFFERED="1"))
        self.stdout, self.stderr = [], []
        self.said = threading.Condition()
        for stream, lines in ((self.process.stdout, self.stdout), (self.process.stderr, self.stderr)):
            threading.Thread(target=self._read, args=(stream, lines), daemon=True).start()

    def _read(self, stream, lines):
        for line in stream:
            with self.said:
                lines.append(line)
                self.said.notify_all()

    def wait_for_line(self, lines, text, timeout=TIMEOUT):
        deadline = time.monotonic() + timeout
        with self.said:
            while not any(text in line for line in lines):
                remaining = deadline - time.monotonic()
                if remaining <= 0:
                    raise AssertionError("no line with [%s] within %.0f s in %s" % (text, timeout, lines))
                self.said.wait(remaining)

    def stop(self):
        return interrupt(self.process, TIMEOUT)

    def __enter__(self):
        return self

    def __exit__(self, *_):
        self.stop()


def wait_for_simulator(timeout=TIMEOUT):
    rospy.wait_for_service("/gazebo/spawn_urdf", timeout)


def fixture_world(name):
    return os.path.join(rospkg.RosPack().get_path("bullet_sim"), "test", "fixtures", "worlds", name)


class NodeTypes(unittest.TestCase):
    def test_gzserver_maps_its_command_line_onto_the_simulator(self):
        with Started("gzserver", "-u", "--verbose", "-e", "ode", "-s", "libgazebo_ros_api_plugin.so",
                     "-s", "libgazebo_ros_paths_plugin.so", "-s", "libmy_world_plugin.so", "--seed", "7",
                     "--lockstep", "--iters", "10", "--bogus", "worlds/shapes.world") as server:
            wait_for_simulator()
            self.assertEqual(rospy.get_param("/gazebo/world"), "worlds/shapes.world")
            self.assertIs(rospy.get_param("/gazebo/paused"), True)
            self.assertEqual(rospy.get_param("/gazebo/seed"), 7)
            self.assertIs(rospy.get_param("/gazebo/lockstep"), True)
            server.wait_for_line(server.stdout, "bullet_sim/worlds/shapes.world")  # the simulator's INFO
            server.wait_for_line(server.stderr, "system plugin [libmy_world_plugin.so] ignored")
            server.wait_for_line(server.stderr, "--iters is not honoured")
            server.wait_for_line(server.stderr, "unknown options ['--bogus'] ignored")
            self.assertFalse(any("libgazebo_ros_api_plugin" in line for line in server.stderr),
                             "the ROS API and paths plugins are what bullet_sim serves")

    def test_a_world_that_cannot_be_found_falls_back_on_the_empty_world(self):
        with Started("gzserver", "no_such.world") as server:
            wait_for_simulator()
            server.wait_for_line(server.stderr, "no world file [no_such.world]")  # the simulator's WARN
            server.wait_for_line(server.stderr, "falling back on worlds/empty.world, as gzserver does")
            server.wait_for_line(server.stdout, "bullet_sim/worlds/empty.world")

    def test_an_unknown_model_is_skipped_with_one_warning_or_refused_when_strict(self):
        with Started("gzserver", fixture_world("unknown_model.world")) as server:
            wait_for_simulator()
            server.wait_for_line(server.stderr, "skipped (2 includes), the rest of the world loads: unknown model "
                                 "[ground_plan] (did you mean [ground_plane]?); the model path is ")
            self.assertEqual(sum("unknown model" in line for line in server.stderr), 1, "one warning")
        strict = Started("gzserver", "_strict_models:=true", fixture_world("unknown_model.world"))
        self.assertEqual(strict.process.wait(timeout=TIMEOUT), 1)
        strict.wait_for_line(strict.stderr, "unknown model [ground_plan]")

    def test_play_is_refused(self):
        refused = Started("gzserver", "-p", "state.log")
        self.assertEqual(refused.process.wait(timeout=TIMEOUT), 1)
        refused.wait_for_line(refused.stderr, "cannot play Gazebo logs")

    def test_gzclient_says_there_is_no_window_and_stays_up_until_stopped(self):
        client = Started("gzclient", "--verbose")
        client.wait_for_line(client.stdout, "there is no window to show")
        self.assertIsNone(client.process.poll())
        self.assertEqual(client.stop(), 0)

    def test_gazebo_and_debug_run_the_simulator(self):
        for name in ("gazebo", "debug"):
            with Started(name, "-u", "worlds/empty.world") as server:
                wait_for_simulator()
                if name == "gazebo":
                    server.wait_for_line(server.stdout, "there is no window to show")


if __name__ == "__main__":
    rospy.init_node("gazebo_ros_node_types")
    rostest.rosrun("bullet_sim_bringup", "gazebo_ros_node_types", NodeTypes, sys.argv)
