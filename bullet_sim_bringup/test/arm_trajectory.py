#!/usr/bin/env python3
"""rostest node: the arm's JointTrajectoryController as MoveIt and scripts use it. A three-waypoint goal through
follow_joint_trajectory reaches each waypoint within the goal tolerance at its time with the state's error inside
the path tolerance; query_state samples the same trajectory; the post (arm_post.world) aborts a goal with
PATH_TOLERANCE_VIOLATED and the shoulder's limit one with GOAL_TOLERANCE_VIOLATED; a new goal replaces the running
one mid-way (which ends PREEMPTED) and leads on from where it was; a trajectory on the command topic moves it."""
import math
import unittest

import actionlib
import rospy
import rostest
from actionlib_msgs.msg import GoalStatus
from control_msgs.msg import (FollowJointTrajectoryAction, FollowJointTrajectoryGoal, FollowJointTrajectoryResult,
                              JointTolerance, JointTrajectoryControllerState)
from control_msgs.srv import QueryTrajectoryState
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

from bringup_support import Collector
from rover_support import wait_until

CONTROLLER = "/arm/arm_controller"
JOINTS = ["shoulder", "wrist"]
GOAL_TOLERANCE = 0.01  # the constraints in arm_trajectory.test
PATH_TOLERANCE = 0.05
STEP = 0.001  # arm_post.world's max_step_size


def trajectory(points, stamp=None):
    """A JointTrajectory through `points`: (time_from_start, positions[, velocities])."""
    message = JointTrajectory()
    message.joint_names = JOINTS
    if stamp is not None:
        message.header.stamp = rospy.Time.from_sec(stamp)
    for point in points:
        waypoint = JointTrajectoryPoint(positions=point[1], time_from_start=rospy.Duration.from_sec(point[0]))
        if len(point) > 2:
            waypoint.velocities = point[2]
        message.points.append(waypoint)
    return message


def state_at(states, t):
    """The desired and actual positions at time t: the state stamped t, or, when the publisher's queue dropped
    it on a loaded machine, the line between its neighbours (at most 5 steps apart: a knot's curvature then
    moves it by less than 1e-4)."""
    stamp = lambda s: s.header.stamp.to_sec()
    before = max((s for s in states if stamp(s) <= t + STEP / 2), key=stamp)
    after = min((s for s in states if stamp(s) >= t - STEP / 2), key=stamp)
    assert stamp(after) - stamp(before) <= 5 * STEP, "no state within 5 steps of %.3f s" % t
    w = 0.0 if after is before else (t - stamp(before)) / (stamp(after) - stamp(before))
    mix = lambda a, b: [x + w * (y - x) for x, y in zip(a, b)]
    return (mix(before.desired.positions, after.desired.positions),
            mix(before.actual.positions, after.actual.positions))


