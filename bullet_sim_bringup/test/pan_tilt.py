#!/usr/bin/env python3
"""rostest node: the Yahboom pan/tilt through ros_control, as its launch file starts it. A goal on
/pan_tilt_controller/follow_joint_trajectory succeeds, and /joint_states and the camera's tf frame then show the
angles it asked for."""
import math
import unittest

import actionlib
import rospy
import rostest
import tf2_ros
from actionlib_msgs.msg import GoalStatus
from control_msgs.msg import FollowJointTrajectoryAction, FollowJointTrajectoryGoal
from sensor_msgs.msg import JointState
from trajectory_msgs.msg import JointTrajectoryPoint

from bringup_support import Collector

PAN, TILT = 0.6, 0.4


class PanTilt(unittest.TestCase):
    def test_a_goal_turns_the_camera(self):
        client = actionlib.SimpleActionClient("/pan_tilt_controller/follow_joint_trajectory",
                                              FollowJointTrajectoryAction)
        self.assertTrue(client.wait_for_server(rospy.Duration(60)), "no follow_joint_trajectory server")
        goal = FollowJointTrajectoryGoal()
        goal.trajectory.joint_names = ["jq1_Joint", "jq2_Joint"]
        goal.trajectory.points = [JointTrajectoryPoint(positions=[PAN, TILT], time_from_start=rospy.Duration(1))]
        client.send_goal(goal)
        self.assertTrue(client.wait_for_result(rospy.Duration(30)), "the goal did not end")
        self.assertEqual(client.get_state(), GoalStatus.SUCCEEDED)
        states = Collector("/joint_states", JointState)
        last = states.wait_for(lambda m: m, 30, "joint_states")[-1]
        angles = dict(zip(last.name, last.position))
        self.assertAlmostEqual(angles["jq1_Joint"], PAN, delta=0.01)
        self.assertAlmostEqual(angles["jq2_Joint"], TILT, delta=0.01)
        # The camera's frame turned with them: its x axis points PAN to the left and TILT up.
        buffer = tf2_ros.Buffer()
        tf2_ros.TransformListener(buffer)
        q = buffer.lookup_transform("base_link", "jq2_Link", rospy.Time(0), rospy.Duration(30)).transform.rotation
        x_axis = (1 - 2 * (q.y * q.y + q.z * q.z), 2 * (q.x * q.y + q.w * q.z), 2 * (q.x * q.z - q.w * q.y))
        self.assertAlmostEqual(math.atan2(x_axis[1], x_axis[0]), PAN, delta=0.02)
        self.assertAlmostEqual(math.asin(x_axis[2]), TILT, delta=0.02)


if __name__ == "__main__":
    rospy.init_node("pan_tilt")
    rostest.rosrun("bullet_sim_bringup", "pan_tilt", PanTilt)
