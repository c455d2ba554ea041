#!/usr/bin/env python3
"""rostest node: Gazebo's world API under /gazebo with gazebo_msgs, on the wheelchair in test_room.world: each
service and topic does what gazebo_ros's api plugin does, and a request that cannot be honoured answers
success false with the reason. Each test leaves the world as it found it (reset_world, the default physics)."""
import math
import sys
import unittest
import xml.etree.ElementTree as ET

import rospy
import rostest
from gazebo_msgs.msg import LinkState, LinkStates, ModelState, ModelStates, ODEJointProperties
from gazebo_msgs.srv import (ApplyBodyWrench, ApplyJointEffort, BodyRequest, DeleteLight, DeleteModel,
                             GetJointProperties, GetLightProperties, GetLinkProperties, GetLinkState,
                             GetModelProperties, GetModelState, GetPhysicsProperties, GetWorldProperties,
                             JointRequest, SetJointProperties, SetLightProperties, SetLinkProperties, SetLinkState,
                             SetModelConfiguration, SetModelState, SetPhysicsProperties, SpawnModel)
from geometry_msgs.msg import Point, Pose, Quaternion, Twist, Vector3, Wrench
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import LaserScan
from std_srvs.srv import Empty

from bringup_support import Collector, yaw

ROBOT = "wheelchair"
BOX_URDF = """<robot name="box"><link name="body">
  <inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
  <collision><geometry><box size="0.2 0.2 0.2"/></geometry></collision></link></robot>"""


def service(name, kind):
    rospy.wait_for_service("/gazebo/" + name, timeout=60)
    return rospy.ServiceProxy("/gazebo/" + name, kind)


def pose(x, y, z, heading=0.0):
    return Pose(Point(x, y, z), Quaternion(0, 0, math.sin(heading / 2), math.cos(heading / 2)))


def axis_inertia(description, joint_name):
    """The moment of inertia [kg m^2] of a joint's child link about the joint axis, from the URDF."""
    urdf = ET.fromstring(description)
    joint = next(j for j in urdf.findall("joint") if j.get("name") == joint_name)
    axis = [float(v) for v in joint.find("axis").get("xyz").split()]
    norm = math.sqrt(sum(a * a for a in axis))
    axis = [a / norm for a in axis]
    link = next(l for l in urdf.findall("link") if l.get("name") == joint.find("child").get("link"))
    i = {k: float(v) for k, v in link.find("inertial/inertia").attrib.items()}
    tensor = [[i["ixx"], i["ixy"], i["ixz"]], [i["ixy"], i["iyy"], i["iyz"]], [i["ixz"], i["iyz"], i["izz"]]]
    return sum(axis[r] * tensor[r][c] * axis[c] for r in range(3) for c in range(3))


