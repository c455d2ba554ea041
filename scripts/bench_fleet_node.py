#!/usr/bin/env python3
"""Measures issue 32's fleet figures through the node, as a user meets them, and writes docs/performance.md's
section "Through the node" and the README's lines under the fleet table (between <!-- bench-fleet-node:begin -->
and <!-- bench-fleet-node:end -->):

- driving, measured first (the spawns leave the machine loaded): `multi_robot.launch count:=D
  real_time_factor:=0 spacing:=3`, every robot sent v 0.3 m/s, w 0.3 rad/s at 10 Hz of sim time by one driver
  (this process), RTF over a window, the CPU of each kind of process, and how far each robot went; the same
  robots spawned through the node's service, without robot_state_publishers;
- a scenario with `count: N` (the wheelchair, N poses on the same grid, 0.1 s of sim time, `upright`): from
  `rosrun bullet_sim scenario` to its result, and its peak RSS;
- spawning: `roslaunch bullet_sim_bringup multi_robot.launch count:=N` (its own master on --port), from the
  launch to the moment /gazebo/get_world_properties lists all N robots and N robot_state_publishers run, the
  median of --repeat launches; after the last, the simulator's peak RSS, and for a window the CPU each kind of
  process takes while the fleet stands at real time (see the page for what the others' share is).

    source devel/setup.bash && /usr/bin/python3 scripts/bench_fleet_node.py [--spawn 100] [--repeat 5]
        [--drive 10] [--window 30] [--port 11411] [--out DIR] [--no-page]
    /usr/bin/python3 scripts/bench_fleet_node.py --from-json DIR/bench_fleet_node.json   # the page again

Takes about 5 minutes. Prints the lines; the JSON goes to DIR.
"""
import argparse
import datetime
import json
import math
import os
import resource
import signal
import subprocess
import sys
import tempfile
import time

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_machine import cpu_model, load_average  # noqa: E402
from readme_section import met, write_section  # noqa: E402

PAGE = os.path.join(REPO, "docs", "performance.md")
README = os.path.join(REPO, "README.md")
TARGET_SPAWN_S = 20
TARGET_RSS_MB = 1024
TARGET_RTF_10 = 100
SPAWN_LIMIT_S = 120  # a bound on every wait for the fleet
CPU_KINDS = {"simulator": "lib/bullet_sim/simulator", "rosmaster": "bin/rosmaster",
             "robot_state_publishers": "robot_state_publisher/robot_state_publisher", "roslaunch": "bin/roslaunch"}
WHEELCHAIR = ("smartwheelchair_model", "urdf/smartwheelchair_model.urdf.xacro")  # package, path in it


def pids(pattern):
    found = subprocess.run(["pgrep", "-f", pattern], stdout=subprocess.PIPE, universal_newlines=True).stdout
    return [int(pid) for pid in found.split()]


def cpu_seconds(pattern):
    """User and system time of every running process whose command line holds `pattern`."""
    total = 0.0
    for pid in pids(pattern):
        try:
            with open("/proc/%d/stat" % pid) as stat:
                fields = stat.read().rsplit(")", 1)[1].split()
        except OSError:
            continue  # it ended meanwhile
        total += (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")
    return total


def cpu_by_kind():
    return {kind: cpu_seconds(pattern) for kind, pattern in CPU_KINDS.items()}


def peak_rss_mb(pattern):
    for pid in pids(pattern):
        with open("/proc/%d/status" % pid) as status:
            for line in status:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) / 1024
    raise RuntimeError("no process matches %s" % pattern)


class Launch:
    """roslaunch in a session of its own, stopped as Ctrl-C would stop it."""

    def __init__(self, arguments, launch_file=("bullet_sim_bringup", "multi_robot.launch")):
        command = ["roslaunch"] + list(launch_file) + arguments
        print("==", " ".join(command), file=sys.stderr)
        self.process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                        start_new_session=True)

    def stop(self):
        os.killpg(self.process.pid, signal.SIGINT)
        try:
            self.process.wait(timeout=60)
        except subprocess.TimeoutExpired:
            os.killpg(self.process.pid, signal.SIGKILL)
            self.process.wait()


def robots_in_world():
    import rospy
    from gazebo_msgs.srv import GetWorldProperties
    try:
        rospy.wait_for_service("/gazebo/get_world_properties", timeout=1)
        names = rospy.ServiceProxy("/gazebo/get_world_properties", GetWorldProperties)().model_names
    except (rospy.ROSException, rospy.ServiceException):
        return []  # not up yet
    return [name for name in names if name.startswith("robot")]


