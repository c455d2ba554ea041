#!/usr/bin/env python3
"""The README's single-robot scenario in MuJoCo and in bullet_sim, side by side in one run (issue 32).

The bench robot (bullet_sim/bench/bench_robot.urdf: 33 kg, drive wheels of r = 0.284 m on a 0.649 m track,
two swivel casters, a 360-beam lidar at 10 Hz, 0.1-12 m) in the bench home (bench_home.world: its walls and
furniture, boxes and cylinders), at rest for 0.5 s, then driving v = 0.5 m/s, w = 0.3 rad/s for 10 s, 1 ms
steps. MuJoCo reads the same URDF; the drive wheels are velocity motors limited to the drive plugin's 30 N m,
the casters turn freely with friction 0.1 as the URDF's <gazebo> blocks say, and the lidar is one mj_multiRay
from the lidar link 10 times a second. bullet_sim is `bench` on the same files (its rtf_physics and
rtf_lidar). The runs alternate, MuJoCo then bullet_sim, --repeat times; the medians and their ratio are
printed as JSON.

Needs mujoco from PyPI (scripts/workspace.sh's install step puts it in /usr/bin/python3) and a built,
sourced workspace (for `rosrun bullet_sim bench`), or --bench. Example:
  single_robot_peers.py --repeat 5
"""
import argparse
import json
import math
import os
import statistics
import subprocess
import time
import xml.etree.ElementTree as ElementTree

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
BENCH_DIR = os.path.dirname(HERE)
ROBOT = os.path.join(BENCH_DIR, "bench_robot.urdf")
HOME = os.path.join(BENCH_DIR, "bench_home.world")

STEP, SETTLE, DURATION = 0.001, 0.5, 10.0
V, W = 0.5, 0.3
RADIUS, TRACK, TORQUE = 0.284, 0.649, 30.0
WHEELS = {"left_wheel_joint": -1, "right_wheel_joint": +1}  # the side of the track each wheel is on
CASTER_FRICTION = 0.1
LIDAR_LINK, LIDAR_BEAMS, LIDAR_RATE, LIDAR_MIN, LIDAR_MAX = "laser_link", 360, 10.0, 0.1, 12.0


def pose_matrix(text):
    """The 4 x 4 transform of an SDF <pose> or a URDF origin: x y z, then roll pitch yaw about fixed axes."""
    import mujoco
    values = [float(v) for v in (text or "0 0 0 0 0 0").split()]
    quat, rotation = np.zeros(4), np.zeros(9)
    mujoco.mju_euler2Quat(quat, np.array(values[3:]), "XYZ")
    mujoco.mju_quat2Mat(rotation, quat)
    matrix = np.eye(4)
    matrix[:3, :3], matrix[:3, 3] = rotation.reshape(3, 3), values[:3]
    return matrix


def home_shapes(path):
    """(kind, size, world transform) of each collision box and cylinder of the world's static models."""
    shapes = []
    for model in ElementTree.parse(path).getroot().iter("model"):
        model_pose = pose_matrix(model.findtext("pose"))
        for link in model.iter("link"):
            link_pose = model_pose @ pose_matrix(link.findtext("pose"))
            for collision in link.iter("collision"):
                pose = link_pose @ pose_matrix(collision.findtext("pose"))
                box, cylinder = collision.find("geometry/box"), collision.find("geometry/cylinder")
                if box is not None:
                    shapes.append(("box", [float(v) / 2 for v in box.findtext("size").split()], pose))
                elif cylinder is not None:
                    size = [float(cylinder.findtext("radius")), float(cylinder.findtext("length")) / 2]
                    shapes.append(("cylinder", size, pose))
    return shapes


def fixed_offset(urdf, link):
    """The transform from the URDF's root link to `link`, up the joints above it (MuJoCo fuses a link fixed to
    its parent into the parent, so the lidar has no body of its own)."""
    joints = {j.find("child").get("link"): j for j in ElementTree.parse(urdf).getroot().iter("joint")}
    offset = np.eye(4)
    while link in joints:
        origin = joints[link].find("origin")
        values = "0 0 0 0 0 0" if origin is None else " ".join(origin.get(a, "0 0 0") for a in ("xyz", "rpy"))
        offset = pose_matrix(values) @ offset
        link = joints[link].find("parent").get("link")
    return offset


def quaternion(rotation):
    import mujoco
    quat = np.zeros(4)
    mujoco.mju_mat2Quat(quat, rotation.ravel())
    return quat