class WorldApi(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.clock = Collector("/clock", Clock)
        cls.clock.wait_for(lambda m: m, 60, "/clock")
        service("get_model_state", GetModelState)  # the simulator is up
        for _ in range(100):  # and the robot is spawned
            if service("get_model_state", GetModelState)(ROBOT, "").success:
                break
            rospy.sleep(0.1)

    def tearDown(self):
        service("set_physics_properties", SetPhysicsProperties)(0.001, 1000, Vector3(0, 0, -9.81),
                                                                  service("get_physics_properties",
                                                                          GetPhysicsProperties)().ode_config)
        service("unpause_physics", Empty)()
        service("reset_world", Empty)()

    def now(self):
        return self.clock.messages[-1].clock.to_sec()

    def wait_sim(self, seconds):
        target = self.now() + seconds
        self.clock.wait_for(lambda m: m[-1].clock.to_sec() >= target, 60, "%.1f s of sim time" % seconds)

    def model_state(self, name, reference=""):
        response = service("get_model_state", GetModelState)(name, reference)
        self.assertTrue(response.success, response.status_message)
        return response

    def test_model_states_and_link_states_list_every_model_and_link(self):
        models = Collector("/gazebo/model_states", ModelStates).wait_for(lambda m: m, 30, "model_states")[-1]
        self.assertEqual(models.name, ["ground_plane", "room", ROBOT])
        self.assertAlmostEqual(models.pose[2].position.x, self.model_state(ROBOT).pose.position.x, delta=0.01)
        links = Collector("/gazebo/link_states", LinkStates).wait_for(lambda m: m, 30, "link_states")[-1]
        self.assertIn("room::wall_east", links.name)
        self.assertIn(ROBOT + "::base_footprint", links.name)
        self.assertNotIn(ROBOT + "::base_link", links.name, "fixed joints merge links, as Gazebo lumps them")
        world = service("get_world_properties", GetWorldProperties)()
        self.assertTrue(world.success)
        self.assertEqual(world.model_names, ["ground_plane", "room", ROBOT])
        self.assertGreater(world.sim_time, 0)

    def test_set_model_state_teleports_by_service_and_by_topic(self):
        set_state = service("set_model_state", SetModelState)
        answer = set_state(ModelState(ROBOT, pose(1.0, -0.5, 0, math.pi / 2), Twist(), ""))
        self.assertTrue(answer.success, answer.status_message)
        got = self.model_state(ROBOT)
        self.assertAlmostEqual(got.pose.position.x, 1.0, delta=0.01)
        self.assertAlmostEqual(yaw(got.pose.orientation), math.pi / 2, delta=0.01)
        relative = self.model_state(ROBOT, "room")  # the room's frame is the world's
        self.assertAlmostEqual(relative.pose.position.y, -0.5, delta=0.01)
        publisher = rospy.Publisher("/gazebo/set_model_state", ModelState, queue_size=1, latch=True)
        publisher.publish(ModelState(ROBOT, pose(-1.0, 0.5, 0), Twist(), "world"))
        states = Collector("/gazebo/model_states", ModelStates)
        states.wait_for(lambda m: m and abs(m[-1].pose[2].position.x + 1.0) < 0.01, 30, "the topic's teleport")
        publisher.unregister()
        wrong = set_state(ModelState(ROBOT, pose(0, 0, 0), Twist(), "no_such_frame"))
        self.assertFalse(wrong.success)
        self.assertIn("[no_such_frame]", wrong.status_message)

    def test_world_models_teleport_and_reset_world_puts_them_back(self):
        answer = service("set_model_state", SetModelState)(ModelState("room", pose(0.5, 0, 0), Twist(), ""))
        self.assertTrue(answer.success, answer.status_message)
        self.assertAlmostEqual(self.model_state("room").pose.position.x, 0.5, delta=1e-9)
        link = service("get_link_state", GetLinkState)("room::wall_east", "")
        self.assertTrue(link.success, link.status_message)
        self.assertAlmostEqual(link.link_state.pose.position.x, 3.05 + 0.5, delta=1e-9)
        service("reset_world", Empty)()
        self.assertAlmostEqual(self.model_state("room").pose.position.x, 0.0, delta=1e-9)
        self.assertFalse(service("get_model_state", GetModelState)("no_such_model", "").success)

    def test_link_states_are_read_and_set_in_reference_frames(self):
        get_link = service("get_link_state", GetLinkState)
        base = get_link(ROBOT + "::base_link", ROBOT + "::base_footprint")
        self.assertTrue(base.success, base.status_message)
        self.assertGreater(base.link_state.pose.position.z, 0.1)  # base_link sits above base_footprint
        target = LinkState(ROBOT + "::base_footprint", pose(0.3, 0.2, 0), Twist(), "")
        answer = service("set_link_state", SetLinkState)(target)
        self.assertTrue(answer.success, answer.status_message)
        self.assertAlmostEqual(self.model_state(ROBOT).pose.position.x, 0.3, delta=0.01)
        wheel = service("set_link_state", SetLinkState)(LinkState(ROBOT + "::front_left_link", pose(0, 0, 0),
                                                                  Twist(), ""))
        self.assertFalse(wheel.success)
        self.assertIn("set_model_configuration", wheel.status_message)

    def test_properties_of_models_links_and_joints(self):
        robot = service("get_model_properties", GetModelProperties)(ROBOT)
        self.assertTrue(robot.success)
        self.assertEqual(robot.canonical_body_name, "base_footprint")
        self.assertIn("front_left_joint", robot.joint_names)
        self.assertFalse(robot.is_static)
        room = service("get_model_properties", GetModelProperties)("room")
        self.assertTrue(room.is_static)
        self.assertEqual(room.body_names, ["wall_east", "wall_west", "wall_north", "wall_south"])
        link = service("get_link_properties", GetLinkProperties)(ROBOT + "::base_link")
        self.assertTrue(link.success, link.status_message)
        self.assertGreater(link.mass, 20)
        same = service("set_link_properties", SetLinkProperties)(ROBOT + "::base_link", link.com,
                                                                 link.gravity_mode,
                                                                 link.mass, link.ixx, link.ixy, link.ixz, link.iyy,
                                                                 link.iyz, link.izz)
        self.assertTrue(same.success, same.status_message)
        heavier = service("set_link_properties", SetLinkProperties)(ROBOT + "::base_link", link.com, True,
                                                                    2 * link.mass, link.ixx, link.ixy, link.ixz,
                                                                    link.iyy, link.iyz, link.izz)
        self.assertFalse(heavier.success)
        self.assertIn("mass", heavier.status_message)
        joint = service("get_joint_properties", GetJointProperties)("wheel_rear_left_joint")
        self.assertTrue(joint.success, joint.status_message)
        self.assertEqual(joint.type, GetJointProperties._response_class.CONTINUOUS)
        self.assertEqual(list(joint.damping), [0.001])

    def test_set_joint_properties_drives_the_motor_and_names_what_it_does_not_use(self):
        set_joint = service("set_joint_properties", SetJointProperties)
        answer = set_joint("wheel_rear_left_joint", ODEJointProperties(erp=[0.2], cfm=[0.0]))
        self.assertTrue(answer.success, answer.status_message)
        self.assertIn("not used", answer.status_message)
        self.assertIn("erp", answer.status_message)
        stop = set_joint("wheel_rear_left_joint", ODEJointProperties(hiStop=[1.0]))
        self.assertFalse(stop.success)
        self.assertIn("hiStop", stop.status_message)
        self.assertFalse(set_joint("no_such_joint", ODEJointProperties()).success)
        self.assertFalse(set_joint("wheel_rear_left_joint", ODEJointProperties(vel=[2.0])).success, "no fmax")
        # The caster wheel carries load but no friction, so its motor spins it up to vel within fmax.
        motor = set_joint("wheel_rear_left_joint", ODEJointProperties(vel=[2.0], fmax=[1.0]))
        self.assertTrue(motor.success, motor.status_message)
        self.wait_sim(0.5)
        rate = service("get_joint_properties", GetJointProperties)("wheel_rear_left_joint").rate[0]
        self.assertAlmostEqual(rate, 2.0, delta=1e-6)

    def test_model_configuration_sets_the_named_joints(self):
        answer = service("set_model_configuration", SetModelConfiguration)(ROBOT, "", ["wheel_rear_left_joint"],
                                                                           [1.25])
        self.assertTrue(answer.success, answer.status_message)
        service("pause_physics", Empty)()
        joint = service("get_joint_properties", GetJointProperties)("wheel_rear_left_joint")
        self.assertAlmostEqual(joint.position[0], 1.25, delta=0.05)
        uneven = service("set_model_configuration", SetModelConfiguration)(ROBOT, "", ["a", "b"], [1.0])
        self.assertFalse(uneven.success)
        # As Gazebo, a joint the model lacks is skipped and the call succeeds (spawn_model -J ... -unpause then
        # unpauses); the status names it.
        skipped = service("set_model_configuration", SetModelConfiguration)(
            ROBOT, "", ["wheel_rear_left_joint", "gripper_joint"], [0.5, 0.1])
        self.assertTrue(skipped.success, skipped.status_message)
        self.assertIn("[gripper_joint] is not a moving joint", skipped.status_message)
        joint = service("get_joint_properties", GetJointProperties)("wheel_rear_left_joint")
        self.assertAlmostEqual(joint.position[0], 0.5, delta=0.05)

    def test_a_body_wrench_lifts_the_robot_for_its_duration(self):
        mass = sum(service("get_link_properties", GetLinkProperties)(ROBOT + "::" + name).mass
                   for name in service("get_model_properties", GetModelProperties)(ROBOT).body_names)
        states = Collector("/gazebo/model_states", ModelStates)
        start = rospy.Time.from_sec(self.now() + 0.2)
        answer = service("apply_body_wrench", ApplyBodyWrench)(
            ROBOT + "::base_footprint", "", Point(), Wrench(Vector3(0, 0, 200 * mass), Vector3()), start,
            rospy.Duration(0.1))
        self.assertTrue(answer.success, answer.status_message)
        # 0.1 s at 20 g upwards net of gravity leaves it rising at about 19.6 m/s: far above the ground.
        states.wait_for(lambda m: m and m[-1].pose[2].position.z > 1.0, 60, "the robot to rise above 1 m")
        forever = service("apply_body_wrench", ApplyBodyWrench)(ROBOT, "", Point(), Wrench(), rospy.Time(),
                                                                rospy.Duration(-1))
        self.assertTrue(forever.success, forever.status_message)
        service("clear_body_wrenches", BodyRequest)(ROBOT + "::base_footprint")
        self.assertFalse(service("apply_body_wrench", ApplyBodyWrench)(
            "room::wall_east", "", Point(), Wrench(), rospy.Time(), rospy.Duration(1)).success)

    def test_a_joint_effort_spins_a_caster_wheel_by_effort_times_duration_over_inertia(self):
        joint = "wheel_rear_left_joint"
        inertia = axis_inertia(rospy.get_param("/robot_description"), joint)
        service("pause_physics", Empty)()
        before = service("get_joint_properties", GetJointProperties)(joint).rate[0]
        effort, duration = 0.05, 0.4
        answer = service("apply_joint_effort", ApplyJointEffort)(joint, effort, rospy.Time(),
                                                                 rospy.Duration(duration))
        self.assertTrue(answer.success, answer.status_message)
        service("unpause_physics", Empty)()
        self.wait_sim(duration + 0.1)
        service("pause_physics", Empty)()
        rate = service("get_joint_properties", GetJointProperties)(joint).rate[0]
        expected = effort * duration / inertia
        self.assertAlmostEqual(rate - before, expected, delta=0.02 * expected)
        service("clear_joint_forces", JointRequest)(joint)
        swivel = service("apply_joint_effort", ApplyJointEffort)("rear_left_joint", 1.0, rospy.Time(),
                                                                 rospy.Duration(1))
        self.assertFalse(swivel.success)
        self.assertIn("<wheelModel>contact</wheelModel>", swivel.status_message)

    def test_physics_properties_set_the_step_and_run_as_fast_as_possible(self):
        get = service("get_physics_properties", GetPhysicsProperties)
        physics = get()
        self.assertEqual((physics.time_step, physics.max_update_rate), (0.001, 1000.0))
        self.assertAlmostEqual(physics.gravity.z, -9.81)
        self.assertEqual(physics.ode_config.sor_pgs_iters, 50)
        answer = service("set_physics_properties", SetPhysicsProperties)(0.002, 0, Vector3(0, 0, -9.81),
                                                                         physics.ode_config)
        self.assertTrue(answer.success, answer.status_message)
        self.assertIn("not used", answer.status_message)
        now = get()
        self.assertEqual((now.time_step, now.max_update_rate), (0.002, 0.0))
        changed_at = service("get_world_properties", GetWorldProperties)().sim_time  # after every earlier tick
        # As fast as possible, a second of sim time can pass within a few ms of wall time, and /clock comes
        # at most every 1 ms of wall time (pub_clock_frequency): wait for ticks, not for sim time.
        def later_ticks(messages):
            return [round(m.clock.to_sec() * 1000) for m in messages if m.clock.to_sec() >= changed_at]
        ticks = later_ticks(self.clock.wait_for(lambda m: len(later_ticks(m)) > 5, 60, "6 ticks of /clock"))
        self.assertTrue(all(t % 2 == ticks[0] % 2 for t in ticks), "the clock moves in steps of 2 ms")
        refused = service("set_physics_properties", SetPhysicsProperties)(0, 1000, Vector3(), physics.ode_config)
        self.assertFalse(refused.success)
        self.assertEqual(get().time_step, 0.002)

    def test_spawn_urdf_model_and_delete_model(self):
        spawn = service("spawn_urdf_model", SpawnModel)
        service("pause_physics", Empty)()  # so that the box has not fallen when it is read back
        answer = spawn("box", BOX_URDF, "", pose(0, 0, 1.0), "room::wall_east")
        self.assertTrue(answer.success, answer.status_message)
        box = self.model_state("box")
        self.assertAlmostEqual(box.pose.position.x, 3.05, delta=1e-6)  # 1 m above the wall's link frame
        self.assertAlmostEqual(box.pose.position.z, 0.5 + 1.0, delta=1e-6)
        self.assertFalse(spawn("box", BOX_URDF, "", pose(0, 0, 1), "").success, "the name is taken")
        sdf = spawn("sdf_box", "<sdf version='1.6'><model name='m'/></sdf>", "", pose(0, 0, 1), "")
        self.assertFalse(sdf.success)
        self.assertIn("spawn_sdf_model", sdf.status_message)
        delete = service("delete_model", DeleteModel)
        self.assertTrue(delete("box").success)
        self.assertFalse(service("get_model_state", GetModelState)("box", "").success)
        self.assertFalse(delete("box").success)
        room = delete("room")
        self.assertFalse(room.success)
        self.assertIn("set_model_state", room.status_message)

    def test_spawn_sdf_model_with_two_links_a_revolute_joint_and_a_lidar(self):
        with open(rospy.get_param("~pan_lidar")) as f:
            sdf = f.read()
        # 1 m to the side of the chair, facing +x: its head's lidar is 0.02 m ahead of the pan axis.
        answer = service("spawn_sdf_model", SpawnModel)("pan_lidar", sdf, "/pan", pose(0, 1.0, 0), "")
        self.assertTrue(answer.success, answer.status_message)
        try:
            scans = Collector("/pan/scan", LaserScan)
            ahead = scans.wait_for(lambda m: m, 30, "/pan/scan")[-1].ranges[90]
            self.assertAlmostEqual(ahead, 3.0 - 0.02, delta=0.01)  # the room's east wall
            joint = service("get_joint_properties", GetJointProperties)("pan_lidar::pan")
            self.assertTrue(joint.success, joint.status_message)
            self.assertEqual(joint.type, GetJointProperties._response_class.REVOLUTE)
            turned = service("set_model_configuration", SetModelConfiguration)("pan_lidar", "", ["pan"],
                                                                               [math.pi / 2])
            self.assertTrue(turned.success, turned.status_message)
            seen = len(scans.messages)
            scans.wait_for(lambda m: len(m) > seen + 1, 30, "scans after the turn")
            self.assertAlmostEqual(scans.messages[-1].ranges[90], 2.0 - 1.0 - 0.02, delta=0.01)  # the north wall
            properties = service("get_model_properties", GetModelProperties)("pan_lidar")
            self.assertEqual(properties.body_names, ["base", "head"])
        finally:
            self.assertTrue(service("delete_model", DeleteModel)("pan_lidar").success)
        unjoined = "<sdf version='1.6'><model name='m'><link name='a'/><link name='b'/></model></sdf>"
        broken = service("spawn_sdf_model", SpawnModel)("broken", unjoined, "", pose(0, 0, 0), "")
        self.assertFalse(broken.success)
        self.assertIn("joined to nothing", broken.status_message)

    def test_bad_requests_are_refused_with_the_reason_and_the_simulator_runs_on(self):
        set_state = service("set_model_state", SetModelState)
        for bad in [pose(float("nan"), 0, 0), pose(1e300, 0, 0)]:
            answer = set_state(ModelState(ROBOT, bad, Twist(), ""))
            self.assertFalse(answer.success)
            self.assertIn("model [%s]" % ROBOT, answer.status_message)
        wrench = service("apply_body_wrench", ApplyBodyWrench)(ROBOT, "", Point(), Wrench(Vector3(1e300, 0, 0),
                                                                                          Vector3()),
                                                               rospy.Time(), rospy.Duration(1))
        self.assertFalse(wrench.success)
        physics = service("get_physics_properties", GetPhysicsProperties)()
        step = service("set_physics_properties", SetPhysicsProperties)(float("inf"), 1000, physics.gravity,
                                                                       physics.ode_config)
        self.assertFalse(step.success)
        publisher = rospy.Publisher("/gazebo/set_model_state", ModelState, queue_size=1, latch=True)
        publisher.publish(ModelState(ROBOT, pose(float("inf"), 0, 0), Twist(), ""))
        self.wait_sim(0.5)  # the clock goes on
        self.assertLess(abs(self.model_state(ROBOT).pose.position.x), 0.05, "the robot is where it was")
        publisher.unregister()

    def test_lights_are_not_simulated_and_say_so(self):
        for name, kind in [("delete_light", DeleteLight), ("get_light_properties", GetLightProperties)]:
            answer = service(name, kind)("sun")
            self.assertFalse(answer.success)
            self.assertIn("no lights", answer.status_message)
        self.assertFalse(service("set_light_properties", SetLightProperties)(light_name="sun").success)


if __name__ == "__main__":
    rospy.init_node("world_api")
    rostest.rosrun("bullet_sim_bringup", "world_api", WorldApi, sys.argv)
