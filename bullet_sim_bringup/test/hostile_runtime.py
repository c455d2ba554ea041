#!/usr/bin/env python3
"""rostest node: hostile requests to the live simulator through what only ROS carries, one row each with the
refusal it must get: gazebo_msgs' services and the set_model_state topic (orientations as quaternions, which the
in-process test cannot send), the controller manager's services, the arm's group controller's command topic and
follow_joint_trajectory goals. After every row the clock goes on, the wheelchair drives, and no model state, link
state or joint state published since is non-finite. Last, the arm is deleted and respawned through
spawn_urdf_model with its robot_namespace (an RL reset), and its controllers load from that namespace's
parameters and run again."""
import math
import time
import unittest

import actionlib
import rospkg
import rospy
import rostest
from control_msgs.msg import FollowJointTrajectoryAction, FollowJointTrajectoryGoal, FollowJointTrajectoryResult
from controller_manager_msgs.srv import ListControllers, LoadController, SwitchController
from gazebo_msgs.msg import LinkState, LinkStates, ModelState, ModelStates
from gazebo_msgs.srv import (ApplyBodyWrench, ApplyJointEffort, DeleteModel, GetModelState, SetJointProperties,
                             SetLinkState, SetModelConfiguration, SetModelState, SetPhysicsProperties, SpawnModel)
from gazebo_msgs.msg import ODEJointProperties, ODEPhysics
from geometry_msgs.msg import Point, Pose, Quaternion, Twist, Vector3, Wrench
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import JointState
from std_msgs.msg import Float64MultiArray
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

from bringup_support import Collector

NAN = float("nan")
INF = float("inf")


def pose(x=0.0, y=0.0, z=0.0, q=(0.0, 0.0, 0.0, 1.0)):
    return Pose(Point(x, y, z), Quaternion(*q))


def finite(*values):
    return all(math.isfinite(v) for v in values)


def finite_pose(p):
    return finite(p.position.x, p.position.y, p.position.z, p.orientation.x, p.orientation.y, p.orientation.z,
                  p.orientation.w)


def finite_twist(t):
    return finite(t.linear.x, t.linear.y, t.linear.z, t.angular.x, t.angular.y, t.angular.z)


