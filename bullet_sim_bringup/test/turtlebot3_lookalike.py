#!/usr/bin/env python3
"""rostest node: a TurtleBot3 look-alike's own launch files run unedited on bullet_sim.

It copies fixtures/turtlebot3_lookalike (turtlebot3_description, turtlebot3_gazebo: written for these tests
with the structure of ROBOTIS's packages) to a temporary folder, writes the world's COLLADA wall there, and
runs `roslaunch turtlebot3_gazebo <~launch>` with that folder first on ROS_PACKAGE_PATH and
TURTLEBOT3_MODEL=burger, as a user would. The launch file includes gazebo_ros's empty_world.launch with a
world of model:// includes found through the package's gazebo_model_path export, expands the robot with
`xacro --inorder` and spawns it with `gazebo_ros spawn_model -param robot_description -z 0.0`.

The burger must spawn at the launch file's pose, see each pillar where geometry puts it (the beam through a
pillar reads the analytic distance to its surface, averaged over noisy scans), drive forward on cmd_vel, and
see the pillars again from where odometry says it stopped.
"""
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time
import unittest

import rospkg
import rospy
import rostest
from gazebo_msgs.srv import GetPhysicsProperties
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from sensor_msgs.msg import LaserScan

from bringup_support import Collector, interrupt, yaw
from collada import prism, write_collada

TIMEOUT = 90.0  # [s] for the launch to come up, and for each wait after that
PILLARS = [(x, y) for x in (-1.1, 0.0, 1.1) for y in (-1.1, 0.0, 1.1)]  # [m] as the world's model.sdf says
PILLAR_RADIUS = 0.15  # [m]
WALL_CIRCUMRADIUS = 3.0  # [m] of the hexagonal wall's centre line
WALL_THICKNESS, WALL_HEIGHT = 0.1, 0.5  # [m]
WALL_UNIT, WALL_SCALE = 0.0254, 0.5  # the DAE is in inches, and model.sdf scales it by 0.5
LIDAR_OFFSET = -0.032  # [m] of base_scan ahead of base_footprint
SCANS_AVERAGED = 5
RANGE_TOLERANCE = 0.02  # [m]: lidar noise 0.01 m, averaged over 5 scans


def write_wall(path):
    """The hexagonal wall as a COLLADA file in inches, six boxes between the hexagon's corners."""
    to_file = 1.0 / (WALL_UNIT * WALL_SCALE)
    corners = [(WALL_CIRCUMRADIUS * math.cos(k * math.pi / 3), WALL_CIRCUMRADIUS * math.sin(k * math.pi / 3))
               for k in range(7)]
    parts = []
    for k, ((x0, y0), (x1, y1)) in enumerate(zip(corners, corners[1:])):
        length = math.hypot(x1 - x0, y1 - y0)
        nx, ny = (y1 - y0) / length * WALL_THICKNESS / 2, -(x1 - x0) / length * WALL_THICKNESS / 2
        outline = [(x0 + nx, y0 + ny), (x1 + nx, y1 + ny), (x1 - nx, y1 - ny), (x0 - nx, y0 - ny)]
        vertices, triangles = prism([(x * to_file, y * to_file) for x, y in outline], WALL_HEIGHT * to_file)
        parts.append(("wall_%d" % k, vertices, triangles, (0.6, 0.6, 0.6, 1)))
    write_collada(path, parts, unit_name="inch", unit_meter=WALL_UNIT)


def build_packages(folder):
    """Copies the look-alike packages into `folder` and writes the world's wall mesh there."""
    fixture = os.path.join(rospkg.RosPack().get_path("bullet_sim_bringup"), "test", "fixtures",
                           "turtlebot3_lookalike")
    shutil.copytree(fixture, folder, ignore=shutil.ignore_patterns("CATKIN_IGNORE"), dirs_exist_ok=True)
    meshes = os.path.join(folder, "turtlebot3_gazebo", "models", "turtlebot3_world", "meshes")
    os.makedirs(meshes)
    write_wall(os.path.join(meshes, "wall.dae"))