def wait_for_fleet(count, started):
    """Seconds from `started` until the world holds `count` robots and as many robot_state_publishers run."""
    while time.monotonic() - started < SPAWN_LIMIT_S:
        if len(robots_in_world()) >= count and len(pids(CPU_KINDS["robot_state_publishers"])) >= count:
            return time.monotonic() - started
        time.sleep(0.2)  # polling the world, a bounded wait
    raise RuntimeError("the fleet of %d was not up after %d s" % (count, SPAWN_LIMIT_S))


def own_cpu_seconds():
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def cpu_over(window, sim_clock=None, own_kind=None):
    """Each kind's share of a core over `window` s of wall time (this process's under `own_kind`, when given),
    and the RTF when a clock is given."""
    def sample():
        cpu = cpu_by_kind()
        if own_kind:
            cpu[own_kind] = own_cpu_seconds()
        return cpu, sim_clock() if sim_clock else 0, time.monotonic()
    before, sim_before, wall_before = sample()
    time.sleep(window)  # the measuring window
    after, sim_after, wall_after = sample()
    wall = wall_after - wall_before
    shares = {kind: (after[kind] - before[kind]) / wall for kind in after}
    return shares, (sim_after - sim_before) / wall


def spawn_once(count, window=0):
    """Seconds to bring the fleet up; with a window, also its peak RSS and where the cores go while it stands."""
    started = time.monotonic()
    launch = Launch(["count:=%d" % count])
    try:
        figures = {"spawn_s": wait_for_fleet(count, started)}
        if window:
            figures["peak_rss_mb"] = peak_rss_mb(CPU_KINDS["simulator"])
            figures["standing_cpu_shares"], _ = cpu_over(window)
    finally:
        launch.stop()
    return figures


