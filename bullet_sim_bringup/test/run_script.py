#!/usr/bin/env python3
"""rostest node: runs a user's script (~script, a file beside this one, with ~args) as a process, as its user
would, within ~timeout wall seconds; it must exit 0."""
import os
import shlex
import subprocess
import sys
import unittest

import rospy
import rostest


class RunScript(unittest.TestCase):
    def test_the_script_exits_0(self):
        script = os.path.join(os.path.dirname(os.path.abspath(__file__)), rospy.get_param("~script"))
        args = shlex.split(rospy.get_param("~args", ""))
        result = subprocess.run([sys.executable, script] + args, capture_output=True, text=True,
                                timeout=rospy.get_param("~timeout", 120))
        self.assertEqual(result.returncode, 0, "%s said:\n%s%s" % (script, result.stdout, result.stderr))


if __name__ == "__main__":
    rospy.init_node("run_script")
    rostest.rosrun("bullet_sim_bringup", "run_script", RunScript, sys.argv)
