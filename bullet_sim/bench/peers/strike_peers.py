#!/usr/bin/env python3
"""One robot's wall strike (issue 28's matrix cell) in MuJoCo and in PyBullet, from the same URDF.

The robot starts at rest heading +x; a static wall (0.1 m thick, 2.5 m tall, mu 1, Gazebo's default) stands
turned by --angle from square, its near face --gap ahead of the robot's front. The named wheel joints are
velocity motors at speed / radius, limited to --torque (gazebo_ros_skid_steer_drive's <torque>); the other
joints hold their zero position. The command runs until 1 s after the first contact, then 0.5 s more is
watched. Printed per engine, as bench --strikes prints a cell: the largest tilt, the root's rise, its path
(sampled every 50 ms) and the time the tilt passed 90 degrees.

Needs mujoco and pybullet from PyPI (scripts/workspace.sh's install step puts them in /usr/bin/python3).
Example, the Yahboom car:
  xacro yahboomcar_description/urdf/yahboomcar.urdf.xacro > /tmp/yahboom.urdf
  strike_peers.py /tmp/yahboom.urdf --wheels zq_Joint yq_Joint zh_Joint yh_Joint --radius 0.02875 --angle 30
"""
import argparse
import contextlib
import importlib.metadata
import json
import math
import os
import sys

import numpy as np

WALL_THICKNESS, WALL_HEIGHT, WALL_LENGTH = 0.1, 2.5, 6.0
MU = 1.0
SAMPLE_PERIOD, AFTER_CONTACT, WATCH_AFTER = 0.05, 1.0, 0.5


def wall_pose(args, low, high):
    """Centre and yaw of the wall turned by --angle whose near face the robot's bounding box (x, y from `low`
    to `high`) meets after travelling --gap along +x."""
    yaw = math.radians(args.angle)
    normal = np.array([math.cos(yaw), math.sin(yaw)])
    corners = [np.array([x, y]) for x in (low[0], high[0]) for y in (low[1], high[1])]
    near = max(normal @ c for c in corners) + args.gap * normal[0]  # the face is {p : normal . p = near}
    centre = (near + WALL_THICKNESS / 2) * normal
    return np.array([centre[0], centre[1], WALL_HEIGHT / 2]), yaw


class Record:
    """The figures of one run, from the root link's pose sampled every 50 ms."""

    def __init__(self, start_z):
        self.start_z, self.max_tilt, self.rise, self.path = start_z, 0.0, 0.0, 0.0
        self.last, self.over_at, self.contact_at = None, None, None

    def sample(self, t, position, up_z):
        tilt = math.acos(max(-1.0, min(1.0, up_z)))
        self.max_tilt = max(self.max_tilt, tilt)
        self.rise = max(self.rise, position[2] - self.start_z)
        if self.last is not None:
            self.path += float(np.linalg.norm(np.asarray(position) - self.last))
        self.last = np.asarray(position, dtype=float)
        if self.over_at is None and tilt > math.pi / 2:
            self.over_at = t

    def report(self, engine):
        return {"engine": engine, "max_tilt_rad": round(self.max_tilt, 3), "root_rise_m": round(self.rise, 4),
                "path_m": round(self.path, 3), "first_contact_s": self.contact_at,
                "turned_over_at_s": None if self.over_at is None else round(self.over_at, 2)}


