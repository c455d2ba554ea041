#!/usr/bin/env python3
"""Generate the robots' visual meshes (binary STL) from the seeds' dimensions, and the meshes of the stock
models bullet_sim ships (bullet_sim/models) from their published sizes.

We have no CAD files. Wheels take their radius and width from the collision cylinders of the expanded URDF,
so each figure stays written once, in the xacro; the rest (seat, frame, brackets) are design sizes for
looks only. Every mesh is written in the frame of the <visual> that uses it.

Usage: scripts/generate_meshes.py            (run after changing a description; commit the meshes)
Needs: xacro (PyPI's, see scripts/workspace.sh) and numpy on /usr/bin/python3.
"""
import os
import struct
import subprocess
import xml.etree.ElementTree as ET

import numpy as np

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SEGMENTS = 48


def rpy_matrix(roll, pitch, yaw):
    """URDF rpy: fixed-axis roll about x, then pitch about y, then yaw about z."""
    cr, sr, cp, sp, cy, sy = np.cos(roll), np.sin(roll), np.cos(pitch), np.sin(pitch), np.cos(yaw), np.sin(yaw)
    rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    return rz @ ry @ rx


def frame_for_axis(axis):
    """A rotation whose z column is the unit vector `axis`."""
    z = np.asarray(axis, float) / np.linalg.norm(axis)
    helper = np.array([1.0, 0, 0]) if abs(z[0]) < 0.9 else np.array([0, 1.0, 0])
    x = np.cross(helper, z)
    x /= np.linalg.norm(x)
    return np.column_stack([x, np.cross(z, x), z])


class Mesh:
    def __init__(self):
        self.triangles = []

    def add(self, triangles):
        self.triangles.extend(triangles)
        return self

    def write(self, path):
        tris = np.asarray(self.triangles, float)
        normals = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
        lengths = np.linalg.norm(normals, axis=1)
        keep = lengths > 1e-12  # the poles of a revolved profile give zero-area triangles
        tris, normals = tris[keep], normals[keep] / lengths[keep, None]
        with open(path, "wb") as f:
            f.write(b"bullet_sim generated mesh".ljust(80, b" "))
            f.write(struct.pack("<I", len(tris)))
            for n, (a, b, c) in zip(normals, tris):
                f.write(struct.pack("<12fH", *n, *a, *b, *c, 0))
        print(f"{os.path.relpath(path, REPO)}: {len(tris)} triangles")


def box(center, size, rotation=np.eye(3)):
    h = np.asarray(size, float) / 2
    corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]) * h
    v = corners @ np.asarray(rotation).T + center
    faces = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    tris = []
    for a, b, c, d in faces:
        tris += [(v[a], v[b], v[c]), (v[a], v[c], v[d])]
    return tris


def frustum(xs, bottom, top):
    """A block from x = xs[0] to xs[1] whose cross-section narrows from (width, z) `bottom` to `top`."""
    (w0, z0), (w1, z1) = bottom, top
    v = np.array([[x, s * w / 2, z] for x in xs for s in (-1, 1) for w, z in ((w0, z0), (w1, z1))])
    faces = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    tris = []
    for a, b, c, d in faces:
        tris += [(v[a], v[b], v[c]), (v[a], v[c], v[d])]
    return tris


def revolve(profile, center=(0, 0, 0), axis=(0, 0, 1), segments=SEGMENTS):
    """Surface of revolution of a closed (r, z) profile, listed counter-clockwise in the r-z plane."""
    rot = frame_for_axis(axis)
    center = np.asarray(center, float)
    angles = np.linspace(0, 2 * np.pi, segments + 1)
    rings = [[center + rot @ np.array([r * np.cos(t), r * np.sin(t), z]) for t in angles] for r, z in profile]
    tris = []
    n = len(profile)
    for i in range(n):
        a, b = rings[i], rings[(i + 1) % n]
        for k in range(segments):
            tris += [(a[k], b[k + 1], b[k]), (a[k], a[k + 1], b[k + 1])]
    return tris


def cylinder(center, axis, radius, length, inner_radius=0.0):
    h = length / 2
    if inner_radius > 0:
        profile = [(inner_radius, h), (inner_radius, -h), (radius, -h), (radius, h)]
    else:
        profile = [(0, h), (0, -h), (radius, -h), (radius, h)]
    return revolve(profile, center, axis)