def first_hit(origin, angle, pillars):
    """Distance along the ray from `origin` at `angle` to the nearest pillar surface, or inf."""
    ux, uy = math.cos(angle), math.sin(angle)
    nearest = math.inf
    for cx, cy in pillars:
        fx, fy = origin[0] - cx, origin[1] - cy
        b = fx * ux + fy * uy
        discriminant = b * b - (fx * fx + fy * fy - PILLAR_RADIUS ** 2)
        if discriminant >= 0 and -b - math.sqrt(discriminant) > 0:
            nearest = min(nearest, -b - math.sqrt(discriminant))
    return nearest


def wall_hit(origin, angle):
    """Distance along the ray from `origin` (inside the wall) at `angle` to the wall's inner face."""
    apothem = WALL_CIRCUMRADIUS * math.cos(math.pi / 6) - WALL_THICKNESS / 2
    # The inner face is the hexagon of apothem `apothem`; its k-th side faces the direction (2k + 1) * 30 deg.
    ux, uy = math.cos(angle), math.sin(angle)
    distances = []
    for k in range(6):
        nx, ny = math.cos((2 * k + 1) * math.pi / 6), math.sin((2 * k + 1) * math.pi / 6)
        along = ux * nx + uy * ny
        if along > 1e-9:
            distances.append((apothem - (origin[0] * nx + origin[1] * ny)) / along)
    return min(distances)