def run_mujoco(args):
    import mujoco
    spec = mujoco.MjSpec.from_file(args.urdf)
    spec.option.timestep = args.step
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST  # the stiff velocity motors, as Gazebo's
    root = spec.worldbody.first_body()
    root.add_freejoint()
    for geom in spec.geoms:
        geom.friction = [MU, 0.005, 0.0001]
    spec.worldbody.add_geom(type=mujoco.mjtGeom.mjGEOM_PLANE, size=[50, 50, 1], friction=[MU, 0.005, 0.0001])
    for joint in spec.joints:
        if joint.name in args.wheels:
            spec.add_actuator(name=joint.name, target=joint.name, trntype=mujoco.mjtTrn.mjTRN_JOINT,
                              gaintype=mujoco.mjtGain.mjGAIN_FIXED, biastype=mujoco.mjtBias.mjBIAS_AFFINE,
                              gainprm=[args.kv] + [0] * 9, biasprm=[0, 0, -args.kv] + [0] * 7,
                              forcelimited=True, forcerange=[-args.torque, args.torque])
        elif joint.type != mujoco.mjtJoint.mjJNT_FREE:
            spec.add_actuator(name=joint.name, target=joint.name, trntype=mujoco.mjtTrn.mjTRN_JOINT,
                              gaintype=mujoco.mjtGain.mjGAIN_FIXED, biastype=mujoco.mjtBias.mjBIAS_AFFINE,
                              gainprm=[50] + [0] * 9, biasprm=[0, -50, -1] + [0] * 7)
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    robot_geoms = [g for g in range(model.ngeom) if model.geom_bodyid[g] > 0]
    data.qpos[2] -= min(data.geom_xpos[g][2] - model.geom_rbound[g] for g in robot_geoms)  # on the ground
    mujoco.mj_forward(model, data)
    settle(lambda _: mujoco.mj_step(model, data), args.step)
    low = np.min([data.geom_xpos[g] - model.geom_rbound[g] for g in robot_geoms], axis=0)
    high = np.max([data.geom_xpos[g] + model.geom_rbound[g] for g in robot_geoms], axis=0)
    centre, yaw = wall_pose(args, low, high)
    # The wall joins the settled robot: the spec is compiled again and the settled state copied over.
    wall = spec.worldbody.add_body(name="wall", pos=centre, quat=[math.cos(yaw / 2), 0, 0, math.sin(yaw / 2)])
    wall.add_geom(name="wall", type=mujoco.mjtGeom.mjGEOM_BOX, friction=[MU, 0.005, 0.0001],
                  size=[WALL_THICKNESS / 2, WALL_LENGTH / 2, WALL_HEIGHT / 2])
    qpos, qvel = data.qpos.copy(), data.qvel.copy()
    model = spec.compile()
    data = mujoco.MjData(model)
    data.qpos[:], data.qvel[:] = qpos, qvel
    mujoco.mj_forward(model, data)
    wall_geom = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, "wall")  # fused into the world body
    body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, root.name)
    record = Record(data.xpos[body][2])
    wheel_speed = args.speed / args.radius

    def touching():
        return bool((data.contact.geom[:data.ncon] == wall_geom).any())

    def drive(command):
        for i in range(model.nu):
            name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_ACTUATOR, i)
            data.ctrl[i] = command if name in args.wheels else 0.0

    run(args, lambda: data.time, lambda c: (drive(c), mujoco.mj_step(model, data)), touching,
        lambda: (data.xpos[body].copy(), data.xmat[body][8]), record, wheel_speed)
    return record.report("mujoco " + mujoco.__version__)