def rod(p0, p1, radius):
    p0, p1 = np.asarray(p0, float), np.asarray(p1, float)
    return cylinder((p0 + p1) / 2, p1 - p0, radius, np.linalg.norm(p1 - p0))


def tyre(radius, width, center=(0, 0, 0), axis=(0, 0, 1), section=None):
    """A tyre of outer `radius` and `width` around `axis`: a torus-like ring with a flat tread."""
    section = section or width / 2
    ts = np.linspace(-np.pi / 2, np.pi / 2, 9)
    outer = [(radius - section + section * np.cos(t), (width / 2) * np.sin(t)) for t in ts]
    inner = [(radius - 2 * section, width / 2 * 0.8), (radius - 2 * section, -width / 2 * 0.8)]
    return revolve(outer + inner, center, axis)


def wheel(radius, width, spokes=0, hub_ratio=0.25):
    """A wheel around z: tyre, rim disc and hub; with spokes, an open rim instead of a disc."""
    section = min(width / 2, radius * 0.12)
    mesh = tyre(radius, width, section=section)
    rim = radius - 2 * section
    if spokes:
        mesh += cylinder((0, 0, 0), (0, 0, 1), rim, width * 0.5, inner_radius=rim * 0.92)
        for k in range(spokes):
            t = 2 * np.pi * k / spokes
            mesh += rod((0, 0, 0), (rim * np.cos(t), rim * np.sin(t), 0), radius * 0.012)
    else:
        mesh += cylinder((0, 0, 0), (0, 0, 1), rim, width * 0.4)
    mesh += cylinder((0, 0, 0), (0, 0, 1), radius * hub_ratio * 0.5, width * 1.1)
    return mesh


def expand(package, robot, *args):
    env = dict(os.environ, ROS_PACKAGE_PATH=REPO)
    path = os.path.join(REPO, package, "urdf", robot + ".urdf.xacro")
    xacro = os.path.join(REPO, "xacro", "xacro")  # Noetic's dialect, the one launch files run
    return ET.fromstring(subprocess.check_output([xacro, path, *args], env=env))


def collision_cylinder(urdf, link):
    cyl = urdf.find(f"./link[@name='{link}']/collision/geometry/cylinder")
    return float(cyl.get("radius")), float(cyl.get("length"))


def floats(text):
    return np.array([float(v) for v in text.split()])


def out(package, name):
    return os.path.join(REPO, package, "meshes", name)