def measure_spawn(count, window, repeat):
    """The last of `repeat` launches also stands for `window` s; the spawn's median and range over all."""
    runs = [spawn_once(count) for _ in range(repeat - 1)] + [spawn_once(count, window)]
    seconds = sorted(run["spawn_s"] for run in runs)
    return {"count": count, "spawn_s": seconds[len(seconds) // 2], "spawn_s_all": seconds,
            "peak_rss_mb": runs[-1]["peak_rss_mb"], "standing_cpu_shares": runs[-1]["standing_cpu_shares"],
            "standing_window_s": window}


def scenario_text(count, columns=10, spacing=1.5):
    poses = ", ".join("{x: %g, y: %g}" % (i % columns * spacing, i // columns * spacing) for i in range(count))
    description = "$(find %s)/%s" % WHEELCHAIR
    return ("name: fleet_%d\nrobot: {description: %s, count: %d}\nworld: empty.world\nspawn: [%s]\n"
            "duration: 0.1\nchecks:\n  - upright: {max_tilt: 0.1}\n" % (count, description, count, poses))


def measure_scenario(count):
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "fleet.yaml")
        with open(path, "w") as file:
            file.write(scenario_text(count))
        command = ["rosrun", "bullet_sim", "scenario", path, "--out", os.path.join(folder, "out")]
        print("==", " ".join(command), file=sys.stderr)
        started = time.monotonic()
        result = subprocess.run(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, universal_newlines=True)
        wall = time.monotonic() - started
    if result.returncode != 0:
        raise RuntimeError("the scenario of %d robots failed (%d): %s" % (count, result.returncode, result.stderr))
    return {"count": count, "wall_s": wall,
            "peak_rss_mb": resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024}


class Driver:
    """Sends every robot v 0.3 m/s, w 0.3 rad/s at 10 Hz of sim time, as a teleop would."""

    def __init__(self, count):
        import rospy
        from geometry_msgs.msg import Twist
        from rosgraph_msgs.msg import Clock
        self.sim_time, self.next_send = 0.0, 0.0
        self.twist = Twist()
        self.twist.linear.x, self.twist.angular.z = 0.3, 0.3
        self.publishers = [rospy.Publisher("/robot%d/cmd_vel" % (i + 1), Twist, queue_size=1)
                           for i in range(count)]
        rospy.Subscriber("/clock", Clock, self.tick, queue_size=1)

    def tick(self, message):
        self.sim_time = message.clock.to_sec()
        if self.sim_time < self.next_send:
            return
        self.next_send = self.sim_time + 0.1
        for publisher in self.publishers:
            publisher.publish(self.twist)


def model_positions(count):
    import rospy
    from gazebo_msgs.srv import GetModelState
    state = rospy.ServiceProxy("/gazebo/get_model_state", GetModelState)
    return [state("robot%d" % (i + 1), "").pose.position for i in range(count)]


def spawn_without_state_publishers(count, spacing=3, columns=10):
    """The fleet of multi_robot.launch, spawned through the node's service, without robot_state_publishers."""
    import rospy
    from gazebo_msgs.srv import SpawnModel
    from geometry_msgs.msg import Pose
    import rospkg
    package, path = WHEELCHAIR
    xacro = os.path.join(rospkg.RosPack().get_path(package), path)
    description = subprocess.run(["xacro", xacro], stdout=subprocess.PIPE, universal_newlines=True, check=True).stdout
    rospy.wait_for_service("/gazebo/spawn_urdf_model", timeout=SPAWN_LIMIT_S)
    spawn = rospy.ServiceProxy("/gazebo/spawn_urdf_model", SpawnModel)
    for i in range(count):
        pose = Pose()
        pose.position.x, pose.position.y = i % columns * spacing, i // columns * spacing
        pose.orientation.w = 1
        name = "robot%d" % (i + 1)
        if not spawn(name, description, "/" + name, pose, "world").success:
            raise RuntimeError("spawning %s failed" % name)


def measure_driving(count, window, state_publishers):
    import rospy  # the node registers once this launch's master is up
    started = time.monotonic()
    if state_publishers:
        launch = Launch(["count:=%d" % count, "real_time_factor:=0", "spacing:=3"])
    else:
        launch = Launch(["real_time_factor:=0"], ("bullet_sim", "empty_world.launch"))
    try:
        if state_publishers:
            wait_for_fleet(count, started)
        rospy.init_node("bench_fleet_node", anonymous=True, disable_signals=True)
        if not state_publishers:
            spawn_without_state_publishers(count)
        driver = Driver(count)
        before = model_positions(count)
        shares, rtf = cpu_over(window, lambda: driver.sim_time, own_kind="driver")
        after = model_positions(count)
    finally:
        launch.stop()
    moved = [math.hypot(a.x - b.x, a.y - b.y) for a, b in zip(after, before)]
    return {"count": count, "rtf": rtf, "cpu_shares": shares, "window_s": window,
            "moved_m": [min(moved), max(moved)], "highest_z_m": max(abs(a.z) for a in after)}


def shares_text(shares):
    return ", ".join("%s %.2f" % (kind.replace("_", " "), share) for kind, share in sorted(shares.items()))


def table(report):
    spawn, scenario, drive, alone = report["spawn"], report["scenario"], report["drive"], report["drive_alone"]
    return [
        "| figure (through the node) | ours | target | met |",
        "|---|---|---|---|",
        "| spawning %d: `multi_robot.launch count:=%d`, to every robot in the world and its "
        "robot_state_publisher running (median of %d launches) | %.1f s (%.1f to %.1f) | <= %d s | %s |"
        % (spawn["count"], spawn["count"], len(spawn["spawn_s_all"]), spawn["spawn_s"], spawn["spawn_s_all"][0],
           spawn["spawn_s_all"][-1], TARGET_SPAWN_S, met(spawn["spawn_s"] <= TARGET_SPAWN_S)),
        "| spawning %d: a scenario with `count: %d`, to its result | %.2f s | <= %d s | %s |"
        % (scenario["count"], scenario["count"], scenario["wall_s"], TARGET_SPAWN_S,
           met(scenario["wall_s"] <= TARGET_SPAWN_S)),
        "| simulator peak RSS with %d (robot_state_publishers not counted) | %.0f MB | <= %d MB | %s |"
        % (spawn["count"], spawn["peak_rss_mb"], TARGET_RSS_MB, met(spawn["peak_rss_mb"] <= TARGET_RSS_MB)),
        "| %d wheelchairs driving circles, each with its robot_state_publisher, `real_time_factor:=0`, RTF | %.1f "
        "| >= %d | %s |" % (drive["count"], drive["rtf"], TARGET_RTF_10, met(drive["rtf"] >= TARGET_RTF_10)),
        "| the same %d spawned through the node's service, without robot_state_publishers, RTF | %.1f | >= %d | %s |"
        % (alone["count"], alone["rtf"], TARGET_RTF_10, met(alone["rtf"] >= TARGET_RTF_10)),
    ]


def driving_text(drive):
    return ("%s; each robot ended %.1f to %.1f m from where the window found it (on its circle, 2 m across), its "
            "origin at most %.1f mm off the ground" % (shares_text(drive["cpu_shares"]), drive["moved_m"][0],
                                                       drive["moved_m"][1], 1000 * drive["highest_z_m"]))


def section(report):
    spawn, drive, alone = report["spawn"], report["drive"], report["drive_alone"]
    return [
        "Measured by `scripts/bench_fleet_node.py` on %s, on this machine (%s), load average (1, 5, 15 min) %s "
        "before and %s after." % (report["date"], report["machine"], report["load_before"], report["load_after"]),
        "",
    ] + table(report) + [
        "",
        "Where the two cores went (a core = 1.00), %d wheelchairs standing at real time after the spawn, over %.0f s: "
        "%s. The %d wheelchairs driving with their robot_state_publishers, over %.0f s: %s. Without them: %s."
        % (spawn["count"], spawn["standing_window_s"], shares_text(spawn["standing_cpu_shares"]), drive["count"],
           drive["window_s"], driving_text(drive), driving_text(alone)),
        "",
        "```",
        "/usr/bin/python3 scripts/bench_fleet_node.py --spawn %d --drive %d" % (spawn["count"], drive["count"]),
        "```",
    ]


def driving_in_own_process(args, state_publishers):
    """A rospy node registers with one master: each launch's driver is a process of its own."""
    command = [sys.executable, os.path.abspath(__file__), "--drive", str(args.drive), "--window", str(args.window),
               "--port", str(args.port), "--drive-only", state_publishers]
    result = subprocess.run(command, stdout=subprocess.PIPE, universal_newlines=True, check=True)
    return json.loads(result.stdout.strip().splitlines()[-1])  # rospy prints its own lines before it


def measure(args):
    os.environ["ROS_MASTER_URI"] = "http://localhost:%d" % args.port
    report = {"date": datetime.date.today().isoformat(), "machine": cpu_model(), "load_before": load_average()}
    # The drives first: after five launches of a hundred robots, the machine's load (13 once) slowed them.
    report["drive_alone"] = driving_in_own_process(args, "without")
    report["drive"] = driving_in_own_process(args, "with")
    report["scenario"] = measure_scenario(args.spawn)
    report["spawn"] = measure_spawn(args.spawn, args.window, args.repeat)
    report["load_after"] = load_average()
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "bench_fleet_node.json"), "w") as file:
        json.dump(report, file, indent=2)
    return report


