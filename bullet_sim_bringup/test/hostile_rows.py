"""The rows of hostile_runtime.py: one hostile request each, through one interface of the live simulator, with a
piece of the answer it must get. A row's `send(harness)` returns an Answer; the harness (hostile_runtime.py) owns
the proxies, the publishers, /rosout and the tools' runs. `refuses` is False only for the few services that take
nothing hostile (the queries of the whole world), whose answer must still say what it should."""
import collections
import os

import rospy
from control_msgs.msg import JointTolerance
from gazebo_msgs.msg import LinkState, ModelState, ODEJointProperties, ODEPhysics
from geometry_msgs.msg import Point, Pose, Quaternion, Twist, Vector3, Wrench
from std_msgs.msg import Float64MultiArray
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

NAN = float("nan")
INF = float("inf")

Row = collections.namedtuple("Row", "interface request send expected refuses", defaults=(True,))
Answer = collections.namedtuple("Answer", "refused text")

GRAVITY = Vector3(0, 0, -9.81)
UPRIGHT = (0.0, 0.0, 0.0, 1.0)


def pose(x=0.0, y=0.0, z=0.0, q=UPRIGHT):
    return Pose(Point(x, y, z), Quaternion(*q))


def twist(linear=(0, 0, 0), angular=(0, 0, 0)):
    return Twist(Vector3(*linear), Vector3(*angular))


def gazebo(service, request, args, expected, refuses=True):
    return Row("/gazebo/" + service, request, lambda h: h.gazebo_call(service, *args), expected, refuses)


def model_state_rows():
    def state(request, expected, model="wheelchair", at=pose(z=0.1), velocity=twist(), frame=""):
        return gazebo("set_model_state", request, [ModelState(model, at, velocity, frame)], expected)
    return [
        state("position.x NaN", "pose.position.x [nan] is not a finite number", at=pose(x=NAN)),
        state("position.y inf", "pose.position.y [inf] is not a finite number", at=pose(y=INF)),
        state("position.z 1e300", "pose.position.z [1e+300] m is beyond the limit", at=pose(z=1e300)),
        state("orientation (NaN 0 0 1)", "pose.orientation (x y z w) [nan 0 0 1] is not finite",
              at=pose(q=(NAN, 0, 0, 1))),
        state("orientation 1e200 each", "is no rotation: its norm [2e+200]", at=pose(q=(1e200,) * 4)),
        state("orientation 1e-200 each", "is no rotation: its norm [2e-200]", at=pose(q=(1e-200,) * 4)),
        state("twist.linear.y NaN", "twist.linear.y [nan] is not finite", velocity=twist((0, NAN, 0))),
        state("twist.linear.x 1e7", "twist.linear.x [1e+07 m/s] is beyond", velocity=twist((1e7, 0, 0))),
        state("twist.angular.z -inf", "twist.angular.z [-inf] is not finite", velocity=twist(angular=(0, 0, -INF))),
        state("model ghost", "no model [ghost]", model="ghost"),
        state("reference_frame nowhere", "reference frame [nowhere] names no model", frame="nowhere"),
        state("rover y 9999 in the rover's frame", "in the world: pose.position.y", at=pose(y=9999),
              frame="rover"),
        gazebo("get_model_state", "model ghost", ["ghost", ""], "no model [ghost]"),
        gazebo("get_model_state", "relative to nowhere", ["wheelchair", "nowhere"],
               "reference frame [nowhere] names no model or link"),
    ]


