#!/usr/bin/env python3
"""Writes bullet_sim/worlds/walled_boxes.world (issue 32's "20 wheelchairs among 200 dynamic boxes in a walled
20 x 20 m world"): Gazebo's ground plane, four walls enclosing 20 x 20 m, and 200 loose cardboard boxes at
seeded places and headings, every one at least ROBOT_CLEARANCE from the 20 places where
`bench --robots 20 --spacing 4` spawns its wheelchairs, so that every robot starts free and its 1 m circle
runs into boxes.

    /usr/bin/python3 scripts/walled_boxes_world.py [--check]   # --check: fail if the committed file differs

The same seed gives the same file on any Python 3 (random.Random's random() is reproducible by its contract).
"""
import argparse
import math
import os
import random
import sys

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
WORLD = os.path.join(REPO, "bullet_sim", "worlds", "walled_boxes.world")

SEED = 32
HALF_SIDE = 10.0  # [m] the walls' inner faces at x, y = +-10
WALL_THICKNESS = 0.1  # [m]
WALL_HEIGHT = 1.0  # [m]: above the wheelchair's lidar (0.56 m), so that it sees them
BOXES = 200
BOX_SIDE = 0.4  # [m] a moving carton: its top is above the wheelchair's seat block (0.28 m off the ground)
BOX_MASS = 4.0  # [kg]
BOX_GAP = 0.8  # [m] between two boxes' centres, at least (their half diagonals are 0.28 m)
WALL_GAP = 0.5  # [m] from a box's centre to a wall's inner face, at least
# bench's fleet grid (bench_fleet.cpp's gridPose) for 20 robots 4 m apart: 5 columns along x, 4 rows along y.
ROBOT_SPACING = 4.0  # [m]
ROBOT_PLACES = [((column - 2) * ROBOT_SPACING, (row - 1.5) * ROBOT_SPACING) for row in range(4) for column in range(5)]
# [m] from a robot's base frame to a box's centre, at least: the wheelchair reaches 0.46 m behind its base frame
# and 0.41 m ahead (its drive wheels), 0.35 m to each side; a box's half diagonal is 0.28 m.
ROBOT_CLEARANCE = 1.0


def box_places():
    """BOXES (x, y, yaw), drawn uniformly and kept when clear of the walls, the robots and the boxes so far."""
    generator = random.Random(SEED)
    reach = HALF_SIDE - WALL_GAP
    places = []
    while len(places) < BOXES:
        x = -reach + 2 * reach * generator.random()
        y = -reach + 2 * reach * generator.random()
        yaw = math.pi / 2 * generator.random()  # a cube looks the same every quarter turn
        if any(math.hypot(x - rx, y - ry) < ROBOT_CLEARANCE for rx, ry in ROBOT_PLACES):
            continue
        if any(math.hypot(x - bx, y - by) < BOX_GAP for bx, by, _ in places):
            continue
        places.append((x, y, yaw))
    return places


def wall(name, x, y, length_x, length_y):
    size = "%g %g %g" % (length_x, length_y, WALL_HEIGHT)
    return """      <link name="{name}">
        <pose>{x:g} {y:g} {z:g} 0 0 0</pose>
        <collision name="collision">
          <geometry><box><size>{size}</size></box></geometry>
          <surface><friction><ode><mu>1</mu><mu2>1</mu2></ode></friction></surface>
        </collision>
        <visual name="visual">
          <geometry><box><size>{size}</size></box></geometry>
          <material><ambient>0.8 0.8 0.75 1</ambient><diffuse>0.8 0.8 0.75 1</diffuse></material>
        </visual>
      </link>
""".format(name=name, x=x, y=y, z=WALL_HEIGHT / 2, size=size)