class TurtleBot3LookAlike(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.folder = tempfile.mkdtemp(prefix="turtlebot3_lookalike_")
        build_packages(cls.folder)
        env = dict(os.environ, TURTLEBOT3_MODEL="burger",
                   ROS_PACKAGE_PATH=cls.folder + ":" + os.environ.get("ROS_PACKAGE_PATH", ""))
        cls.log = open(os.path.join(cls.folder, "roslaunch.log"), "w")
        cls.launch = subprocess.Popen(["roslaunch", "turtlebot3_gazebo", rospy.get_param("~launch")], env=env,
                                      stdout=cls.log, stderr=subprocess.STDOUT)

    @classmethod
    def tearDownClass(cls):
        interrupt(cls.launch, TIMEOUT)
        cls.log.close()
        shutil.rmtree(cls.folder, ignore_errors=True)

    def averaged_scan(self, scans, after):
        """Ranges averaged over the first scans stamped after `after` [sim s], and the first such scan."""
        recent = scans.wait_for(lambda m: len([s for s in m if s.header.stamp.to_sec() > after]) >= SCANS_AVERAGED,
                                TIMEOUT, "%d scans" % SCANS_AVERAGED)
        recent = [s for s in recent if s.header.stamp.to_sec() > after][:SCANS_AVERAGED]
        return [sum(s.ranges[i] for s in recent) / len(recent) for i in range(len(recent[0].ranges))], recent[0]

    def check_pillars(self, ranges, scan, pose):
        """Each visible pillar's beam reads the analytic distance from the lidar at odometry's `pose`."""
        x, y, heading = pose
        lidar = (x + LIDAR_OFFSET * math.cos(heading), y + LIDAR_OFFSET * math.sin(heading))
        seen = 0
        for cx, cy in PILLARS:
            bearing = math.atan2(cy - lidar[1], cx - lidar[0]) - heading
            beam = round(((bearing - scan.angle_min) % (2 * math.pi)) / scan.angle_increment) % len(ranges)
            angle = heading + scan.angle_min + beam * scan.angle_increment
            expected = first_hit(lidar, angle, PILLARS)
            if expected > scan.range_max:
                continue
            seen += 1
            self.assertAlmostEqual(ranges[beam], expected, delta=RANGE_TOLERANCE,
                                   msg="pillar (%g, %g), beam %d from (%.3f, %.3f)" % (cx, cy, beam, *lidar))
        # The COLLADA wall (inches, scaled by the SDF) where no pillar stands in the way.
        walls = 0
        for beam in range(0, len(ranges), 10):
            angle = heading + scan.angle_min + beam * scan.angle_increment
            expected = wall_hit(lidar, angle)
            if expected < scan.range_max and first_hit(lidar, angle, PILLARS) > expected:
                walls += 1
                self.assertAlmostEqual(ranges[beam], expected, delta=RANGE_TOLERANCE,
                                       msg="the wall, beam %d from (%.3f, %.3f)" % (beam, *lidar))
        self.assertGreater(walls, 5, "beams that reach the wall")
        return seen

    def test_burger_spawns_scans_and_drives(self):
        odometry = Collector("/odom", Odometry)
        scans = Collector("/scan", LaserScan)
        start = odometry.wait_for(lambda m: m, TIMEOUT, "odom from the spawned burger")[-1].pose.pose
        self.assertAlmostEqual(start.position.x, rospy.get_param("~x"), delta=0.01)
        self.assertAlmostEqual(start.position.y, rospy.get_param("~y"), delta=0.01)
        self.assertLess(abs(start.position.z), 0.005, "spawned with -z 0.0: base_footprint on the ground")
        in_world = rospy.get_param("~launch") == "turtlebot3_world.launch"

        ranges, scan = self.averaged_scan(scans, 0)
        if in_world:
            self.assertGreaterEqual(self.check_pillars(ranges, scan, (start.position.x, start.position.y, 0)), 6)
        else:
            self.assertTrue(all(math.isinf(r) for r in ranges), "nothing within 3.5 m of the empty world")

        stopped = self.drive_forward(odometry, 0.3)
        pose = stopped.pose.pose
        self.assertGreater(pose.position.x - start.position.x, 0.3)
        self.assertLess(abs(pose.position.y - start.position.y), 0.02, "drove straight")
        if in_world:
            ranges, scan = self.averaged_scan(scans, stopped.header.stamp.to_sec())
            self.check_pillars(ranges, scan, (pose.position.x, pose.position.y, yaw(pose.orientation)))

    def test_physics_properties_are_the_worlds(self):
        """get_physics_properties reports the world's <ode> settings, as Gazebo does (they are not used)."""
        rospy.wait_for_service("/gazebo/get_physics_properties", timeout=TIMEOUT)
        physics = rospy.ServiceProxy("/gazebo/get_physics_properties", GetPhysicsProperties)()
        self.assertTrue(physics.success, physics.status_message)
        self.assertEqual(physics.time_step, 0.001)
        self.assertEqual(physics.max_update_rate, 1000.0)
        ode = physics.ode_config
        self.assertEqual((ode.sor_pgs_iters, ode.sor_pgs_precon_iters), (150, 0))
        self.assertAlmostEqual(ode.sor_pgs_w, 1.4)
        self.assertAlmostEqual(ode.cfm, 1e-5)
        self.assertAlmostEqual(ode.erp, 0.2)
        self.assertEqual(ode.max_contacts, 20, "sdformat's default: the world writes none")

    def drive_forward(self, odometry, distance):
        """Drives at 0.15 m/s until odometry has moved `distance` [m], then stops; the odometry at rest."""
        commands = rospy.Publisher("/cmd_vel", Twist, queue_size=1)
        start = odometry.messages[-1].pose.pose.position.x
        forward = Twist()
        forward.linear.x = 0.15
        deadline = time.monotonic() + TIMEOUT
        while odometry.messages[-1].pose.pose.position.x - start < distance:
            self.assertLess(time.monotonic(), deadline, "the burger did not drive %.1f m" % distance)
            commands.publish(forward)
            odometry.wait_for(lambda m, n=len(odometry.messages): len(m) > n, TIMEOUT, "odom while driving")
        halted = len(odometry.messages)
        while True:
            commands.publish(Twist())
            latest = odometry.wait_for(lambda m, n=len(odometry.messages): len(m) > n, TIMEOUT, "odom")[-1]
            if len(odometry.messages) - halted > 10 and abs(latest.twist.twist.linear.x) < 0.002:
                return latest
            self.assertLess(time.monotonic(), deadline, "the burger did not stop")


if __name__ == "__main__":
    rospy.init_node("turtlebot3_lookalike")
    rostest.rosrun("bullet_sim_bringup", "turtlebot3_lookalike", TurtleBot3LookAlike, sys.argv)