def link_rows():
    def link_state(request, expected, link="wheelchair::base_footprint", at=pose(z=0.1), velocity=twist()):
        return gazebo("set_link_state", request, [LinkState(link, at, velocity, "")], expected)
    return [
        link_state("position.x NaN", "pose.position.x [nan]", at=pose(x=NAN)),
        link_state("orientation (0 inf 0 1)", "pose.orientation (x y z w) [0 inf 0 1] is not finite",
                   at=pose(q=(0, INF, 0, 1))),
        link_state("twist.angular.y NaN", "twist.angular.y [nan] is not finite", velocity=twist(angular=(0, NAN, 0))),
        link_state("a link on a joint (arm::upper_arm)", "moves on joint [shoulder]", link="arm::upper_arm"),
        link_state("a model as a link", "is a model, not a link", link="wheelchair"),
        link_state("link wheelchair::ghost", "[wheelchair::ghost] names no model or link", link="wheelchair::ghost"),
        gazebo("get_link_state", "a model as a link", ["rover", ""], "is a model, not a link"),
        gazebo("get_link_state", "relative to nowhere", ["rover::base_link", "nowhere"], "names no model or link"),
        gazebo("get_link_properties", "link wheelchair::ghost", ["wheelchair::ghost"], "names no model or link"),
        gazebo("get_link_properties", "the ground's link", ["ground_plane::link"], "without mass"),
        gazebo("set_link_properties", "mass NaN", ["rover::base_link", Pose(), True, NAN, 1, 0, 0, 1, 0, 1],
               "fixes a link's mass"),
        gazebo("set_link_properties", "link ghost", ["ghost", Pose(), True, 1, 1, 0, 0, 1, 0, 1],
               "[ghost] names no model or link"),
        gazebo("get_model_properties", "model ghost", ["ghost"], "no model [ghost]"),
        gazebo("get_world_properties", "(nothing to send): the three robots listed", [], "got properties",
               refuses=False),
    ]


def wrench_rows():
    def wrench(request, expected, force=(0, 0, 0), torque=(0, 0, 0), point=(0, 0, 0), body="wheelchair::base_link",
               frame=""):
        return gazebo("apply_body_wrench", request, [body, frame, Point(*point), Wrench(Vector3(*force),
                      Vector3(*torque)), rospy.Time(), rospy.Duration(0.1)], expected)
    return [
        wrench("force.x NaN", "wrench.force.x [nan] is not finite", force=(NAN, 0, 0)),
        wrench("force.y NaN after a finite x", "wrench.force.y [nan] is not finite", force=(1, NAN, 0)),
        wrench("force.z inf", "wrench.force.z [inf] is not finite", force=(0, 0, INF)),
        wrench("force.x 1e13", "wrench.force.x [1e+13 N] is beyond", force=(1e13, 0, 0)),
        wrench("torque.y NaN after a finite x", "wrench.torque.y [nan] is not finite", torque=(1, NAN, 0)),
        wrench("torque.x -1e13", "wrench.torque.x [-1e+13 N m] is beyond", torque=(-1e13, 0, 0)),
        wrench("reference_point.z inf", "reference_point.z [inf] is not a finite number", point=(0, 0, INF)),
        wrench("reference_point.x 1e5", "reference_point.x [100000] m is beyond", point=(1e5, 0, 0)),
        wrench("body ghost", "body [ghost] names no model or link", force=(1, 0, 0), body="ghost"),
        wrench("the ground", "it takes no wrench", force=(1, 0, 0), body="ground_plane::link"),
        wrench("reference_frame nowhere", "reference frame [nowhere] names no model or link", force=(1, 0, 0),
               frame="nowhere"),
        Row("/gazebo/clear_body_wrenches", "body ghost (its answer has no fields: the reason on /rosout)",
            lambda h: h.logged_call("clear_body_wrenches", ["ghost"], "clear_body_wrenches: "),
            "body [ghost] names no model or link"),
    ]


