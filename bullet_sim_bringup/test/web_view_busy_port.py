#!/usr/bin/env python3
"""rostest node: a simulator whose ~web_port is taken says so in one error and runs on without the viewer.
It runs against a ROS master of its own (on a free port), with another program listening on its web port."""
import os
import shutil
import socket
import subprocess
import sys
import tempfile
import unittest

import rospy
import rostest

from simulator_lifecycle import Output, free_port


class WebViewBusyPort(unittest.TestCase):
    def setUp(self):
        self.folder = tempfile.mkdtemp(prefix="web_view_busy_port_")
        self.env = dict(os.environ, ROS_MASTER_URI="http://localhost:%d" % free_port(), ROS_HOME=self.folder,
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

    def test_a_busy_port_is_one_error_and_the_simulation_runs_on(self):
        with socket.socket() as other:
            other.bind(("127.0.0.1", 0))
            other.listen()
            port = other.getsockname()[1]
            self.start("rosmaster", "--core", "-p", self.env["ROS_MASTER_URI"].rsplit(":", 1)[1])
            simulator, output = self.start("rosrun", "bullet_sim", "simulator", "_web_port:=%d" % port)
            error = (r"~web_port %d: no web viewer: cannot listen on 127\.0\.0\.1:%d: another program already "
                     r"listens there\. The simulation runs on without it\." % (port, port))
            output.wait_for(error, 40)
            output.wait_for(r"first /clock", 20)  # it steps
            self.assertIsNone(simulator.poll(), output.text)
            self.assertEqual(output.text.count("no web viewer"), 1, output.text)


if __name__ == "__main__":
    rospy.init_node("web_view_busy_port")
    rostest.rosrun("bullet_sim_bringup", "web_view_busy_port", WebViewBusyPort, sys.argv)
