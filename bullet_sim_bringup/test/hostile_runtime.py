#!/usr/bin/env python3
"""rostest node: a table of hostile requests (hostile_rows.py) to the live simulator with three robots, one row
each through one interface: gazebo_msgs' services and topics, both controller managers' services,
follow_joint_trajectory, the controllers' command topics, and the scenario and sweep tools run with bad
arguments. Each row names the piece of the answer it must get: a service's status_message (which a refusal
also logs on /rosout, as Gazebo's do), the reason a controller manager or a topic's subscriber logs on /rosout,
an action's error_string, a tool's one line on stderr with exit code 2. After every row the clock goes on, the
wheelchair (always told to drive a circle) drives on, and no message published since is non-finite. The table
is printed as it runs. Then the arm is deleted and respawned by spawn_urdf_model with its robot_namespace (an
RL reset) and its controllers load again."""
import concurrent.futures
import math
import shutil
import subprocess
import tempfile
import threading
import time
import unittest

import actionlib
import rospkg
import rospy
import rostest
from control_msgs.msg import FollowJointTrajectoryAction, FollowJointTrajectoryGoal
from controller_manager_msgs.srv import (ListControllers, ListControllerTypes, LoadController,
                                         ReloadControllerLibraries, SwitchController, UnloadController)
from gazebo_msgs.msg import LinkState, LinkStates, ModelState, ModelStates
from gazebo_msgs import srv as gazebo_srv
from geometry_msgs.msg import Twist, Vector3
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Log
from sensor_msgs.msg import JointState
from std_msgs.msg import Float64MultiArray, String
from trajectory_msgs.msg import JointTrajectory

import hostile_rows
from hostile_rows import Answer, pose

ROW_TIMEOUT = 10.0  # [wall s] for a row's answer, and for the world to go on after it
LOG_WAIT = 3.0  # [wall s] for a reason to reach /rosout
ALIVE_SIM_SECONDS = 0.05  # [sim s] the clock must advance after each row, the wheelchair move by ALIVE_METRES
ALIVE_METRES = 0.01
DRIVE = Twist(Vector3(0.5, 0, 0), Vector3(0, 0, 0.3))  # a circle of 1.7 m radius about (0, 1.7)
SIMULATOR = "/gazebo"
NOTHING_LOGGED = "(nothing on /rosout)"
# The simulator logs a dropped message once per topic per period of sim time, and a bad
# /gazebo/set_*_state message once per second (gazebo_services.cpp).
THROTTLE = {"/gazebo/set_model_state": ("set_model_state: ", 1.0),
            "/gazebo/set_link_state": ("set_link_state: ", 1.0)}
INPUT_THROTTLE = 5.0
TOPIC_TYPES = {"/cmd_vel": Twist, "/rover_velocity_controller/cmd_vel": Twist,
               "/arm/group_controller/command": Float64MultiArray, "/arm/arm_controller/command": JointTrajectory,
               "/gazebo/set_model_state": ModelState, "/gazebo/set_link_state": LinkState}


def finite(*values):
    return all(math.isfinite(v) for v in values)


def finite_pose(p):
    return finite(p.position.x, p.position.y, p.position.z, p.orientation.x, p.orientation.y, p.orientation.z,
                  p.orientation.w)


def finite_twist(t):
    return finite(t.linear.x, t.linear.y, t.linear.z, t.angular.x, t.angular.y, t.angular.z)


def finite_odometry(m):
    return finite_pose(m.pose.pose) and finite_twist(m.twist.twist)


def bounded_wait(condition, timeout):
    """Whether `condition()` held within `timeout` wall seconds (polled every 10 ms)."""
    deadline = time.monotonic() + timeout
    while not condition():
        if time.monotonic() > deadline:
            return False
        time.sleep(0.01)
    return True


class NonFiniteWatch:
    """A topic's messages checked as they arrive, the first that is not finite kept, and the last. A short queue:
    when the test falls behind some are skipped, but a state gone non-finite stays so."""

    def __init__(self, topic, message_type, is_finite, queue_size=10):
        self.topic, self.message, self.count, self.bad = topic, None, 0, None
        self._is_finite = is_finite
        self._subscriber = rospy.Subscriber(topic, message_type, self._check, queue_size=queue_size)

    def _check(self, message):
        self.message = message
        self.count += 1
        if self.bad is None and not self._is_finite(message):
            self.bad = message