def wheelchair():
    pkg = "smartwheelchair_model"
    urdf = expand(pkg, "smartwheelchair_model")
    cy = 0.00295  # the chair's centre line (base_link y of the drive axle centre)

    chair = []
    chair += box((-0.1, cy, -0.21), (0.56, 0.36, 0.18))  # battery and motor box under the seat
    chair += box((-0.065, cy, -0.085), (0.53, 0.46, 0.07))  # seat cushion
    chair += box((-0.35, cy, 0.19), (0.06, 0.44, 0.50))  # backrest
    for side in (-1, 1):
        y = cy + side * 0.25
        chair += box((-0.08, y, 0.14), (0.44, 0.06, 0.04))  # armrest
        chair += rod((-0.26, y, -0.12), (-0.26, y, 0.12), 0.012)
        chair += rod((0.10, y, -0.12), (0.10, y, 0.12), 0.012)
        chair += rod((0.18, cy + side * 0.15, -0.12), (0.46, cy + side * 0.15, -0.50), 0.014)  # footrest hanger
        chair += rod((-0.36, cy + side * 0.2, 0.44), (-0.42, cy + side * 0.2, 0.52), 0.013)  # push handle
        chair += rod((0.125, cy + side * 0.18, -0.25), (0.125, cy + side * 0.29, -0.32), 0.02)  # axle mount
        chair += rod((-0.38, cy + side * 0.18, -0.24), (-0.40, cy + side * 0.26, -0.20), 0.015)  # caster mount
    chair += box((0.48, cy, -0.515), (0.16, 0.36, 0.02))  # footrest plate
    Mesh().add(chair).write(out(pkg, "base_link.stl"))

    r, w = collision_cylinder(urdf, "front_left_link")
    Mesh().add(wheel(r, w, spokes=12)).write(out(pkg, "drive_wheel.stl"))
    r, w = collision_cylinder(urdf, "wheel_rear_left_link")
    Mesh().add(wheel(r, w, hub_ratio=0.4)).write(out(pkg, "caster_wheel.stl"))

    # Fork, in the swivel link's frame (its +y is up): stem on the swivel axis, prongs to the wheel axle.
    for side in ("left", "right"):
        joint = urdf.find(f"./joint[@name='wheel_rear_{side}_joint']")
        axle = floats(joint.find("origin").get("xyz"))
        axis = rpy_matrix(*floats(joint.find("origin").get("rpy"))) @ floats(joint.find("axis").get("xyz"))
        axis /= np.linalg.norm(axis)
        half = w / 2 + 0.015
        top = np.array([0.0, -0.05, 0.0])
        fork = rod((0, 0.03, 0), top, 0.016)
        fork += rod(top - axis * half, top + axis * half, 0.012)
        for s in (-1, 1):
            fork += rod(top + s * axis * half, axle + s * axis * half, 0.01)
        Mesh().add(fork).write(out(pkg, f"caster_fork_{side}.stl"))

    # Lidar puck with its bracket to the backrest, in laser_Link's frame (the scan plane is z = 0).
    lidar = cylinder((0, 0, -0.015), (0, 0, 1), 0.038, 0.04)
    lidar += cylinder((0, 0, 0.0125), (0, 0, 1), 0.03, 0.015)
    lidar += rod((0, 0, -0.035), (0, 0, -0.09), 0.012)
    lidar += rod((0, 0, -0.09), (0.08, 0, -0.09), 0.012)
    Mesh().add(lidar).write(out(pkg, "laser_Link.stl"))


def smartcar():
    pkg = "smartcar_description"
    urdf = expand(pkg, "smartcar")
    size = floats(urdf.find("./link[@name='base_link']/collision/geometry/box").get("size"))
    body = box((0, 0, 0), size)
    body += box((size[0] / 2 + 0.005, 0, -size[2] / 4), (0.01, size[1] * 0.9, size[2] / 2))  # bumper
    Mesh().add(body).write(out(pkg, "body.stl"))

    r, w = collision_cylinder(urdf, "left_front_wheel")
    Mesh().add(wheel(r, w)).write(out(pkg, "wheel.stl"))

    head = floats(urdf.find("./link[@name='head']/collision/geometry/box").get("size"))
    mesh = box((0, 0, 0), head)
    mesh += cylinder((0, 0, head[2] / 2 + 0.005), (0, 0, 1), 0.012, 0.01)  # lidar window on top
    Mesh().add(mesh).write(out(pkg, "head.stl"))


def yahboomcar():
    pkg = "yahboomcar_description"
    urdf = expand(pkg, "yahboomcar")
    collision = urdf.find("./link[@name='base_link']/collision")
    size = floats(collision.find("geometry/box").get("size"))
    chassis = box(floats(collision.find("origin").get("xyz")), size)
    chassis += box((-0.02, 0, 0.0425), (0.10, 0.08, 0.003))  # upper deck carrying the lidar
    for x in (-0.06, 0.02):
        for y in (-0.032, 0.032):
            chassis += rod((x, y, 0.015), (x, y, 0.041), 0.003)
    chassis += box((-0.045, 0, 0.022), (0.05, 0.06, 0.014))  # battery
    Mesh().add(chassis).write(out(pkg, "base_link.stl"))

    r, w = collision_cylinder(urdf, "zq_Link")
    Mesh().add(wheel(r, w, hub_ratio=0.3)).write(out(pkg, "wheel.stl"))

    Mesh().add(box((-0.03, 0, 0), (0.03, 0.025, 0.003))).write(out(pkg, "imu_Link.stl"))

    lidar_r, lidar_h = collision_cylinder(urdf, "radar_Link")
    lidar = cylinder((0, 0, -0.0175), (0, 0, 1), lidar_r, lidar_h)
    lidar += cylinder((0, 0, 0.003), (0, 0, 1), 0.75 * lidar_r, 0.011)
    Mesh().add(lidar).write(out(pkg, "radar_Link.stl"))

    bracket = box((0.008, 0, 0.004), (0.025, 0.03, 0.008))
    for y in (-0.013, 0.013):
        bracket += box((0.017, y, 0.016), (0.006, 0.003, 0.024))
    Mesh().add(bracket).write(out(pkg, "jq1_Link.stl"))

    camera = box((0.012, 0, 0.003), (0.016, 0.022, 0.02))
    camera += cylinder((0.023, 0, 0.003), (1, 0, 0), 0.006, 0.008)
    Mesh().add(camera).write(out(pkg, "jq2_Link.stl"))


