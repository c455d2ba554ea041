#!/usr/bin/env python3
"""rostest node: every link of /robot_description is reachable in tf from ~root (default: its root link)."""
import sys
import unittest
import xml.etree.ElementTree as ET

import rospy
import rostest
import tf2_ros


class TfTreeComplete(unittest.TestCase):
    def test_every_link_is_in_tf(self):
        urdf = ET.fromstring(rospy.get_param("robot_description"))
        links = [link.get("name") for link in urdf.findall("link")]
        children = {joint.find("child").get("link") for joint in urdf.findall("joint")}
        roots = [link for link in links if link not in children]
        self.assertEqual(len(roots), 1, "one root link expected, got %s" % roots)
        root = rospy.get_param("~root", roots[0])

        buffer = tf2_ros.Buffer()
        tf2_ros.TransformListener(buffer)
        timeout = rospy.Duration(rospy.get_param("~timeout", 20.0))
        missing = [link for link in links
                   if not buffer.can_transform(root, link, rospy.Time(0), timeout)]
        self.assertEqual(missing, [], "no transform from %s to %s" % (root, missing))


if __name__ == "__main__":
    rospy.init_node("tf_tree_complete")
    rostest.rosrun("bullet_sim_bringup", "tf_tree_complete", TfTreeComplete, sys.argv)