def joint_rows():
    def effort(request, expected, value, joint="arm::wrist"):
        return gazebo("apply_joint_effort", request, [joint, value, rospy.Time(), rospy.Duration(0.1)], expected)

    def motor(request, expected, vel, fmax, joint="arm::wrist", **more):
        return gazebo("set_joint_properties", request, [joint, ODEJointProperties(vel=vel, fmax=fmax, **more)],
                      expected)

    def configure(request, expected, names, positions, model="arm"):
        return gazebo("set_model_configuration", request, [model, "", names, positions], expected)
    return [
        effort("effort NaN", "effort [nan] is not finite", NAN),
        effort("effort -inf", "effort [-inf] is not finite", -INF),
        effort("effort 1e13", "effort [1e+13 N m or N] is beyond", 1e13),
        effort("joint arm::elbow", "no moving joint [arm::elbow]", 1, joint="arm::elbow"),
        Row("/gazebo/clear_joint_forces", "joint arm::elbow (its answer has no fields: the reason on /rosout)",
            lambda h: h.logged_call("clear_joint_forces", ["arm::elbow"], "clear_joint_forces: "),
            "no moving joint [arm::elbow]"),
        motor("vel NaN", "vel [nan] is not finite", [NAN], [1]),
        motor("vel 1e7", "vel [1e+07 rad/s or m/s] is beyond", [1e7], [1]),
        motor("fmax -1", "fmax [-1] must be >= 0", [1], [-1]),
        motor("fmax 1e13", "fmax [1e+13 N m or N] is beyond", [1], [1e13]),
        motor("vel without fmax", "vel and fmax drive the joint's motor together", [1], []),
        motor("damping of two values", "damping has 2 values, and the joint one axis", [], [], damping=[0.1, 0.2]),
        motor("joint ghost", "no moving joint [ghost]", [1], [1], joint="ghost"),
        gazebo("get_joint_properties", "joint ghost", ["ghost"], "no moving joint [ghost]"),
        configure("shoulder NaN", "the position of [shoulder] [nan] is not a finite", ["shoulder"], [NAN]),
        configure("wrist inf", "the position of [wrist] [inf] is not a finite", ["wrist"], [INF]),
        configure("wrist 1e5", "[100000] is beyond the limit of 10000", ["wrist"], [1e5]),
        configure("two names, one position", "joint name and position list have different lengths",
                  ["shoulder", "wrist"], [0.0]),
        configure("of the ground", "is the world's", ["x"], [0.0], model="ground_plane"),
        configure("model ghost", "no model [ghost]", ["x"], [0.0], model="ghost"),
    ]


def physics_rows():
    def physics(request, expected, step=0.001, rate=0.0, gravity=GRAVITY):
        return gazebo("set_physics_properties", request, [step, rate, gravity, ODEPhysics()], expected)
    return [
        physics("time_step NaN", "time_step [nan] is not finite", step=NAN),
        physics("time_step 0", "time_step [0] must be positive", step=0),
        physics("time_step -0.001", "time_step [-0.001] must be positive", step=-0.001),
        physics("time_step 1e-10", "time_step [1e-10 s] is below the 1e-06 s", step=1e-10),
        physics("time_step 10", "time_step [10 s] is beyond the 1 s", step=10),
        physics("max_update_rate NaN", "max_update_rate [nan] is not finite", rate=NAN),
        physics("max_update_rate inf", "max_update_rate [inf] is not finite", rate=INF),
        physics("max_update_rate -1", "max_update_rate [-1] must be 0 (as fast as possible)", rate=-1),
        physics("max_update_rate 1e-10", "max_update_rate [1e-10] must be 0 (as fast as possible) or at least",
                rate=1e-10),
        physics("gravity.y NaN after a finite x", "gravity.y [nan] is not finite", gravity=Vector3(0, NAN, -9.81)),
        physics("gravity.z -inf", "gravity.z [-inf] is not finite", gravity=Vector3(0, 0, -INF)),
        physics("gravity.z -1e7", "gravity.z [-1e+07 m/s^2] is beyond", gravity=Vector3(0, 0, -1e7)),
        Row("/gazebo/set_physics_properties", "the values in force, ode_config.erp NaN",
            lambda h: h.physics_with_ode(erp=NAN), "ode_config.erp [nan] is not finite"),
        Row("/gazebo/set_physics_properties", "the values in force, ode_config.contact_max_correcting_vel inf",
            lambda h: h.physics_with_ode(contact_max_correcting_vel=INF),
            "ode_config.contact_max_correcting_vel [inf] is not finite"),
        Row("/gazebo/get_physics_properties", "(nothing to send): time_step and gravity as before the refusals",
            lambda h: h.physics_now(), "time_step 0.001, gravity (0, 0, -9.81)", refuses=False),
    ]