class ArmTrajectory(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.states = Collector(CONTROLLER + "/state", JointTrajectoryControllerState)
        cls.client = actionlib.SimpleActionClient(CONTROLLER + "/follow_joint_trajectory",
                                                  FollowJointTrajectoryAction)
        if not cls.client.wait_for_server(rospy.Duration(60)):
            raise AssertionError("no follow_joint_trajectory action server within 60 s")
        cls.states.wait_for(lambda m: m, 60, "the controller's state")

    def follow(self, goal, timeout=30):
        """Sends `goal` and waits for its end; its state and result."""
        self.client.send_goal(goal)
        self.assertTrue(self.client.wait_for_result(rospy.Duration(timeout)), "the goal did not end")
        return self.client.get_state(), self.client.get_result()

    def go_home(self):
        """Stops the arm where it is, then brings it home. After an abort the trajectory runs on beyond where the
        arm could follow (as in ros_controllers), and a new one would lead on from there; a stop (an empty
        trajectory) holds where the joints are."""
        stop = trajectory([])
        state, _ = self.follow(FollowJointTrajectoryGoal(trajectory=stop))
        self.assertEqual(state, GoalStatus.SUCCEEDED)
        state, _ = self.follow(FollowJointTrajectoryGoal(trajectory=trajectory([(1.0, [0.0, 0.0])])))
        self.assertEqual(state, GoalStatus.SUCCEEDED)

    def test_three_waypoints_through_the_action(self):
        self.go_home()
        # Velocities through the middle waypoint: a cubic there, lines elsewhere. It starts 0.5 s ahead, on a step.
        points = [(1.0, [0.6, -0.8], [0.6, 0.0]), (2.0, [1.2, 0.4], [0.0, 0.8]), (3.0, [0.3, 0.0], [0.0, 0.0])]
        start = round((rospy.get_time() + 0.5) / STEP) * STEP
        self.client.send_goal(FollowJointTrajectoryGoal(trajectory=trajectory(points, start)))
        wait_until(lambda: self.client.get_state() == GoalStatus.ACTIVE, 30, "the goal to be accepted")
        query = rospy.ServiceProxy(CONTROLLER + "/query_state", QueryTrajectoryState)
        sampled = query(rospy.Time.from_sec(start + 2.0))
        self.assertEqual(list(sampled.name), JOINTS)
        for j in range(2):
            self.assertAlmostEqual(sampled.position[j], points[1][1][j], places=6)
            self.assertAlmostEqual(sampled.velocity[j], points[1][2][j], places=6)
        self.assertTrue(self.client.wait_for_result(rospy.Duration(30)))
        self.assertEqual(self.client.get_state(), GoalStatus.SUCCEEDED)
        self.assertEqual(self.client.get_result().error_code, FollowJointTrajectoryResult.SUCCESSFUL)
        # The result and the state come on separate connections: wait for the states past the last waypoint.
        end = start + 3.0 + 5 * STEP
        self.states.wait_for(lambda ms: ms[-1].header.stamp.to_sec() >= end, 30, "the states past the last waypoint")
        states = [s for s in self.states.messages if start <= s.header.stamp.to_sec() <= end]
        self.assertGreater(len(states), 1000, "the state at 1000 Hz along the trajectory")
        worst = max(abs(e) for s in states for e in s.error.positions)
        self.assertLess(worst, PATH_TOLERANCE, "the largest position error on the way")
        for time_from_start, positions, _ in points:
            desired, actual = state_at(states, start + time_from_start)
            for j in range(2):
                self.assertAlmostEqual(desired[j], positions[j], delta=1e-4)
                self.assertLess(abs(actual[j] - positions[j]), GOAL_TOLERANCE,
                                "%s at waypoint %.0f s" % (JOINTS[j], time_from_start))

    def test_what_cannot_be_followed_aborts(self):
        self.go_home()
        # The post stops the straight arm at pi/2 - asin(0.07 / 0.65) = 1.463 rad on its way to 2.
        state, result = self.follow(FollowJointTrajectoryGoal(trajectory=trajectory([(2.0, [2.0, 0.0])])))
        self.assertEqual(state, GoalStatus.ABORTED)
        self.assertEqual(result.error_code, FollowJointTrajectoryResult.PATH_TOLERANCE_VIOLATED)
        self.assertAlmostEqual(self.states.messages[-1].actual.positions[0], math.pi / 2 - math.asin(0.07 / 0.65),
                               delta=0.01)
        self.go_home()
        # Beyond the shoulder's 3 rad limit, with its path tolerance lifted: the goal is missed past goal_time.
        goal = FollowJointTrajectoryGoal(trajectory=trajectory([(1.0, [-3.4, 0.0])]))
        goal.path_tolerance = [JointTolerance(name="shoulder", position=-1)]
        state, result = self.follow(goal)
        self.assertEqual(state, GoalStatus.ABORTED)
        self.assertEqual(result.error_code, FollowJointTrajectoryResult.GOAL_TOLERANCE_VIOLATED)
        self.assertIn("shoulder goal error", result.error_string)

    def test_a_new_goal_replaces_the_running_one_mid_way(self):
        self.go_home()
        first = actionlib.SimpleActionClient(CONTROLLER + "/follow_joint_trajectory", FollowJointTrajectoryAction)
        self.assertTrue(first.wait_for_server(rospy.Duration(30)))
        first.send_goal(FollowJointTrajectoryGoal(trajectory=trajectory([(2.0, [1.2, 0.0])])))
        self.states.wait_for(lambda m: m[-1].desired.positions[0] > 0.6, 30, "the shoulder half way")
        replaced = len(self.states.messages)
        state, result = self.follow(FollowJointTrajectoryGoal(trajectory=trajectory([(1.0, [-0.6, 0.5])])))
        self.assertEqual(state, GoalStatus.SUCCEEDED)
        self.assertTrue(first.wait_for_result(rospy.Duration(10)))
        self.assertEqual(first.get_state(), GoalStatus.PREEMPTED)
        final = self.states.messages[-1].actual.positions
        self.assertAlmostEqual(final[0], -0.6, delta=GOAL_TOLERANCE)
        self.assertAlmostEqual(final[1], 0.5, delta=GOAL_TOLERANCE)
        # It leads on from where the first one was: the desired shoulder never jumps (0.01 rad in a 1 ms step would
        # be 10 rad/s); it moves at about 1.3 rad/s at most, from a little past 0.6 to -0.6 in 1 s.
        states = self.states.messages[replaced - 100:]
        speeds = [abs(b.desired.positions[0] - a.desired.positions[0]) /
                  (b.header.stamp - a.header.stamp).to_sec() for a, b in zip(states, states[1:])]
        self.assertLess(max(speeds), 2.0)

    def test_a_trajectory_on_the_command_topic_moves_it(self):
        self.go_home()
        command = rospy.Publisher(CONTROLLER + "/command", JointTrajectory, queue_size=1, latch=True)
        command.publish(trajectory([(0.5, [-0.4, 0.7])]))
        self.states.wait_for(lambda m: abs(m[-1].actual.positions[0] + 0.4) < GOAL_TOLERANCE and
                             abs(m[-1].actual.positions[1] - 0.7) < GOAL_TOLERANCE, 30, "the arm at the command")
        command.unregister()


if __name__ == "__main__":
    rospy.init_node("arm_trajectory")
    rostest.rosrun("bullet_sim_bringup", "arm_trajectory", ArmTrajectory)
