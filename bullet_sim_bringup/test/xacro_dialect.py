#!/usr/bin/env python3
"""rostest node: the xacro package runs Noetic's dialect of xacro (1.14.17) through each way a user calls it.

`xacro` on PATH, `rosrun xacro xacro` and `$(find xacro)/xacro` (as roslaunch resolves it) expand the same file to
the same URDF. xacro.load_yaml reads `!degrees` and `!radians`; `$(find)` resolves through rospkg; `$(arg)`,
`$(env)`, `$(optenv)`, `$(eval)`, `$(cwd)` and `$(anon)` resolve as on Noetic, and the failures (an undefined
argument, an unknown package, an unset variable, `$(dirname)`, an unknown command) say what Noetic's xacro says.
`--deps` lists the files a description includes and loads, as xacro_add_files needs.
"""
import math
import os
import shutil
import subprocess
import sys
import tempfile
import unittest
import xml.etree.ElementTree as ET

import rospkg
import rostest
from roslaunch.substitution_args import resolve_args

TIMEOUT = 30.0  # [s] per xacro run
HEAD = '<?xml version="1.0"?>\n<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'


class XacroDialect(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.folder = tempfile.mkdtemp(prefix="xacro_dialect_")

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.folder, ignore_errors=True)

    def write(self, name, text):
        path = os.path.join(self.folder, name)
        with open(path, "w") as f:
            f.write(text)
        return path

    def xacro(self, body, *args, command=("xacro",), env=None):
        """Runs `command` on a file holding `body` in <robot>; (exit status, stdout, stderr)."""
        path = self.write("robot.urdf.xacro", HEAD + body + "\n</robot>\n")
        run = subprocess.run([*command, path, *args], capture_output=True, text=True, timeout=TIMEOUT,
                             cwd=self.folder, env=dict(os.environ, **(env or {})))
        return run.returncode, run.stdout, run.stderr

    def attributes(self, body, *args, **kwargs):
        """The attributes of the <a> element a successful expansion of `body` holds."""
        status, out, err = self.xacro(body, *args, **kwargs)
        self.assertEqual(status, 0, err)
        return ET.fromstring(out).find("a").attrib

    def test_every_entry_point_expands_alike(self):
        self.write("angles.yaml", "right: !degrees 90\n")
        body = ('<xacro:property name="angles" value="${xacro.load_yaml(\'angles.yaml\')}"/>'
                '<a path="$(find bullet_sim_bringup)" right="${angles.right}"/>')
        find_xacro = resolve_args("$(find xacro)/xacro")
        outputs = {}
        for name, command in [("xacro on PATH", ("xacro",)), ("rosrun xacro xacro", ("rosrun", "xacro", "xacro")),
                              ("$(find xacro)/xacro", (find_xacro,))]:
            status, out, err = self.xacro(body, command=command)
            self.assertEqual(status, 0, "%s: %s" % (name, err))
            outputs[name] = ET.canonicalize(out, strip_text=True)
        self.assertEqual(len(set(outputs.values())), 1, outputs)
        a = ET.fromstring(outputs["xacro on PATH"]).find("a").attrib
        self.assertEqual(a["path"], rospkg.RosPack().get_path("bullet_sim_bringup"))
        self.assertAlmostEqual(float(a["right"]), math.pi / 2, places=12)

    def test_load_yaml_reads_angle_tags_with_dotted_access(self):
        self.write("arm.yaml", "joints:\n  - {name: pan, max: !degrees 170, min: !radians -pi/4}\n"
                               "limits: {elbow: {max: !degrees -45.5}}\n")
        a = self.attributes('<xacro:property name="arm" value="${xacro.load_yaml(\'arm.yaml\')}"/>'
                            '<a pan="${arm.joints[0].max}" low="${arm.joints[0].min}" elbow="${arm.limits.elbow.max}"'
                            ' name="${arm.joints[0].name}"/>')
        self.assertAlmostEqual(float(a["pan"]), math.radians(170), places=12)
        self.assertAlmostEqual(float(a["low"]), -math.pi / 4, places=12)
        self.assertAlmostEqual(float(a["elbow"]), math.radians(-45.5), places=12)
        self.assertEqual(a["name"], "pan")

    def test_substitutions_resolve_as_on_noetic(self):
        a = self.attributes('<xacro:arg name="b" default="7"/>'
                            '<a arg="$(arg a)" default="$(arg b)" env="$(env XACRO_DIALECT_VALUE)"'
                            ' optenv="$(optenv XACRO_DIALECT_UNSET two words)" eval="$(eval 2 * a + 1)"'
                            ' find="$(find bullet_sim_bringup)/test" cwd="$(cwd)"'
                            ' anon="$(anon node)" again="$(anon node)"/>',
                            "a:=3", env={"XACRO_DIALECT_VALUE": "from the environment"})
        self.assertEqual(a["arg"], "3")
        self.assertEqual(a["default"], "7")
        self.assertEqual(a["env"], "from the environment")
        self.assertEqual(a["optenv"], "two words")
        self.assertEqual(a["eval"], "7")
        self.assertEqual(a["find"], os.path.join(rospkg.RosPack().get_path("bullet_sim_bringup"), "test"))
        self.assertEqual(a["cwd"], self.folder)
        self.assertTrue(a["anon"].startswith("node_"), a["anon"])
        self.assertEqual(a["anon"], a["again"], "one anonymous name per name in a file")

    def test_failures_say_what_noetic_says(self):
        for body, message in [
                ('<a b="$(arg undefined_argument)"/>', "Undefined substitution argument undefined_argument"),
                ('<a b="$(find no_such_package_here)"/>', "resource not found: no_such_package_here"),
                ('<a b="$(env XACRO_DIALECT_UNSET)"/>', "environment variable 'XACRO_DIALECT_UNSET' is not set"),
                ('<a b="$(dirname)"/>', "Cannot substitute $(dirname), no file/directory information available."),
                ('<a b="$(where is)"/>', "Unknown substitution command [where is]")]:
            status, out, err = self.xacro(body)
            self.assertEqual(status, 2, body)
            self.assertIn(message, err, body)
            self.assertNotIn("<class", err, "2.x's wrapping of the message")

    def test_deps_lists_includes_and_loaded_yaml(self):
        part = self.write("part.xacro", HEAD + '<xacro:property name="p" value="${xacro.load_yaml(\'p.yaml\')}"/>'
                                               '<link name="link${p.x}"/>\n</robot>\n')
        loaded = self.write("p.yaml", "x: 1\n")
        status, out, err = self.xacro('<xacro:include filename="part.xacro"/>', "--deps")
        self.assertEqual(status, 0, err)
        self.assertEqual(sorted(os.path.abspath(os.path.join(self.folder, f)) for f in out.split()),
                         sorted([part, loaded]))

    def test_melodic_inorder_flag_is_accepted(self):
        self.assertEqual(self.attributes('<a b="${1 + 1}"/>', "--inorder")["b"], "2")


if __name__ == "__main__":
    rostest.rosrun("bullet_sim_bringup", "xacro_dialect", XacroDialect, sys.argv)
