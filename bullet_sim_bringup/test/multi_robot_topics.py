#!/usr/bin/env python3
"""rostest node: in multi_robot.launch each robot publishes odom and scan in its own namespace with frames that
carry its prefix, tf reaches each robot's lidar from its odom, and nothing is published un-namespaced. ~count
is the launch's count (0: its three robots robot1 to robot3; N: its fleet, robot1 to robotN); with
~real_time_factor, the launch's real_time_factor, which the simulator must have been given; with
~publish_frequency, the launch's, which every robot's robot_state_publisher must have been given."""
import sys
import time
import unittest

import rosgraph
import rospy
import rostest
import tf2_ros
from nav_msgs.msg import Odometry
from sensor_msgs.msg import LaserScan

from bringup_support import Collector, ray_sensor

class MultiRobotTopics(unittest.TestCase):
    def test_each_robot_has_its_own_topics_and_frames(self):
        buffer = tf2_ros.Buffer()
        tf2_ros.TransformListener(buffer)
        count = rospy.get_param("~count", 0)
        robots = ["robot%d" % (i + 1) for i in range(count or 3)]
        for ns in robots:
            odom = Collector("/%s/odom" % ns, Odometry).wait_for(lambda m: m, 90, "/%s/odom" % ns)[0]
            self.assertEqual(odom.header.frame_id, ns + "/odom")
            self.assertEqual(odom.child_frame_id, ns + "/base_footprint")
            scan = Collector("/%s/scan" % ns, LaserScan).wait_for(lambda m: m, 90, "/%s/scan" % ns)[0]
            description = rospy.get_param("/%s/robot_description" % ns if count == 0 else "/robot_description")
            lidar_link = ray_sensor(description).findtext("plugin/frameName")
            self.assertEqual(scan.header.frame_id, ns + "/" + lidar_link)
            self.assertTrue(buffer.can_transform(ns + "/odom", scan.header.frame_id, rospy.Time(0), rospy.Duration(30)),
                            "no tf from %s/odom to %s" % (ns, scan.header.frame_id))
        if rospy.has_param("~real_time_factor"):
            self.assertEqual(rospy.get_param("/gazebo/real_time_factor"), rospy.get_param("~real_time_factor"))
        if rospy.has_param("~publish_frequency"):
            for ns in robots:
                self.assertEqual(rospy.get_param("/%s/robot_state_publisher/publish_frequency" % ns),
                                 rospy.get_param("~publish_frequency"))
        publishers, _, _ = rosgraph.Master("/multi_robot_topics").getSystemState()
        for topic in ("/odom", "/scan", "/joint_states", "/cmd_vel"):
            self.assertNotIn(topic, [t for t, _ in publishers], "%s is not namespaced" % topic)


if __name__ == "__main__":
    rospy.init_node("multi_robot_topics")
    rostest.rosrun("bullet_sim_bringup", "multi_robot_topics", MultiRobotTopics, sys.argv)