def run_pybullet(args):
    import pybullet as p
    client = p.connect(p.DIRECT)
    p.setGravity(0, 0, -9.81, physicsClientId=client)
    p.setTimeStep(args.step, physicsClientId=client)
    plane = p.createMultiBody(0, p.createCollisionShape(p.GEOM_PLANE, physicsClientId=client), physicsClientId=client)
    with quiet_stdout():  # PyBullet prints each merged link
        robot = p.loadURDF(args.urdf, [0, 0, 0], flags=p.URDF_MERGE_FIXED_LINKS, physicsClientId=client)
    for link in [-1] + list(range(p.getNumJoints(robot, physicsClientId=client))):
        p.changeDynamics(robot, link, lateralFriction=MU, physicsClientId=client)
    p.changeDynamics(plane, -1, lateralFriction=MU, physicsClientId=client)
    low, _ = aabb(p, robot, client)  # on the ground, as a spawn on it puts the robot
    position, orientation = p.getBasePositionAndOrientation(robot, physicsClientId=client)
    p.resetBasePositionAndOrientation(robot, [position[0], position[1], position[2] - low[2]], orientation,
                                      physicsClientId=client)
    joints = {p.getJointInfo(robot, j, physicsClientId=client)[1].decode(): j
              for j in range(p.getNumJoints(robot, physicsClientId=client))}
    wheels = [joints[name] for name in args.wheels]

    def drive(command):
        for name, j in joints.items():
            if j in wheels:
                p.setJointMotorControl2(robot, j, p.VELOCITY_CONTROL, targetVelocity=command, force=args.torque,
                                        physicsClientId=client)
            else:
                p.setJointMotorControl2(robot, j, p.POSITION_CONTROL, targetPosition=0, force=1.0,
                                        physicsClientId=client)
        p.stepSimulation(physicsClientId=client)

    clock = [0.0]

    def step(command):
        drive(command)
        clock[0] += args.step

    settle(step, args.step)
    low, high = aabb(p, robot, client)
    centre, yaw = wall_pose(args, low, high)
    box = p.createCollisionShape(p.GEOM_BOX, halfExtents=[WALL_THICKNESS / 2, WALL_LENGTH / 2, WALL_HEIGHT / 2],
                                 physicsClientId=client)
    wall = p.createMultiBody(0, box, basePosition=centre.tolist(),
                             baseOrientation=p.getQuaternionFromEuler([0, 0, yaw]), physicsClientId=client)
    p.changeDynamics(wall, -1, lateralFriction=MU, physicsClientId=client)

    def pose():
        position, orientation = p.getBasePositionAndOrientation(robot, physicsClientId=client)
        return np.array(position), p.getMatrixFromQuaternion(orientation)[8]

    record = Record(pose()[0][2])
    run(args, lambda: clock[0], step, lambda: bool(p.getContactPoints(robot, wall, physicsClientId=client)),
        pose, record, args.speed / args.radius)
    p.disconnect(physicsClientId=client)
    return record.report("pybullet " + importlib.metadata.version("pybullet"))


def aabb(p, body, client):
    links = range(-1, p.getNumJoints(body, physicsClientId=client))
    boxes = [p.getAABB(body, link, physicsClientId=client) for link in links]
    return np.min([b[0] for b in boxes], axis=0), np.max([b[1] for b in boxes], axis=0)


@contextlib.contextmanager
def quiet_stdout():
    sys.stdout.flush()
    saved = os.dup(1)
    with open(os.devnull, "w") as devnull:
        os.dup2(devnull.fileno(), 1)
        try:
            yield
        finally:
            os.dup2(saved, 1)
            os.close(saved)


def settle(step, dt, seconds=0.3):
    for _ in range(int(round(seconds / dt))):
        step(0.0)


def run(args, now, step, touching, pose, record, wheel_speed, longest=20.0):
    """Drives in until 1 s after the first contact, watches 0.5 s more, sampling the root every 50 ms."""
    start = now()
    next_sample, stop = start, None
    while now() - start < longest:
        t = now() - start
        if record.contact_at is None and touching():
            record.contact_at = round(t, 3)
            stop = t + AFTER_CONTACT
        if stop is not None and t > stop + WATCH_AFTER:
            break
        step(0.0 if stop is not None and t > stop else wheel_speed)
        if now() >= next_sample:
            position, up_z = pose()
            record.sample(t, position, up_z)
            next_sample += SAMPLE_PERIOD


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("urdf")
    parser.add_argument("--wheels", nargs="+", required=True, help="the driven wheels' joints")
    parser.add_argument("--radius", type=float, required=True, help="[m] of the wheels")
    parser.add_argument("--torque", type=float, default=0.5, help="[N m] per wheel")
    parser.add_argument("--speed", type=float, default=0.5, help="[m/s]")
    parser.add_argument("--angle", type=float, default=0.0, help="[deg] of the wall from square")
    parser.add_argument("--gap", type=float, default=0.3, help="[m] from the robot's front to the wall")
    parser.add_argument("--step", type=float, default=0.001, help="[s]")
    parser.add_argument("--kv", type=float, default=10.0, help="[N m s] MuJoCo's velocity motor gain")
    parser.add_argument("--engines", nargs="+", default=["mujoco", "pybullet"], choices=["mujoco", "pybullet"])
    args = parser.parse_args()
    runs = {"mujoco": run_mujoco, "pybullet": run_pybullet}
    print(json.dumps([runs[engine](args) for engine in args.engines], indent=1))


if __name__ == "__main__":
    sys.exit(main())