def wall_wait(condition, timeout):
    """Whether `condition()` (which may wait a little in sim time, which runs fast here) held within `timeout`
    wall seconds."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if condition():
            return True
    return False


def service(name, service_type):
    rospy.wait_for_service(name, timeout=60)
    return rospy.ServiceProxy(name, service_type)


class NonFiniteWatch:
    """Checks every message of a topic as it arrives (kept: only the first that is not finite); a short queue,
    since the states come every step and sim time runs fast here."""

    def __init__(self, topic, message_type, is_finite):
        self.count = 0
        self.bad = None
        self._is_finite = is_finite
        self._subscriber = rospy.Subscriber(topic, message_type, self._check, queue_size=10)

    def _check(self, message):
        self.count += 1
        if self.bad is None and not self._is_finite(message):
            self.bad = message


class HostileRuntime(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("hostile_runtime")
        cls.clock = Collector("/clock", Clock)
        cls.odometry = Collector("/odom", Odometry)
        cls.watches = [
            NonFiniteWatch("/gazebo/model_states", ModelStates,
                           lambda m: all(map(finite_pose, m.pose)) and all(map(finite_twist, m.twist))),
            NonFiniteWatch("/gazebo/link_states", LinkStates, lambda m: all(map(finite_pose, m.pose))),
            NonFiniteWatch("/arm/joint_states", JointState, lambda m: finite(*m.position, *m.velocity))]
        cls.cmd_vel = rospy.Publisher("/cmd_vel", Twist, queue_size=1)
        cls.group = rospy.Publisher("/arm/group_controller/command", Float64MultiArray, queue_size=10)
        cls.model_state_topic = rospy.Publisher("/gazebo/set_model_state", ModelState, queue_size=10)
        cls.gazebo = {name: service("/gazebo/" + name, kind) for name, kind in [
            ("set_model_state", SetModelState), ("get_model_state", GetModelState), ("set_link_state", SetLinkState),
            ("spawn_urdf_model", SpawnModel), ("spawn_sdf_model", SpawnModel), ("delete_model", DeleteModel),
            ("apply_body_wrench", ApplyBodyWrench), ("apply_joint_effort", ApplyJointEffort),
            ("set_physics_properties", SetPhysicsProperties), ("set_model_configuration", SetModelConfiguration),
            ("set_joint_properties", SetJointProperties)]}
        if not wall_wait(lambda: cls.cmd_vel.get_num_connections() > 0, 30):
            raise AssertionError("nobody subscribes to /cmd_vel")
        cls.wait_for_controller("group_controller", "running")
        cls.wait_for_controller("arm_controller", "initialized")

    @classmethod
    def wait_for_controller(cls, name, state, timeout=60):
        list_controllers = service("/arm/controller_manager/list_controllers", ListControllers)
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            if any(c.name == name and c.state == state for c in list_controllers().controller):
                return
            time.sleep(0.1)
        raise AssertionError("controller %s never became %s" % (name, state))

    def expect_alive(self):
        """The clock goes on, the wheelchair drives 0.5 s of sim time ahead, and all published since is finite."""
        start = self.odometry.wait_for(lambda m: m, 30, "odometry")[-1]
        t0 = start.header.stamp.to_sec()
        deadline = time.monotonic() + 30
        sent = 0  # sim time runs fast here: at least 20 commands, whatever sim time they take
        while self.odometry.messages[-1].header.stamp.to_sec() < t0 + 0.5 or sent < 20:
            sent += 1
            self.assertLess(time.monotonic(), deadline, "the clock stopped")
            self.cmd_vel.publish(Twist(Vector3(0.5, 0, 0), Vector3()))
            time.sleep(0.02)
        self.cmd_vel.publish(Twist())
        end = self.odometry.messages[-1]
        moved = math.hypot(end.pose.pose.position.x - start.pose.pose.position.x,
                           end.pose.pose.position.y - start.pose.pose.position.y)
        self.assertGreater(moved, 0.02, "the wheelchair did not drive")
        for watch in self.watches:
            self.assertIsNone(watch.bad, "a message not finite on %s" % watch._subscriber.name)
            self.assertGreater(watch.count, 0, "nothing on %s" % watch._subscriber.name)

    def refusal_problem(self, name, request_args, expected):
        """None when `name` refuses the request with `expected` in its status_message and all is well after."""
        answer = self.gazebo[name](*request_args)
        self.expect_alive()
        if answer.success or expected not in answer.status_message:
            return "%s%r: success %s, %r (expected %r)" % (name, request_args, answer.success,
                                                           answer.status_message, expected)
        return None

    def test_1_gazebo_msgs_requests_are_refused_with_the_field(self):
        rows = [
            ("set_model_state", [ModelState("wheelchair", pose(q=(NAN, 0, 0, 1)), Twist(), "")],
             "pose.orientation (x y z w) [nan 0 0 1] is not finite"),
            ("set_model_state", [ModelState("wheelchair", pose(q=(1e200, 1e200, 1e200, 1e200)), Twist(), "")],
             "is no rotation: its norm [2e+200]"),
            ("set_model_state", [ModelState("wheelchair", pose(q=(1e-200, 1e-200, 1e-200, 1e-200)), Twist(), "")],
             "is no rotation: its norm [2e-200]"),
            ("set_model_state", [ModelState("wheelchair", pose(), Twist(Vector3(0, NAN, 0), Vector3()), "")],
             "twist.linear.y [nan] is not finite"),
            ("set_link_state", [LinkState("arm::base_link", pose(q=(0, INF, 0, 1)), Twist(), "")],
             "pose.orientation (x y z w) [0 inf 0 1] is not finite"),
            ("spawn_urdf_model", ["box", "<robot name='box'/>", "", pose(q=(NAN, 0, 0, 1)), ""],
             "initial_pose.orientation (x y z w) [nan 0 0 1] is not finite"),
            ("spawn_urdf_model", ["box", "<robot name='box'/>", "", pose(x=NAN), ""],
             "initial_pose.position.x [nan] is not finite"),
            ("spawn_sdf_model", ["box", "<sdf version='1.6'/>", "", pose(q=(0, 0, 1e200, 1e200)), ""],
             "is no rotation"),
            ("apply_body_wrench", ["wheelchair", "", Point(), Wrench(Vector3(1, NAN, 0), Vector3()), rospy.Time(),
                                   rospy.Duration(1)], "wrench.force.y [nan] is not finite"),
            ("apply_body_wrench", ["wheelchair", "", Point(0, 0, INF), Wrench(), rospy.Time(), rospy.Duration(1)],
             "reference_point.z [inf] is not a finite number"),
            ("apply_joint_effort", ["arm::wrist", NAN, rospy.Time(), rospy.Duration(1)], "effort [nan] is not finite"),
            ("set_model_configuration", ["arm", "", ["shoulder"], [NAN]], "the position of [shoulder] [nan]"),
            ("set_joint_properties", ["arm::wrist", ODEJointProperties(vel=[NAN], fmax=[1])], "vel [nan] is not finite"),
            ("set_physics_properties", [0.001, 1e-10, Vector3(0, 0, -9.81), ODEPhysics()],
             "max_update_rate [1e-10] must be 0 (as fast as possible) or at least"),
            ("set_physics_properties", [NAN, 0, Vector3(0, 0, -9.81), ODEPhysics()], "time_step [nan] is not finite"),
            ("set_physics_properties", [0.001, 0, Vector3(0, NAN, -9.81), ODEPhysics()],
             "gravity.y [nan] is not finite"),
        ]
        problems = [self.refusal_problem(name, args, expected) for name, args, expected in rows]
        self.assertEqual([p for p in problems if p], [])

    def test_2_a_bad_set_model_state_message_changes_nothing(self):
        before = self.gazebo["get_model_state"]("wheelchair", "").pose
        for q in [(NAN, 0, 0, 1), (1e200, 0, 0, 1e200), (1e-200, 0, 0, 0)]:
            self.model_state_topic.publish(ModelState("wheelchair", pose(x=before.position.x + 5, q=q), Twist(), ""))
        t = self.odometry.messages[-1].header.stamp.to_sec()
        self.odometry.wait_for(lambda m: m[-1].header.stamp.to_sec() > t + 0.5, 30, "0.5 s of sim time")
        after = self.gazebo["get_model_state"]("wheelchair", "").pose
        self.assertLess(abs(after.position.x - before.position.x), 1.0, "a refused teleport moved the wheelchair")
        self.expect_alive()

    def test_3_commands_that_are_not_finite_are_dropped_and_the_arm_switches_back(self):
        for data in [[NAN, 0.0], [0.0, NAN], [1e308, -1e308], [INF, -INF]]:
            self.group.publish(Float64MultiArray(data=data))
            self.expect_alive()
        switch = service("/arm/controller_manager/switch_controller", SwitchController)
        self.assertFalse(switch(["ghost_controller"], [], 2, False, 0.0).ok)
        self.assertFalse(service("/arm/controller_manager/load_controller", LoadController)("ghost_controller").ok)
        self.assertTrue(switch(["arm_controller"], ["group_controller"], 2, False, 0.0).ok)
        self.expect_alive()

    def test_3a_hostile_trajectory_goals_are_rejected_with_the_reason(self):
        # After test_3 the trajectory controller runs. Each goal is rejected at once, naming what is wrong.
        client = actionlib.SimpleActionClient("/arm/arm_controller/follow_joint_trajectory",
                                              FollowJointTrajectoryAction)
        self.assertTrue(client.wait_for_server(rospy.Duration(60)), "no follow_joint_trajectory server")
        invalid_goal = FollowJointTrajectoryResult.INVALID_GOAL
        invalid_joints = FollowJointTrajectoryResult.INVALID_JOINTS
        rows = [
            (["shoulder", "wrist"], [(1.0, [NAN, 0.0], [])], invalid_goal,
             "points[0].positions[0] [nan] is not finite"),
            (["shoulder", "wrist"], [(1.0, [0.0, 0.0], [INF, 0.0])], invalid_goal,
             "points[0].velocities[0] [inf] is not finite"),
            (["shoulder", "wrist"], [(1.0, [0.0], [])], invalid_goal, "has 1 positions for 2 joints"),
            (["shoulder", "elbow"], [(1.0, [0.0, 0.0], [])], invalid_joints, "joint [elbow] is not one of"),
            (["shoulder", "wrist"], [(1.0, [0.0, 0.0], []), (1.0, [0.1, 0.0], [])], invalid_goal,
             "time_from_start must increase strictly"),
        ]
        problems = []
        for joints, points, code, expected in rows:
            trajectory = JointTrajectory(joint_names=joints, points=[
                JointTrajectoryPoint(positions=p, velocities=v, time_from_start=rospy.Duration.from_sec(t))
                for t, p, v in points])
            client.send_goal(FollowJointTrajectoryGoal(trajectory=trajectory))
            self.assertTrue(client.wait_for_result(rospy.Duration(60)), "no result for %r" % expected)
            result = client.get_result()
            if result.error_code != code or expected not in result.error_string:
                problems.append("%r: error %d %r (expected %d, %r)" % (points, result.error_code,
                                                                        result.error_string, code, expected))
            self.expect_alive()
        self.assertEqual(problems, [])

    def test_4_the_arm_respawned_in_its_namespace_gets_its_controllers_again(self):
        description = rospy.get_param("/arm_description")
        self.assertTrue(self.gazebo["delete_model"]("arm").success)
        # Under another model name, so that only the namespace given can lead it to /arm's parameters.
        answer = self.gazebo["spawn_urdf_model"]("arm_again", description, "/arm", pose(y=-4), "")
        self.assertTrue(answer.success, answer.status_message)
        load = service("/arm/controller_manager/load_controller", LoadController)
        for name in ["joint_state_controller", "arm_controller"]:
            self.assertTrue(load(name).ok, "load_controller %s after the respawn" % name)
        switch = service("/arm/controller_manager/switch_controller", SwitchController)
        self.assertTrue(switch(["joint_state_controller", "arm_controller"], [], 2, False, 0.0).ok)
        self.wait_for_controller("arm_controller", "running")
        self.expect_alive()

    def test_5_a_drive_that_cannot_publish_its_odometry_is_spawned_with_the_reason(self):
        # As in Gazebo, the robot comes and drives without its odometry; the answer says why, not only /rosout.
        path = rospkg.RosPack().get_path("bullet_sim") + "/test/fixtures/doctor/clean_two_wheeler.urdf"
        with open(path) as file:
            urdf = file.read().replace("</leftJoint>", "</leftJoint><odometryTopic>/clock</odometryTopic>")
        answer = self.gazebo["spawn_urdf_model"]("odometry_on_clock", urdf, "/stray", pose(y=4, z=0.06), "")
        self.assertTrue(answer.success, answer.status_message)
        self.assertIn("cannot publish nav_msgs/Odometry on [/clock]: it carries rosgraph_msgs/Clock",
                      answer.status_message)
        self.expect_alive()
        self.assertTrue(self.gazebo["delete_model"]("odometry_on_clock").success)


if __name__ == "__main__":
    rostest.rosrun("bullet_sim_bringup", "hostile_runtime", HostileRuntime)
