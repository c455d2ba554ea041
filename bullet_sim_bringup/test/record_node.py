#!/usr/bin/env python3
"""rostest node: the simulator records the wheelchair it drives into ~record's bag; after reset_simulation, the
closed bag holds its topics in sim time (ground truth, the latched /tf_static, /tf, sensors and cmd_vel) and no
/clock, and the recording goes on in FILE_1.bag."""
import os
import sys
import time
import unittest

import rosbag
import rospy
import rostest
from geometry_msgs.msg import Twist
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import LaserScan
from std_srvs.srv import Empty

from bringup_support import Collector


def under_ros_home(path):
    return os.path.join(os.environ.get("ROS_HOME", os.path.expanduser("~/.ros")), path)


class RecordNode(unittest.TestCase):
    def test_the_closed_bag_holds_the_run_in_sim_time(self):
        bag_path = under_ros_home(rospy.get_param("~bag"))
        clock = Collector("/clock", Clock)
        Collector("/scan", LaserScan).wait_for(lambda scans: scans, 30, "the wheelchair's first scan")
        commands = rospy.Publisher("/cmd_vel", Twist, queue_size=1)
        command = Twist()
        command.linear.x = 0.4
        command.angular.z = 0.3
        deadline = time.monotonic() + 30
        while not clock.messages or clock.messages[-1].clock.to_sec() < 3.0:  # commands re-sent as rostopic pub -r 10 does
            self.assertLess(time.monotonic(), deadline, "sim time did not reach 3 s")
            commands.publish(command)
            time.sleep(0.1)
        rospy.wait_for_service("/gazebo/reset_simulation", 10)
        rospy.ServiceProxy("/gazebo/reset_simulation", Empty)()
        self.assertTrue(os.path.exists(bag_path), "reset_simulation closes " + bag_path)
        self.assertFalse(os.path.exists(bag_path + ".active"))
        following = bag_path[:-4] + "_1.bag.active"
        self.assertTrue(os.path.exists(following), "and recording goes on in " + following)

        with rosbag.Bag(bag_path) as bag:
            info = bag.get_type_and_topic_info().topics
            for topic in ["/ground_truth", "/tf", "/tf_static", "/scan", "/odom", "/joint_states", "/cmd_vel"]:
                self.assertIn(topic, info)
            self.assertNotIn("/clock", info, "rosbag play --clock makes /clock from the bag's time")
            duration = bag.get_end_time() - bag.get_start_time()
            self.assertGreater(duration, 2.5)
            self.assertLess(bag.get_end_time(), 60, "bag time is sim time")
            self.assertAlmostEqual(info["/ground_truth"].message_count / duration, 50, delta=3)
            self.assertAlmostEqual(info["/scan"].message_count / duration, 5.5, delta=1)
            headers = {}
            for topic, message, stamp, header in bag.read_messages(return_connection_header=True):
                headers.setdefault(topic, header)
                if topic in ("/scan", "/odom", "/ground_truth", "/joint_states"):
                    self.assertEqual(message.header.stamp, stamp, topic + ": stamped when recorded")
                if topic == "/ground_truth":
                    self.assertEqual(message.header.frame_id, "world")
                    self.assertEqual(message.child_frame_id, "base_footprint")
                if topic == "/cmd_vel":
                    self.assertAlmostEqual(message.linear.x, 0.4)
            self.assertEqual(headers["/tf_static"].get("latching"), b"1")  # rosbag reads header values as bytes
            for topic, header in headers.items():
                self.assertNotIn("callerid", header, topic)
        os.remove(bag_path)


if __name__ == "__main__":
    rospy.init_node("record_node")
    rostest.rosrun("bullet_sim_bringup", "record_node", RecordNode, sys.argv)