def chain(links, sdf):
    """A model of `links` links chained by fixed joints, as URDF or SDF."""
    if sdf:
        body = "".join("<link name='l%d'/>" % i for i in range(links)) + "".join(
            "<joint name='j%d' type='fixed'><parent>l%d</parent><child>l%d</child></joint>" % (i, i - 1, i)
            for i in range(1, links))
        return "<sdf version='1.6'><model name='chain'>%s</model></sdf>" % body
    body = "".join("<link name='l%d'/>" % i for i in range(links)) + "".join(
        "<joint name='j%d' type='fixed'><parent link='l%d'/><child link='l%d'/></joint>" % (i, i - 1, i)
        for i in range(1, links))
    return "<robot name='chain'>%s</robot>" % body


def spawn_rows():
    box = "<robot name='box'><link name='box'/></robot>"

    def spawn(service, request, expected, xml=box, at=pose(y=-8, z=1), name="box", frame=""):
        return gazebo(service, request, [name, xml, "", at, frame], expected)
    return [
        spawn("spawn_urdf_model", "initial_pose.position.x NaN", "initial_pose.position.x [nan] is not finite",
              at=pose(x=NAN)),
        spawn("spawn_urdf_model", "initial_pose.orientation (NaN 0 0 1)",
              "initial_pose.orientation (x y z w) [nan 0 0 1] is not finite", at=pose(q=(NAN, 0, 0, 1))),
        spawn("spawn_urdf_model", "initial_pose.orientation 1e-200 each", "is no rotation",
              at=pose(q=(1e-200,) * 4)),
        spawn("spawn_urdf_model", "an SDF", "is SDF, not a URDF: spawn it with spawn_sdf_model",
              xml="<sdf version='1.6'><model name='m'><link name='l'/></model></sdf>"),
        spawn("spawn_urdf_model", "text that is not XML", "it is not XML", xml="box, please"),
        spawn("spawn_urdf_model", "root element <world>", "its root element is <world>", xml="<world/>"),
        spawn("spawn_urdf_model", "a name taken (wheelchair)", "a robot named [wheelchair] already exists",
              name="wheelchair"),
        spawn("spawn_urdf_model", "reference_frame nowhere", "reference frame [nowhere] names no model or link",
              frame="nowhere"),
        Row("/gazebo/spawn_urdf_model", "the arm under robot_namespace 'bad ns!'",
            lambda h: h.gazebo_call("spawn_urdf_model", "arm_2", rospy.get_param("/arm_description"), "bad ns!",
                                    pose(y=-8), ""), "robot_namespace [bad ns!] is not a ROS name"),
        spawn("spawn_urdf_model", "3000 links", "the robot has 3000 links, above the limit of 1000 (max_links)",
              xml=chain(3000, sdf=False)),
        spawn("spawn_sdf_model", "initial_pose.orientation 1e200 on z and w", "is no rotation",
              at=pose(q=(0, 0, 1e200, 1e200))),
        spawn("spawn_sdf_model", "text that is not XML", "it is not XML", xml="<<<"),
        spawn("spawn_sdf_model", "3000 links chained by fixed joints",
              "the robot has 3000 links, above the limit of 1000 (max_links)", xml=chain(3000, sdf=True)),
        gazebo("delete_model", "model ghost", ["ghost"], "no model [ghost]"),
        gazebo("delete_model", "the world's ground_plane", ["ground_plane"], "is a model of the world file"),
        gazebo("get_light_properties", "light sun", ["sun"], "bullet_sim simulates no lights"),
        gazebo("set_light_properties", "light sun", [{"light_name": "sun"}], "bullet_sim simulates no lights"),
        gazebo("delete_light", "light sun", ["sun"], "bullet_sim simulates no lights"),
    ]


def manager(robot, service, request, args, expected, refuses=True):
    """A controller manager's service: `ok` false and the reason on /rosout as `[robot] ...`; the list
    services answer what they list."""
    ns = "/arm" if robot == "arm" else ""
    return Row("%s/controller_manager/%s" % (ns, service), request,
               lambda h: h.manager_call(ns, service, args, "[%s] " % robot), expected, refuses)


def controller_manager_rows():
    return arm_manager_rows() + rover_manager_rows()


