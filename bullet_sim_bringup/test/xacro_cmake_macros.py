#!/usr/bin/env python3
"""rostest node: the xacro package's CMake functions behave as Noetic's (xacro's cmake/xacro-extras.cmake).

Each case configures and builds a catkin package with cmake and make, as catkin_make builds one, in a temporary
folder:
- the Noetic arm look-alike's description (fixtures/noetic_arm_lookalike), whose CMakeLists.txt calls
  `xacro_add_files(urdf/arm.urdf.xacro INSTALL DESTINATION urdf)`: `make` writes the URDF that xacro makes of the
  file into the build folder and the devel space, `make install` installs it, and editing a YAML file the
  description loads makes `make` write it again;
- a package the test writes, calling xacro_add_xacro_file with an explicit output, REMAP and OUTPUT, xacro_install,
  and xacro_add_files with a TARGET and no INSTALL;
- xacro_add_xacro_file on a file whose name does not end in .xacro, with no output, which fails at configure time.
"""
import os
import shutil
import subprocess
import sys
import tempfile
import unittest
import xml.etree.ElementTree as ET

import rospkg
import rostest

TIMEOUT = 120.0  # [s] per cmake or make run
XACRO_HEAD = '<?xml version="1.0"?>\n<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="r">\n'

FUNCTIONS_PROJECT = """cmake_minimum_required(VERSION 3.0.2)
project(xacro_functions)
find_package(catkin REQUIRED COMPONENTS xacro)
catkin_package()

xacro_add_xacro_file(greeting.xml named.xml REMAP greeting:=hello)
set(outputs ${XACRO_OUTPUT_FILE})
xacro_add_xacro_file(sub/two.urdf.xacro OUTPUT TWO_FILE)
list(APPEND outputs ${TWO_FILE})
add_custom_target(manual ALL DEPENDS ${outputs})
xacro_install(manual ${outputs} DESTINATION xml)

xacro_add_files(three.urdf.xacro REMAP greeting:=hi TARGET more)
"""


def canonical(urdf):
    return ET.canonicalize(urdf, strip_text=True)


class XacroCMakeMacros(unittest.TestCase):
    def setUp(self):
        self.folder = tempfile.mkdtemp(prefix="xacro_cmake_")

    def tearDown(self):
        shutil.rmtree(self.folder, ignore_errors=True)

    def path(self, *parts):
        return os.path.join(self.folder, *parts)

    def run_in_build(self, *command):
        return subprocess.run(command, cwd=self.path("build"), capture_output=True, text=True, timeout=TIMEOUT)

    def configure(self, source):
        os.makedirs(self.path("build"), exist_ok=True)
        return self.run_in_build("cmake", source, "-DCATKIN_DEVEL_PREFIX=" + self.path("devel"),
                                 "-DCMAKE_INSTALL_PREFIX=" + self.path("install"))

    def build(self, *targets):
        made = self.run_in_build("make", *targets)
        self.assertEqual(made.returncode, 0, made.stdout + made.stderr)

    def read(self, *parts):
        with open(self.path(*parts)) as f:
            return f.read()

    def write(self, relative, text):
        os.makedirs(os.path.dirname(self.path("src", relative)), exist_ok=True)
        with open(self.path("src", relative), "w") as f:
            f.write(text)

    def test_lookalike_description_generates_installs_and_regenerates_its_urdf(self):
        fixture = os.path.join(rospkg.RosPack().get_path("bullet_sim_bringup"), "test", "fixtures",
                               "noetic_arm_lookalike", "noetic_arm_description")
        source = self.path("src", "noetic_arm_description")
        shutil.copytree(fixture, source)
        configured = self.configure(source)
        self.assertEqual(configured.returncode, 0, configured.stdout + configured.stderr)
        self.build()

        xacro = os.path.join(source, "urdf", "arm.urdf.xacro")
        env = dict(os.environ, ROS_PACKAGE_PATH=self.path("src") + ":" + os.environ.get("ROS_PACKAGE_PATH", ""))
        expected = canonical(subprocess.check_output(["xacro", xacro], env=env, text=True, timeout=TIMEOUT))
        self.assertEqual(canonical(self.read("build", "urdf", "arm.urdf")), expected)
        self.assertEqual(canonical(self.read("devel", "share", "noetic_arm_description", "urdf", "arm.urdf")),
                         expected)
        self.build("install")
        self.assertEqual(canonical(self.read("install", "share", "noetic_arm_description", "urdf", "arm.urdf")),
                         expected)

        limits = os.path.join(source, "config", "joint_limits.yaml")
        with open(limits) as f:
            text = f.read()
        self.assertIn("max_effort: 20.0", text)
        with open(limits, "w") as f:
            f.write(text.replace("max_effort: 20.0", "max_effort: 25.0"))
        self.build()
        elbow = ET.fromstring(self.read("devel", "share", "noetic_arm_description", "urdf", "arm.urdf"))
        self.assertEqual(elbow.find("joint[@name='elbow_joint']/limit").get("effort"), "25.0",
                         "make did not expand the description again after a YAML file it loads changed")

    def test_each_function_with_its_options(self):
        greeting = XACRO_HEAD + '<xacro:arg name="greeting" default="none"/><link name="$(arg greeting)"/>\n</robot>\n'
        self.write("greeting.xml", greeting)
        self.write("sub/two.urdf.xacro", XACRO_HEAD + '<link name="two"/>\n</robot>\n')
        self.write("three.urdf.xacro", greeting)
        self.write("CMakeLists.txt", FUNCTIONS_PROJECT)
        self.write("package.xml", '<?xml version="1.0"?><package format="2"><name>xacro_functions</name>'
                                  '<version>0.0.0</version><description>test</description>'
                                  '<maintainer email="a@b.invalid">a</maintainer><license>BSD</license>'
                                  '<buildtool_depend>catkin</buildtool_depend><build_depend>xacro</build_depend>'
                                  '</package>')
        configured = self.configure(self.path("src"))
        self.assertEqual(configured.returncode, 0, configured.stdout + configured.stderr)
        self.build()

        link = lambda *parts: ET.fromstring(self.read(*parts)).find("link").get("name")
        self.assertEqual(link("build", "named.xml"), "hello")
        self.assertEqual(link("build", "sub", "two.urdf"), "two")
        self.assertEqual(link("build", "three.urdf"), "hi")
        devel = ("devel", "share", "xacro_functions", "xml")
        self.assertEqual(sorted(os.listdir(self.path(*devel))), ["named.xml", "two.urdf"])
        self.build("xacro_functions_more")
        self.build("install")
        self.assertEqual(sorted(os.listdir(self.path("install", "share", "xacro_functions", "xml"))),
                         ["named.xml", "two.urdf"])
        self.assertFalse(os.path.exists(self.path("install", "share", "xacro_functions", "three.urdf")),
                         "xacro_add_files without INSTALL installed its output")

    def test_input_without_xacro_suffix_needs_an_output(self):
        self.write("plain.xml", XACRO_HEAD + "</robot>\n")
        self.write("CMakeLists.txt", "cmake_minimum_required(VERSION 3.0.2)\nproject(xacro_no_output)\n"
                                     "find_package(catkin REQUIRED COMPONENTS xacro)\nxacro_add_xacro_file(plain.xml)\n")
        configured = self.configure(self.path("src"))
        self.assertNotEqual(configured.returncode, 0)
        self.assertIn("xacro_add_xacro_file(plain.xml): give an <output>", configured.stderr)


if __name__ == "__main__":
    rostest.rosrun("bullet_sim_bringup", "xacro_cmake_macros", XacroCMakeMacros, sys.argv)