class Rosout:
    """The simulator's lines on /rosout, as (sim stamp, text)."""

    def __init__(self):
        self.lines = []
        self._lock = threading.Lock()
        self._subscriber = rospy.Subscriber("/rosout", Log, self._add, queue_size=None)

    def _add(self, message):
        if message.name == SIMULATOR:
            with self._lock:
                self.lines.append((message.header.stamp.to_sec(), message.msg))

    def mark(self):
        with self._lock:
            return len(self.lines)

    def since(self, mark):
        with self._lock:
            return self.lines[mark:]

    def wait_for(self, mark, prefix):
        """The first line after `mark` that holds `prefix`, waited for LOG_WAIT; None if none came."""
        def found():
            return next((text for _, text in self.since(mark) if prefix in text), None)
        bounded_wait(lambda: found() is not None, LOG_WAIT)
        return found()

    def last_stamp(self, prefix):
        with self._lock:
            return max((stamp for stamp, text in self.lines if prefix in text), default=-math.inf)


class Driver(threading.Thread):
    """Tells the wheelchair to drive its circle, 20 times a wall second, until stopped."""

    def __init__(self):
        super().__init__(daemon=True)
        self.publisher = rospy.Publisher("/cmd_vel", Twist, queue_size=1)
        self.stopped = threading.Event()

    def run(self):
        while not self.stopped.wait(0.05):
            self.publisher.publish(DRIVE)


def run_tool(command):
    """The finished run of `command`, or its TimeoutExpired after 60 s."""
    try:
        return subprocess.run(command, capture_output=True, text=True, timeout=60, cwd=tempfile.gettempdir())
    except subprocess.TimeoutExpired as e:
        return e