def arm_manager_rows():
    """The arm's controller manager (/arm), with group_controller running and arm_controller loaded."""
    arm = "arm"
    return [
        manager(arm, "load_controller", "ghost_controller (no parameters)", ["ghost_controller"],
                "could not load controller [ghost_controller]: its type is not set"),
        manager(arm, "load_controller", "'bad name'", ["bad name"], "its name must be a ROS name"),
        manager(arm, "load_controller", "'' (empty)", [""], "its name must be a ROS name"),
        manager(arm, "load_controller", "arm_controller again", ["arm_controller"],
                "a controller of that name is loaded already"),
        manager(arm, "unload_controller", "group_controller, running", ["group_controller"],
                "it is still running: stop it first"),
        manager(arm, "unload_controller", "ghost", ["ghost"], "could not unload controller [ghost]: no controller"),
        manager(arm, "switch_controller", "start ghost, STRICT", [["ghost"], [], 2, False, 0.0],
                "could not start controller [ghost]: no controller of that name is loaded"),
        manager(arm, "switch_controller", "start and stop group_controller", [["group_controller"],
                ["group_controller"], 1, False, 0.0], "it is asked both to start and to stop"),
        manager(arm, "switch_controller", "start arm_controller beside group_controller",
                [["arm_controller"], [], 2, False, 0.0], "joint [shoulder] would be claimed by"),
        manager(arm, "switch_controller", "stop arm_controller, not running", [[], ["arm_controller"], 2, False, 0.0],
                "controller [arm_controller] is not running, so it cannot stop"),
        manager(arm, "reload_controller_libraries", "force_kill false, controllers loaded", [False],
                "cannot reload controller libraries: 3 controllers are still loaded"),
        manager(arm, "load_controller", "nan_goal_time_controller (constraints/goal_time .nan)",
                ["nan_goal_time_controller"], "constraints/goal_time must be >= 0 (0 is not enforced), not [.nan]"),
        manager(arm, "load_controller", "nan_state_rate_controller (state_publish_rate .nan)",
                ["nan_state_rate_controller"], "state_publish_rate must be >= 0 [Hz], not [.nan]"),
        manager(arm, "load_controller", "elbow_controller (a joint the arm lacks)", ["elbow_controller"],
                "joint [elbow] has no transmission ros_control drives"),
        manager(arm, "list_controllers", "(nothing to send): three controllers", [], "group_controller running",
                refuses=False),
        manager(arm, "list_controller_types", "(nothing to send): the trajectory controller among them", [],
                "position_controllers/JointTrajectoryController", refuses=False),
    ]


def rover_manager_rows():
    """The rover's controller manager (/), with rover_velocity_controller running and rover_joint_publisher
    loaded."""
    rover = "rover"
    return [
        manager(rover, "load_controller", "ghost_controller (no parameters)", ["ghost_controller"],
                "could not load controller [ghost_controller]: its type is not set"),
        manager(rover, "load_controller", "rover_velocity_controller again", ["rover_velocity_controller"],
                "a controller of that name is loaded already"),
        manager(rover, "load_controller", "'a/../b'", ["a/../b"], "its name must be a ROS name"),
        manager(rover, "load_controller", "inf_radius_drive (wheel_radius .inf)", ["inf_radius_drive"],
                "radii (inf, inf m), multipliers included, must be finite and > 0"),
        manager(rover, "load_controller", "nan_limit_drive (linear/x/max_velocity .nan)", ["nan_limit_drive"],
                "linear/x/max_velocity must be a number, not [.nan]"),
        manager(rover, "load_controller", "nan_timeout_drive (cmd_vel_timeout .nan)", ["nan_timeout_drive"],
                "cmd_vel_timeout must be >= 0 [s], not [.nan]"),
        manager(rover, "load_controller", "nan_rate_publisher (publish_rate .nan)", ["nan_rate_publisher"],
                "publish_rate must be finite and >= 0 [Hz], not [.nan]"),
        manager(rover, "unload_controller", "rover_velocity_controller, running", ["rover_velocity_controller"],
                "it is still running: stop it first"),
        manager(rover, "switch_controller", "start rover_velocity_controller, running, STRICT",
                [["rover_velocity_controller"], [], 2, False, 0.0],
                "controller [rover_velocity_controller] is running already"),
        manager(rover, "switch_controller", "stop rover_joint_publisher, not running, STRICT",
                [[], ["rover_joint_publisher"], 2, False, 0.0], "is not running, so it cannot stop"),
        manager(rover, "switch_controller", "stop ghost, STRICT", [[], ["ghost"], 2, False, 0.0],
                "could not stop controller [ghost]: no controller of that name is loaded"),
        manager(rover, "reload_controller_libraries", "force_kill false, controllers loaded", [False],
                "cannot reload controller libraries: 2 controllers are still loaded"),
        manager(rover, "list_controller_types", "(nothing to send): the diff drive among them", [],
                "diff_drive_controller/DiffDriveController", refuses=False),
        manager(rover, "list_controllers", "(nothing to send): the drive running, the joint publisher not", [],
                "rover_joint_publisher initialized", refuses=False),
    ]