def tianracer():
    pkg = "tianracer_description"
    urdf = expand(pkg, "tianracer")

    # The body, in the chassis visual's frame (the middle of the collision box, halfway between the axles):
    # a floor pan between the wheels, a cabin that narrows upwards, a low nose, a tail and a rear wing.
    size = floats(urdf.find("./link[@name='chassis']/collision/geometry/box").get("size"))
    centre = floats(urdf.find("./link[@name='chassis']/visual/origin").get("xyz"))
    front = floats(urdf.find("./joint[@name='left_steering_hinge_joint']/origin").get("xyz"))
    rear = floats(urdf.find("./joint[@name='left_rear_wheel_joint']/origin").get("xyz"))
    r, w = collision_cylinder(urdf, "left_rear_wheel")
    length, width, height = size
    axle = (front[0] - rear[0]) / 2  # the axles are at x = -axle and +axle
    inner = rear[1] - w / 2 - 0.004  # the wheels' inner faces, less a gap
    bottom, top = -height / 2, height / 2
    body = box((0, 0, bottom + 0.003), (length, 2 * inner, 0.006))  # floor pan
    cabin = axle - r - 0.006
    body += frustum((-cabin, cabin), (width, bottom + 0.006), (0.6 * width, top))
    body += frustum((cabin, length / 2 - 0.012), (1.2 * inner, bottom + 0.006), (0.6 * inner, bottom + 0.5 * height))
    body += frustum((-length / 2 + 0.01, -cabin), (1.4 * inner, bottom + 0.006), (inner, top - 0.01))
    body += box((length / 2 - 0.006, 0, bottom + 0.012), (0.012, width * 0.8, 0.012))  # front bumper
    for y in (-0.35 * inner, 0.35 * inner):
        body += box((-length / 2 + 0.03, y, top + 0.01), (0.01, 0.004, 0.02))  # wing posts
    body += box((-length / 2 + 0.03, 0, top + 0.02), (0.045, width, 0.003))  # rear wing
    Mesh().add(body).write(out(pkg, "chassis.stl"))

    Mesh().add(wheel(r, w, spokes=6, hub_ratio=0.3)).write(out(pkg, "wheel.stl"))

    # Steering knuckle around its kingpin (the hinge's z axis).
    knuckle = floats(urdf.find("./link[@name='left_steering_hinge']/collision/geometry/box").get("size"))
    mesh = box((0, 0, 0), knuckle)
    mesh += rod((0, 0, -knuckle[2] / 2 - 0.004), (0, 0, knuckle[2] / 2 + 0.004), 0.003)
    Mesh().add(mesh).write(out(pkg, "steering_hinge.stl"))

    # Lidar puck in its frame (the scan plane is z = 0): a base and a turning head.
    lidar_r, lidar_h = collision_cylinder(urdf, "laser")
    lidar = cylinder((0, 0, -lidar_h / 4), (0, 0, 1), lidar_r, lidar_h / 2)
    lidar += cylinder((0, 0, lidar_h / 4), (0, 0, 1), 0.8 * lidar_r, lidar_h / 2)
    Mesh().add(lidar).write(out(pkg, "laser.stl"))


def construction_cone():
    """Gazebo's construction_cone above its 0.066 m foot: from radius 0.194 m to 0.052 m at 1.082 m."""
    foot, top = 0.066, 1.082
    profile = [(0, top), (0, foot), (0.194, foot), (0.052, top)]
    path = os.path.join(REPO, "bullet_sim", "models", "construction_cone", "meshes", "construction_cone.stl")
    Mesh().add(revolve(profile)).write(path)


if __name__ == "__main__":
    construction_cone()
    wheelchair()
    smartcar()
    yahboomcar()
    tianracer()