def interleaved(rows, spread):
    """`rows` with the rows of `spread` evenly among them (the topics' rows: their warnings' throttle passes
    meanwhile)."""
    every = max(1, len(rows) // max(1, len(spread)))
    mixed, pending = [], list(spread)
    for index, row in enumerate(rows):
        if index % every == 0 and pending:
            mixed.append(pending.pop(0))
        mixed.append(row)
    return mixed + pending


class HostileRuntime(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("hostile_runtime")
        cls.start_tools()
        cls.odometry = NonFiniteWatch("/odom", Odometry, finite_odometry, queue_size=1)  # never behind
        cls.rosout = Rosout()
        cls.watches = [
            NonFiniteWatch("/gazebo/model_states", ModelStates,
                           lambda m: all(map(finite_pose, m.pose)) and all(map(finite_twist, m.twist))),
            NonFiniteWatch("/gazebo/link_states", LinkStates,
                           lambda m: all(map(finite_pose, m.pose)) and all(map(finite_twist, m.twist))),
            NonFiniteWatch("/arm/joint_states", JointState, lambda m: finite(*m.position, *m.velocity)),
            NonFiniteWatch("/joint_states", JointState, lambda m: finite(*m.position, *m.velocity)),
            NonFiniteWatch("/rover_velocity_controller/odom", Odometry, finite_odometry),
            cls.odometry]
        cls.publishers = {topic: rospy.Publisher(topic, kind, queue_size=10) for topic, kind in TOPIC_TYPES.items()}
        cls.gazebo = {}
        cls.driver = Driver()
        for topic, publisher in cls.publishers.items():
            if not bounded_wait(lambda: publisher.get_num_connections() > 0, 60):
                raise AssertionError("nobody subscribes to %s" % topic)
        cls.wait_for_controller("/arm", "group_controller", "running")
        cls.wait_for_controller("/arm", "arm_controller", "initialized")
        cls.wait_for_controller("", "rover_velocity_controller", "running")
        cls.wait_for_controller("", "rover_joint_publisher", "initialized")
        cls.driver.start()
        cls.table = []

    @classmethod
    def tearDownClass(cls):
        cls.driver.stopped.set()
        cls.tools.shutdown(wait=True, cancel_futures=True)
        shutil.rmtree(cls.tool_folder, ignore_errors=True)
        print("hostile_runtime: %d rows (interface | request | answer), printed as they ran" % len(cls.table),
              flush=True)

    @classmethod
    def start_tools(cls):
        """The tools' rows run as subprocesses from the start, two at a time; their rows collect the answers."""
        bullet_sim = rospkg.RosPack().get_path("bullet_sim")
        cls.tool_folder = tempfile.mkdtemp(prefix="hostile_runtime_")
        cases = hostile_rows.tool_cases(cls.tool_folder, bullet_sim + "/test/fixtures/scenarios/reach_region.yaml",
                                        bullet_sim + "/test/fixtures/scenarios/drive_matrix.yaml")
        executables = {tool: subprocess.run(["catkin_find", "--first-only", "bullet_sim", tool], capture_output=True,
                                            text=True, check=True).stdout.strip() for tool in ("scenario", "sweep")}
        cls.tools = concurrent.futures.ThreadPoolExecutor(max_workers=2)
        cls.tool_runs = [cls.tools.submit(run_tool, [executables[tool]] + arguments) for tool, arguments, _ in cases]
        cls.tool_table = hostile_rows.tool_rows(cases)

    @classmethod
    def wait_for_controller(cls, ns, name, state, timeout=60):
        rospy.wait_for_service(ns + "/controller_manager/list_controllers", timeout=timeout)
        listing = rospy.ServiceProxy(ns + "/controller_manager/list_controllers", ListControllers)
        if not bounded_wait(lambda: any(c.name == name and c.state == state for c in listing().controller),
                            timeout):
            raise AssertionError("controller %s never became %s" % (name, state))

    # What the rows call (hostile_rows.py).

    def proxy(self, name, service_type):
        if name not in self.gazebo:
            rospy.wait_for_service(name, timeout=ROW_TIMEOUT)
            self.gazebo[name] = rospy.ServiceProxy(name, service_type)
        return self.gazebo[name]

    def gazebo_call(self, service, *args):
        kind = gazebo_srv.SpawnModel if service.startswith("spawn_") else getattr(
            gazebo_srv, "".join(word.capitalize() for word in service.split("_")))
        call = self.proxy("/gazebo/" + service, kind)
        mark = self.rosout.mark()
        answer = call(**args[0]) if args and isinstance(args[0], dict) else call(*args)
        if service == "get_world_properties":
            return Answer(not answer.success, "%s: %s" % (answer.status_message, ", ".join(answer.model_names)))
        if answer.success:
            return Answer(False, answer.status_message)
        # Refused: logged as well, as Gazebo logs it.
        logged = self.rosout.wait_for(mark, "%s refused: %s" % (service, answer.status_message))
        return Answer(logged is not None, answer.status_message + ("" if logged else " " + NOTHING_LOGGED))

    def logged_call(self, service, args, prefix):
        """A service whose answer has no fields: its refusal is the line it logs."""
        mark = self.rosout.mark()
        kind = {"clear_body_wrenches": gazebo_srv.BodyRequest, "clear_joint_forces": gazebo_srv.JointRequest}[service]
        self.proxy("/gazebo/" + service, kind)(*args)
        text = self.rosout.wait_for(mark, prefix)
        return Answer(text is not None, text or NOTHING_LOGGED)

    def physics_now(self):
        answer = self.proxy("/gazebo/get_physics_properties", gazebo_srv.GetPhysicsProperties)()
        g = answer.gravity
        return Answer(not answer.success, "time_step %g, gravity (%g, %g, %g)" % (answer.time_step, g.x, g.y, g.z))

    def physics_with_ode(self, **fields):
        """set_physics_properties of the values in force, with `fields` of ode_config changed."""
        now = self.proxy("/gazebo/get_physics_properties", gazebo_srv.GetPhysicsProperties)()
        for name, value in fields.items():
            setattr(now.ode_config, name, value)
        return self.gazebo_call("set_physics_properties", now.time_step, now.max_update_rate, now.gravity,
                                now.ode_config)

    def manager_call(self, ns, service, args, prefix):
        """A controller manager's service: ok false, and the reason it logs."""
        kind = {"load_controller": LoadController, "unload_controller": UnloadController,
                "switch_controller": SwitchController, "reload_controller_libraries": ReloadControllerLibraries,
                "list_controllers": ListControllers, "list_controller_types": ListControllerTypes}[service]
        mark = self.rosout.mark()
        answer = self.proxy("%s/controller_manager/%s" % (ns, service), kind)(*args)
        if service == "list_controllers":
            return Answer(False, ", ".join("%s %s" % (c.name, c.state) for c in answer.controller))
        if service == "list_controller_types":
            return Answer(False, ", ".join(answer.types))
        if answer.ok:
            return Answer(False, "ok")
        return Answer(True, self.rosout.wait_for(mark, prefix) or NOTHING_LOGGED)

    def publish(self, topic, message):
        """Publishes once the topic's warning throttle has passed; the answer is the warning it logs."""
        prefix, period = THROTTLE.get(topic, (topic + ": ignored ", INPUT_THROTTLE))
        due = self.rosout.last_stamp(prefix) + period + 0.3  # the simulator's ROS clock trails its own
        if not self.odometry_after(due):
            return Answer(False, "the clock never reached %.1f s" % due)
        mark = self.rosout.mark()
        self.publishers[topic].publish(message)
        text = self.rosout.wait_for(mark, prefix)
        return Answer(text is not None, text or NOTHING_LOGGED)

    def send_goal(self, trajectory, path_tolerance=(), goal_tolerance=()):
        if not hasattr(self, "action"):
            self.action = actionlib.SimpleActionClient("/arm/arm_controller/follow_joint_trajectory",
                                                       FollowJointTrajectoryAction)
            self.assertTrue(self.action.wait_for_server(rospy.Duration(ROW_TIMEOUT)), "no action server")
        self.action.send_goal(FollowJointTrajectoryGoal(trajectory=trajectory, path_tolerance=list(path_tolerance),
                                                        goal_tolerance=list(goal_tolerance)))
        if not self.action.wait_for_result(rospy.Duration(ROW_TIMEOUT)):
            return Answer(False, "no result")
        result = self.action.get_result()
        return Answer(result.error_code != 0, "error_code %d: %s" % (result.error_code, result.error_string))

    def tool_answer(self, index):
        run = self.tool_runs[index].result(timeout=60)
        if isinstance(run, subprocess.TimeoutExpired):
            return Answer(False, "no exit within 60 s")
        lines = run.stderr.splitlines()
        one_line = len(lines) == 1 and run.stdout == ""
        return Answer(run.returncode == 2 and one_line, "exit %d: %s" % (run.returncode, run.stderr.strip()))

    # The checks after each row.

    def odometry_after(self, stamp):
        """Whether the wheelchair's odometry reached sim time `stamp` within ROW_TIMEOUT."""
        return bounded_wait(lambda: self.odometry.message and
                            self.odometry.message.header.stamp.to_sec() >= stamp, ROW_TIMEOUT)

    def alive_problem(self, start):
        """None when the clock went on from `start` (an odometry message), the wheelchair moved and all
        published is finite."""
        def moved():
            end = self.odometry.message
            return (end.header.stamp.to_sec() >= start.header.stamp.to_sec() + ALIVE_SIM_SECONDS and
                    math.hypot(end.pose.pose.position.x - start.pose.pose.position.x,
                               end.pose.pose.position.y - start.pose.pose.position.y) >= ALIVE_METRES)
        if not bounded_wait(moved, ROW_TIMEOUT):
            return "the clock stopped or the wheelchair no longer drives (odometry at %.3f s)" % (
                self.odometry.message.header.stamp.to_sec())
        bad = [watch.topic for watch in self.watches if watch.bad is not None]
        return "a message not finite on %s" % ", ".join(bad) if bad else None

    def run_rows(self, rows):
        """Sends each row, checks its answer and that all is well after; the problems, one line each."""
        problems = []
        for row in rows:
            if not bounded_wait(lambda: self.odometry.message, ROW_TIMEOUT):
                raise AssertionError("no odometry")
            start = self.odometry.message
            try:
                answer = row.send(self)
            except Exception as e:  # a transport error, a dead service: the row fails, the table goes on
                answer = Answer(None, "%s: %s" % (type(e).__name__, e))
            self.table.append((row.interface, row.request, answer.text))
            print("| %s | %s | %s |" % (row.interface, row.request, answer.text.replace("\n", " ")), flush=True)
            if answer.refused is not row.refuses or row.expected not in answer.text:
                problems.append("%s %s: %r (expected %s%r)" % (row.interface, row.request, answer,
                                                               "a refusal with " if row.refuses else "", row.expected))
            alive = self.alive_problem(start)
            if alive:
                problems.append("after %s %s: %s" % (row.interface, row.request, alive))
                break  # the rows after it would only repeat this
        return problems

    def test_1_every_hostile_request_is_refused_and_the_world_runs_on(self):
        services = (hostile_rows.model_state_rows() + hostile_rows.link_rows() + hostile_rows.wrench_rows() +
                    hostile_rows.joint_rows() + hostile_rows.physics_rows() + hostile_rows.spawn_rows() +
                    hostile_rows.controller_manager_rows())
        problems = self.run_rows(interleaved(services, hostile_rows.command_topic_rows()))
        # After the group controller's bad commands the arm switches back to its trajectory controller.
        switch = self.proxy("/arm/controller_manager/switch_controller", SwitchController)
        self.assertTrue(switch(["arm_controller"], ["group_controller"], 2, False, 0.0).ok, "switch back")
        problems += self.run_rows(hostile_rows.trajectory_rows() + self.tool_table)
        self.assertGreaterEqual(len(self.table), 100)
        self.assertEqual(problems, [])
        self.assertTrue(all(watch.count > 0 for watch in self.watches),
                        ", ".join("%s %d" % (w.topic, w.count) for w in self.watches))

    def test_2_the_arm_respawned_in_its_namespace_gets_its_controllers_again(self):
        description = rospy.get_param("/arm_description")
        delete = self.proxy("/gazebo/delete_model", gazebo_srv.DeleteModel)
        spawn = self.proxy("/gazebo/spawn_urdf_model", gazebo_srv.SpawnModel)
        self.assertTrue(delete("arm").success)
        # Under another model name, so that only the namespace given can lead it to /arm's parameters.
        answer = spawn("arm_again", description, "/arm", pose(y=-4), "")
        self.assertTrue(answer.success, answer.status_message)
        load = self.proxy("/arm/controller_manager/load_controller", LoadController)
        for name in ["joint_state_controller", "arm_controller"]:
            self.assertTrue(load(name).ok, "load_controller %s after the respawn" % name)
        switch = self.proxy("/arm/controller_manager/switch_controller", SwitchController)
        self.assertTrue(switch(["joint_state_controller", "arm_controller"], [], 2, False, 0.0).ok)
        self.wait_for_controller("/arm", "arm_controller", "running")
        self.assertIsNone(self.alive_problem(self.odometry.message))

    def test_3_a_drive_that_cannot_publish_its_odometry_is_spawned_with_the_reason(self):
        # As in Gazebo, the robot comes and drives without its odometry; the answer says why, not only /rosout.
        path = rospkg.RosPack().get_path("bullet_sim") + "/test/fixtures/doctor/clean_two_wheeler.urdf"
        with open(path) as file:
            urdf = file.read().replace("</leftJoint>", "</leftJoint><odometryTopic>/clock</odometryTopic>")
        spawn = self.proxy("/gazebo/spawn_urdf_model", gazebo_srv.SpawnModel)
        answer = spawn("odometry_on_clock", urdf, "/stray", pose(x=-6, z=0.06), "")
        self.assertTrue(answer.success, answer.status_message)
        self.assertIn("cannot publish nav_msgs/Odometry on [/clock]: it carries rosgraph_msgs/Clock",
                      answer.status_message)
        self.assertIsNone(self.alive_problem(self.odometry.message))
        self.assertTrue(self.proxy("/gazebo/delete_model", gazebo_srv.DeleteModel)("odometry_on_clock").success)

    def test_4_a_drive_on_a_topic_another_node_publishes_as_another_type_is_spawned_with_the_reason(self):
        # ROS joins a publisher and a subscriber only when their types agree: the drive would hear nobody.
        occupied = rospy.Publisher("/hostile/occupied", String, queue_size=1)
        topics = lambda: dict(rospy.get_published_topics())
        self.assertTrue(bounded_wait(lambda: topics().get("/hostile/occupied") == "std_msgs/String", 30),
                        "the master never listed /hostile/occupied")
        path = rospkg.RosPack().get_path("bullet_sim") + "/test/fixtures/doctor/clean_two_wheeler.urdf"
        with open(path) as file:
            urdf = file.read().replace("</leftJoint>", "</leftJoint><commandTopic>/hostile/occupied</commandTopic>")
        spawn = self.proxy("/gazebo/spawn_urdf_model", gazebo_srv.SpawnModel)
        answer = spawn("command_elsewhere", urdf, "/stray", pose(x=-6, y=2, z=0.06), "")
        self.assertTrue(answer.success, answer.status_message)
        self.assertIn("cannot subscribe to geometry_msgs/Twist on [/hostile/occupied]: another node publishes "
                      "std_msgs/String there", answer.status_message)
        self.assertIsNone(self.alive_problem(self.odometry.message))
        self.assertTrue(self.proxy("/gazebo/delete_model", gazebo_srv.DeleteModel)("command_elsewhere").success)
        occupied.unregister()


if __name__ == "__main__":
    rostest.rosrun("bullet_sim_bringup", "hostile_runtime", HostileRuntime)