def box(index, x, y, yaw):
    inertia = BOX_MASS * BOX_SIDE ** 2 / 6  # [kg m^2] of a solid cube about any axis through its centre
    size = "%g %g %g" % (BOX_SIDE, BOX_SIDE, BOX_SIDE)
    return """    <model name="box_{index:03d}">
      <pose>{x:.3f} {y:.3f} {z:g} 0 0 {yaw:.4f}</pose>
      <link name="link">
        <inertial>
          <mass>{mass:g}</mass>
          <inertia><ixx>{i:.6g}</ixx><iyy>{i:.6g}</iyy><izz>{i:.6g}</izz><ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia>
        </inertial>
        <collision name="collision">
          <geometry><box><size>{size}</size></box></geometry>
        </collision>
        <visual name="visual">
          <geometry><box><size>{size}</size></box></geometry>
          <material><ambient>0.72 0.55 0.33 1</ambient><diffuse>0.72 0.55 0.33 1</diffuse></material>
        </visual>
      </link>
    </model>
""".format(index=index, x=x, y=y, z=BOX_SIDE / 2, yaw=yaw, mass=BOX_MASS, i=inertia, size=size)


def world_text():
    outer = 2 * (HALF_SIDE + WALL_THICKNESS)  # the x walls run the full outer length: the corners are closed
    middle = HALF_SIDE + WALL_THICKNESS / 2
    header = """<?xml version="1.0"?>
<!-- Written by scripts/walled_boxes_world.py (seed {seed}); edit the script, not this file.

  Issue 32's "20 wheelchairs among 200 dynamic boxes in a walled 20 x 20 m world":
    free space inside:  x and y from -{half:g} to {half:g} m, floor at z = 0 (Gazebo's ground plane, mu 1)
    walls:              one static model of four boxes {thick:g} m thick and {height:g} m high, mu 1; the east and
                        west walls run the full outer length, so the corners are closed
    boxes:              {boxes} loose cartons, {side:g} m cubes of {mass:g} kg (Gazebo's default friction, mu 1),
                        at seeded places and headings, centres at least {box_gap:g} m apart and {wall_gap:g} m from the
                        walls, and at least {clear:g} m from the 20 places of `bench --robots 20 --spacing 4`
                        (x in -8, -4, 0, 4, 8; y in -6, -2, 2, 6), which its wheelchairs' 1 m circles cross
-->
<sdf version="1.6">
  <world name="walled_boxes">
    <model name="ground_plane">
      <static>true</static>
      <link name="link">
        <collision name="collision">
          <geometry><plane><normal>0 0 1</normal><size>100 100</size></plane></geometry>
          <surface><friction><ode><mu>1</mu><mu2>1</mu2></ode></friction></surface>
        </collision>
        <visual name="visual">
          <cast_shadows>false</cast_shadows>
          <geometry><plane><normal>0 0 1</normal><size>100 100</size></plane></geometry>
          <material>
            <script><uri>file://media/materials/scripts/gazebo.material</uri><name>Gazebo/Grey</name></script>
          </material>
        </visual>
      </link>
    </model>
    <gravity>0 0 -9.81</gravity>
    <physics type="ode">
      <max_step_size>0.001</max_step_size>
      <real_time_factor>1</real_time_factor>
      <real_time_update_rate>1000</real_time_update_rate>
    </physics>

    <model name="walls">
      <static>true</static>
""".format(seed=SEED, half=HALF_SIDE, thick=WALL_THICKNESS, height=WALL_HEIGHT, boxes=BOXES, side=BOX_SIDE,
           mass=BOX_MASS, box_gap=BOX_GAP, wall_gap=WALL_GAP, clear=ROBOT_CLEARANCE)
    walls = (wall("wall_east", middle, 0, WALL_THICKNESS, outer) + wall("wall_west", -middle, 0, WALL_THICKNESS, outer)
             + wall("wall_north", 0, middle, 2 * HALF_SIDE, WALL_THICKNESS)
             + wall("wall_south", 0, -middle, 2 * HALF_SIDE, WALL_THICKNESS))
    boxes = "".join(box(index, x, y, yaw) for index, (x, y, yaw) in enumerate(box_places()))
    return header + walls + "    </model>\n\n" + boxes + "  </world>\n</sdf>\n"


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--check", action="store_true", help="compare with the committed file, write nothing")
    args = parser.parse_args()
    text = world_text()
    if args.check:
        with open(WORLD) as file:
            if file.read() != text:
                sys.exit("%s differs from what %s writes: run it" % (WORLD, os.path.basename(__file__)))
        return
    with open(WORLD, "w") as file:
        file.write(text)
    print("wrote", WORLD)


if __name__ == "__main__":
    main()