def topic(name, request, message, expected):
    """A message on a topic: dropped, with a (per-topic throttled) warning on /rosout naming the value."""
    return Row(name, request, lambda h: h.publish(name, message), expected)


def command_topic_rows():
    """Round robin over the topics, so that waiting out one topic's warning throttle overlaps the others."""
    cmd_vel, rover, group = "/cmd_vel", "/rover_velocity_controller/cmd_vel", "/arm/group_controller/command"
    model_state, link_state = "/gazebo/set_model_state", "/gazebo/set_link_state"
    return [
        topic(cmd_vel, "linear.x NaN", twist((NAN, 0, 0)), "linear.x [nan] is not finite"),
        topic(rover, "linear.x NaN", twist((NAN, 0, 0)), "linear.x [nan] is not finite"),
        topic(group, "data [NaN, 0]", Float64MultiArray(data=[NAN, 0.0]),
              "a message whose data[0] [nan] is not finite"),
        topic(model_state, "wheelchair turned by (NaN 0 0 1)", ModelState("wheelchair", pose(q=(NAN, 0, 0, 1)),
              twist(), ""), "pose.orientation (x y z w) [nan 0 0 1] is not finite"),
        topic(link_state, "arm::forearm at x NaN", LinkState("arm::forearm", pose(x=NAN), twist(), ""),
              "pose.position.x [nan]"),
        topic(cmd_vel, "angular.z inf", twist(angular=(0, 0, INF)), "angular.z [inf] is not finite"),
        topic(rover, "angular.z -1e300", twist(angular=(0, 0, -1e300)), "angular.z [-1e+300 rad/s] is beyond"),
        topic(group, "data [1e308, -1e308]", Float64MultiArray(data=[1e308, -1e308]), "data[0] [1e+308] is beyond"),
        topic(model_state, "wheelchair turned by 1e200 on x and w", ModelState("wheelchair",
              pose(q=(1e200, 0, 0, 1e200)), twist(), ""), "is no rotation"),
        topic(cmd_vel, "linear.x 1e300", twist((1e300, 0, 0)), "linear.x [1e+300 m/s]"),
        topic(rover, "linear.x inf", twist((INF, 0, 0)), "linear.x [inf] is not finite"),
        topic(group, "data [inf, -inf]", Float64MultiArray(data=[INF, -INF]), "data[0] [inf] is not finite"),
        topic(model_state, "wheelchair turned by 1e-200 on x", ModelState("wheelchair", pose(q=(1e-200, 0, 0, 0)),
              twist(), ""), "is no rotation"),
        topic(group, "data [0] (one value for two joints)", Float64MultiArray(data=[0.0]),
              "a command of 1 values for controller [group_controller]"),
    ]


def trajectory(points, joints=("shoulder", "wrist")):
    """(time_from_start, positions, velocities) per point."""
    return JointTrajectory(joint_names=list(joints), points=[
        JointTrajectoryPoint(positions=p, velocities=v, time_from_start=rospy.Duration.from_sec(t))
        for t, p, v in points])


