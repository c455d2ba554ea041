#!/usr/bin/env python3
"""Frame names of namespaced robots follow Noetic's gazebo_plugins: tf::resolve(tf_prefix, frame), where the
drives, lasers and cameras search the tf_prefix parameter up from the robot's namespace, the rangers (and p3d,
bumpers, block lasers) read <namespace>/tf_prefix only, and the IMUs take none; the namespace alone prefixes
nothing. Two robots publishing the same frame on /tf draw one warning naming both and the tf_prefix to set."""
import subprocess
import unittest

import rospy
import rostest
from gazebo_msgs.srv import SpawnModel
from geometry_msgs.msg import Point, Pose, Quaternion
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Log
from sensor_msgs.msg import Imu, Range



def robot_xml():
    path = subprocess.check_output(["rospack", "find", "bullet_sim"], text=True).strip()
    return subprocess.check_output(
        ["xacro", path + "/test/fixtures/robots/multi_sensor_robot.urdf.xacro", "drive:=planar"], text=True)


class TfPrefixRule(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("tf_prefix_rule")
        cls.warnings = []
        rosout = rospy.Subscriber("/rosout", Log, lambda log: cls.warnings.append(log.msg), queue_size=100)
        rospy.wait_for_service("/gazebo/spawn_urdf_model", timeout=60)
        deadline = rospy.Time.now() + rospy.Duration(30)  # hear the simulator's log before it warns
        while rosout.get_num_connections() == 0 and rospy.Time.now() < deadline:
            rospy.sleep(0.05)
        spawn = rospy.ServiceProxy("/gazebo/spawn_urdf_model", SpawnModel)
        xml = robot_xml()
        rospy.set_param("/r1/tf_prefix", "r1")         # in the robot's own namespace: every rule finds it
        rospy.set_param("/r2/tf_prefix", "r2")         # one level up from /r2/inner: only a search finds it
        for name, ns, x in [("r1", "/r1", 0.0), ("r2", "/r2/inner", 1.5), ("r3", "/r3", -1.5), ("r4", "/r4", 3.0)]:
            pose = Pose(position=Point(x, 0, 0), orientation=Quaternion(0, 0, 0, 1))
            reply = spawn(name, xml, ns, pose, "world")
            assert reply.success, reply.status_message

    def frames(self, ns):
        odom = rospy.wait_for_message(ns + "/odom", Odometry, timeout=30)
        ranged = rospy.wait_for_message(ns + "/range/ir", Range, timeout=30)
        imu = rospy.wait_for_message(ns + "/imu/data", Imu, timeout=30)
        return odom.header.frame_id, odom.child_frame_id, ranged.header.frame_id, imu.header.frame_id

    def test_tf_prefix_in_the_namespace_prefixes_all_but_the_imu(self):
        self.assertEqual(self.frames("/r1"), ("r1/odom", "r1/base_footprint", "r1/ir_link", "imu_link"))

    def test_a_tf_prefix_above_is_found_by_a_search_only(self):
        self.assertEqual(self.frames("/r2/inner"), ("r2/odom", "r2/base_footprint", "ir_link", "imu_link"))

    def test_the_namespace_alone_prefixes_nothing(self):
        self.assertEqual(self.frames("/r3"), ("odom", "base_footprint", "ir_link", "imu_link"))

    def test_two_robots_publishing_one_frame_draw_one_warning(self):
        deadline = rospy.Time.now() + rospy.Duration(30)
        wanted = lambda msg: "both publish frame [base_footprint] on /tf" in msg and "tf_prefix" in msg
        while not any(map(wanted, self.warnings)) and rospy.Time.now() < deadline:
            rospy.sleep(0.1)
        found = [msg for msg in self.warnings if wanted(msg)]
        self.assertEqual(len(found), 1, found)
        self.assertIn("[r3]", found[0])
        self.assertIn("[r4]", found[0])


if __name__ == "__main__":
    rostest.rosrun("bullet_sim_bringup", "tf_prefix_rule", TfPrefixRule)