def place_in_page(text, marked):
    """A page without the markers gets the section at the end of "Through the node", before "## Cameras"."""
    if "\n## Cameras\n" in text:
        return text.replace("\n## Cameras\n", "\n" + marked + "\n\n## Cameras\n", 1)
    return text.rstrip("\n") + "\n\n" + marked + "\n"


def place_in_readme(text, marked):
    """A README without the markers gets the table right after the fleet's (bench_fleet.py's) section."""
    end = "<!-- bench-fleet:end -->"
    if end in text:
        return text.replace(end, end + "\n\n" + marked, 1)
    return text.rstrip("\n") + "\n\n" + marked + "\n"


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--spawn", type=int, default=100, help="robots spawned by the launch file and the scenario")
    parser.add_argument("--repeat", type=int, default=5, help="launches of the fleet to spawn, for the median")
    parser.add_argument("--drive", type=int, default=10, help="robots driven through the node")
    parser.add_argument("--window", type=float, default=30, help="wall seconds of each CPU and RTF window")
    parser.add_argument("--port", type=int, default=11411, help="the launches' own ROS master")
    parser.add_argument("--out", default="/tmp/bench_fleet_node", help="where the JSON goes")
    parser.add_argument("--no-page", action="store_true", help="leave docs/performance.md and the README alone")
    parser.add_argument("--from-json", help="measure nothing: the page and the README from this earlier JSON")
    parser.add_argument("--drive-only", choices=["with", "without"], help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.drive_only:
        os.environ["ROS_MASTER_URI"] = "http://localhost:%d" % args.port
        print(json.dumps(measure_driving(args.drive, args.window, args.drive_only == "with")))
        return
    if args.from_json:
        with open(args.from_json) as file:
            report = json.load(file)
    else:
        report = measure(args)
    lines = section(report)
    print("\n".join(lines))
    if args.no_page:
        return
    write_section(PAGE, "bench-fleet-node", lines, place_in_page)
    lead = ("Through the node, as a user runs a fleet (`scripts/bench_fleet_node.py`, %s; what the other "
            "processes take: [Performance](docs/performance.md#through-the-node)):" % report["date"])
    write_section(README, "bench-fleet-node", [lead, ""] + table(report), place_in_readme)


if __name__ == "__main__":
    main()