def trajectory_rows():
    """With arm_controller running."""
    def goal(request, expected, points, joints=("shoulder", "wrist"), **tolerances):
        return Row("/arm/arm_controller/follow_joint_trajectory", request,
                   lambda h: h.send_goal(trajectory(points, joints), **tolerances), expected)
    command = "/arm/arm_controller/command"
    return [
        goal("positions [NaN, 0]", "points[0].positions[0] [nan] is not finite", [(1.0, [NAN, 0.0], [])]),
        goal("velocities [inf, 0]", "points[0].velocities[0] [inf] is not finite", [(1.0, [0.0, 0.0], [INF, 0.0])]),
        goal("positions [0, -1e308]", "points[0].positions[1] [-1e+308] is beyond", [(1.0, [0.0, -1e308], [])]),
        goal("one position for two joints", "has 1 positions for 2 joints", [(1.0, [0.0], [])]),
        goal("joint elbow", "joint [elbow] is not one of", [(1.0, [0.0, 0.0], [])], joints=("shoulder", "elbow")),
        goal("time_from_start not increasing", "time_from_start must increase strictly",
             [(1.0, [0.0, 0.0], []), (1.0, [0.1, 0.0], [])]),
        goal("path_tolerance of shoulder NaN", "path_tolerance[0].position [nan] is not finite",
             [(1.0, [0.1, 0.1], [])], path_tolerance=[JointTolerance("shoulder", NAN, 0, 0)]),
        goal("goal_tolerance of wrist velocity inf", "goal_tolerance[0].velocity [inf] is not finite",
             [(1.0, [0.1, 0.1], [])], goal_tolerance=[JointTolerance("wrist", 0, INF, 0)]),
        topic(command, "positions [0, NaN]", trajectory([(1.0, [0.0, NAN], [])]),
              "points[0].positions[1] [nan] is not finite"),
    ]


def tool_cases(folder, scenario_file, matrix_file):
    """(tool, arguments, what its one line must say): the scenario and sweep tools, as subprocesses."""
    a_file = os.path.join(folder, "a_file")
    with open(a_file, "w") as file:
        file.write("x\n")

    def written(name, text):
        path = os.path.join(folder, name)
        with open(path, "w") as file:
            file.write(text)
        return path
    wraps = written("wraps.yaml", "scenario: %s\naxes: {seed: {from: 9223372036854775807, count: 2}}\n"
                    % scenario_file)
    negative = written("negative.yaml", "scenario: %s\naxes: {seed: {from: -5, count: 2}}\n" % scenario_file)
    two_problems = written("two_problems.yaml", "seed: -1\nduration: -2\nrobot: {description: nope.xacro}\n")
    return [
        ("scenario", [], "give a scenario FILE, or --matrix M.yaml --index N"),
        ("scenario", [os.path.join(folder, "nope.yaml")], "is not a file"),
        ("scenario", [two_problems], "seed: [-1] is out of range: give a number from 0 to 9.0072e+15; duration: [-2]"),
        ("scenario", [scenario_file, "--bogus"], "The following argument was not expected: --bogus"),
        ("scenario", [scenario_file, "--seed", "nan"], "--seed: [nan] is not a number"),
        ("scenario", [scenario_file, "--seed", "1e300"], "--seed [1e300]: give a whole number from 0"),
        ("scenario", [scenario_file, "--out", a_file], "is a file, not a folder"),
        ("scenario", ["--matrix", matrix_file, "--index", "8"], "no cell [8]: it has 8, numbered 0 to 7"),
        ("scenario", ["--matrix", wraps, "--list"], "goes past the largest whole number"),
        ("scenario", ["--matrix", negative, "--list"], "seed: [-5] is out of range"),
        ("sweep", [], "the following arguments are required: matrix"),
        ("sweep", [os.path.join(folder, "nope.yaml")], "is not a file"),
        ("sweep", [matrix_file, "--out", a_file], "is a file, not a folder"),
        ("sweep", [matrix_file, "--cpus", "0"], "argument --cpus: [0] is not in 1 to 4096"),
        ("sweep", [matrix_file, "--timeout", "nan"], "argument --timeout: [nan] is not a positive number of seconds"),
        ("sweep", [matrix_file, "--address", "headnode"], "--address [headnode] is not HOST:PORT"),
        ("sweep", [wraps], "goes past the largest whole number"),
    ]


def tool_rows(cases):
    """The rows of `cases`, their files named by their base names."""
    def request(arguments):
        return " ".join(os.path.basename(a) if os.sep in a else a for a in arguments) or "(no arguments)"
    return [Row(tool, request(arguments), lambda h, index=index: h.tool_answer(index), expected)
            for index, (tool, arguments, expected) in enumerate(cases)]