def mujoco_model():
    import mujoco
    spec = mujoco.MjSpec.from_file(ROBOT)
    spec.option.timestep = STEP
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    spec.worldbody.first_body().add_freejoint()
    for body in spec.bodies:
        if "caster" in body.name:
            for geom in body.geoms:
                geom.friction = [CASTER_FRICTION, 0.005, 0.0001]
    spec.worldbody.add_geom(type=mujoco.mjtGeom.mjGEOM_PLANE, size=[50, 50, 1])
    kinds = {"box": mujoco.mjtGeom.mjGEOM_BOX, "cylinder": mujoco.mjtGeom.mjGEOM_CYLINDER}
    for kind, size, pose in home_shapes(HOME):
        spec.worldbody.add_geom(type=kinds[kind], size=size + [0] * (3 - len(size)), pos=pose[:3, 3],
                                quat=quaternion(pose[:3, :3]))
    for joint in WHEELS:
        kv = 200.0  # [N m s]: stiff enough that the motor, not the gain, limits the wheel
        spec.add_actuator(name=joint, target=joint, trntype=mujoco.mjtTrn.mjTRN_JOINT,
                          gaintype=mujoco.mjtGain.mjGAIN_FIXED, biastype=mujoco.mjtBias.mjBIAS_AFFINE,
                          gainprm=[kv] + [0] * 9, biasprm=[0, 0, -kv] + [0] * 7,
                          forcelimited=True, forcerange=[-TORQUE, TORQUE])
    model = spec.compile()
    return mujoco, model


def run_mujoco(lidar):
    """RTF of MuJoCo driving the arc (after the rest, which is not timed), with or without the lidar."""
    mujoco, model = mujoco_model()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    root = 1  # the URDF's root link, with every link fixed to it (the lidar's too)
    lidar_pose = fixed_offset(ROBOT, LIDAR_LINK)
    angles = np.arange(LIDAR_BEAMS) * 2 * math.pi / LIDAR_BEAMS
    local = np.stack([np.cos(angles), np.sin(angles), np.zeros(LIDAR_BEAMS)], axis=1)
    geomid = np.zeros(LIDAR_BEAMS, dtype=np.int32)
    distance = np.zeros(LIDAR_BEAMS)
    for _ in range(int(round(SETTLE / STEP))):
        mujoco.mj_step(model, data)
    for joint, side in WHEELS.items():
        data.actuator(joint).ctrl = (V + side * W * TRACK / 2) / RADIUS
    steps, every = int(round(DURATION / STEP)), int(round(1 / (LIDAR_RATE * STEP)))
    hits = 0
    start = time.perf_counter()
    for i in range(steps):
        mujoco.mj_step(model, data)
        if lidar and i % every == 0:
            rotation = data.xmat[root].reshape(3, 3)
            origin = data.xpos[root] + rotation @ lidar_pose[:3, 3]
            directions = (rotation @ lidar_pose[:3, :3] @ local.T).T.ravel()
            mujoco.mj_multiRay(model, data, origin, directions, None, True, root, geomid, distance, None,
                               LIDAR_BEAMS, LIDAR_MAX)
            hits += int(np.count_nonzero((distance >= LIDAR_MIN) & (distance <= LIDAR_MAX)))
    wall = time.perf_counter() - start
    return {"rtf": DURATION / wall, "x": float(data.xpos[root][0]), "y": float(data.xpos[root][1]),
            "lidar_hits_per_scan": hits / math.ceil(steps / every) if lidar else None}


def run_ours(bench):
    """bullet_sim's bench on the same robot and world: its physics-only and lidar RTFs."""
    command = bench + ["--robot", ROBOT, "--world", HOME, "--duration", str(DURATION),
                       "--cmd", "%g,%g" % (V, W), "--repeat", "1"]
    out = subprocess.run(command, check=True, capture_output=True, text=True).stdout
    figures = json.loads(out)
    return {"rtf_physics": figures["rtf_physics"], "rtf_lidar": figures["rtf_lidar"]}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--repeat", type=int, default=5, help="alternating runs of each engine (default 5)")
    parser.add_argument("--bench", help="bullet_sim's bench binary (default: rosrun bullet_sim bench)")
    args = parser.parse_args()
    bench = [args.bench] if args.bench else ["rosrun", "bullet_sim", "bench"]
    runs = {"mujoco_physics": [], "mujoco_lidar": [], "ours_physics": [], "ours_lidar": []}
    last = {}
    for _ in range(args.repeat):
        physics, lidar = run_mujoco(False), run_mujoco(True)
        runs["mujoco_physics"].append(physics["rtf"])
        runs["mujoco_lidar"].append(lidar["rtf"])
        ours = run_ours(bench)
        runs["ours_physics"].append(ours["rtf_physics"])
        runs["ours_lidar"].append(ours["rtf_lidar"])
        last = lidar
    import mujoco
    medians = {name: statistics.median(values) for name, values in runs.items()}
    print(json.dumps({
        "mujoco": mujoco.__version__, "step_s": STEP, "duration_s": DURATION, "cmd": [V, W],
        "repeat": args.repeat,
        "median_rtf": medians,
        "ours_over_mujoco": {"physics": medians["ours_physics"] / medians["mujoco_physics"],
                             "lidar": medians["ours_lidar"] / medians["mujoco_lidar"]},
        "ours_lidar_over_physics": medians["ours_lidar"] / medians["ours_physics"],
        "mujoco_end_xy": [last["x"], last["y"]], "mujoco_lidar_hits_per_scan": last["lidar_hits_per_scan"],
        "runs": runs}, indent=2))


if __name__ == "__main__":
    main()
