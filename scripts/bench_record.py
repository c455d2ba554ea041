#!/usr/bin/env python3
"""Measures what recording a bag costs the simulator node (never asserted by tests): the wheelchair standing in
home.world with its lidar, the default topics and ground truth at 50 Hz, against the same run without ~record.

    source devel/setup.bash && scripts/bench_record.py [--out DIR] [--repeat N] [--window S] [--page docs/performance.md]

Starts a ROS master of its own on a free port, then for each repeat and each pace (~real_time_factor 0, then 1)
a simulator without and one with ~record (in alternating order), spawns the wheelchair into it, lets it run a
few seconds, and measures over --window wall seconds: the real-time factor (sim time from /clock over wall
time), and from /proc the CPU time of the simulation's thread, of the bag's writer thread and of the whole
process. On a shared machine the RTF follows the load; the simulation thread's CPU time per sim second does
much less, and is what sets the RTF when the simulation has a core to itself. Prints a Markdown table of the
medians and writes DIR/bench_record.json; --page rewrites the Performance page's bench-record section with them.
"""
import argparse
import json
import os
import signal
import socket
import statistics
import subprocess
import sys
import tempfile
import time

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_machine import cpu_model  # noqa: E402
from readme_section import write_section  # noqa: E402

TICKS = os.sysconf("SC_CLK_TCK")
WARM_UP = 3.0  # [wall s] after the spawn, before measuring


def load():
    with open("/proc/loadavg") as file:
        return [float(x) for x in file.read().split()[:3]]


def cpu_seconds(stat_path):
    """utime + stime of a process or thread, from its /proc stat file."""
    with open(stat_path) as file:
        fields = file.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / TICKS


def thread_named(pid, name):
    """The /proc stat file of `pid`'s thread called `name`, or None."""
    for task in os.listdir("/proc/%d/task" % pid):
        with open("/proc/%d/task/%s/comm" % (pid, task)) as file:
            if file.read().strip() == name:
                return "/proc/%d/task/%s/stat" % (pid, task)
    return None


def bag_duration(path):
    """The sim seconds a bag spans."""
    import rosbag
    with rosbag.Bag(path) as bag:
        return bag.get_end_time() - bag.get_start_time()


def free_port():
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


class Clock:
    """The latest /clock, as rospy receives it."""

    def __init__(self):
        import rospy
        from rosgraph_msgs.msg import Clock as ClockMessage
        self.latest = None
        rospy.Subscriber("/clock", ClockMessage, self._take, queue_size=1)

    def _take(self, message):
        self.latest = message.clock.to_sec()


def run_once(real_time_factor, bag, window, clock):
    """One simulator run: its RTF and CPU figures over `window` wall seconds."""
    import rosservice
    import rospy
    if rospy.has_param("/gazebo/record"):  # a private parameter outlives the run that set it
        rospy.delete_param("/gazebo/record")
    command = ["rosrun", "bullet_sim", "simulator", "__name:=gazebo", "_world:=home.world",
               "_real_time_factor:=%g" % real_time_factor]
    if bag:
        command.append("_record:=" + bag)
    simulator = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + 60
        while "/gazebo/spawn_urdf" not in rosservice.get_service_list():
            if time.monotonic() > deadline or simulator.poll() is not None:
                raise RuntimeError("the simulator did not come up")
            time.sleep(0.1)
        subprocess.run(["rosrun", "bullet_sim", "spawn_model", "-urdf", "-param", "robot_description", "-model",
                        "wheelchair", "-x", "0", "-y", "-1", "-Y", "3.14159"], check=True, stdout=subprocess.DEVNULL)
        time.sleep(WARM_UP)
        process, thread = "/proc/%d/stat" % simulator.pid, "/proc/%d/task/%d/stat" % (simulator.pid, simulator.pid)
        writer = thread_named(simulator.pid, "bag_writer")
        if bag and not writer:
            raise RuntimeError("the simulator has no bag_writer thread")
        if writer and not bag:
            raise RuntimeError("the simulator records a bag without ~record")
        writer_cpu = (lambda: cpu_seconds(writer)) if writer else (lambda: 0.0)
        wall0, sim0, cpu0, main0, writer0 = (time.monotonic(), clock.latest, cpu_seconds(process),
                                             cpu_seconds(thread), writer_cpu())
        time.sleep(window)
        wall1, sim1, cpu1, main1, writer1 = (time.monotonic(), clock.latest, cpu_seconds(process),
                                             cpu_seconds(thread), writer_cpu())
    finally:
        simulator.send_signal(signal.SIGINT)
        simulator.wait(timeout=30)
    wall, sim = wall1 - wall0, sim1 - sim0
    figures = {"rtf": sim / wall, "process_cpu": (cpu1 - cpu0) / wall, "main_cpu": (main1 - main0) / wall,
               "writer_cpu": (writer1 - writer0) / wall, "main_cpu_per_sim_s": (main1 - main0) / sim}
    if bag:
        figures["bag_bytes_per_sim_s"] = os.path.getsize(bag) / bag_duration(bag)
        os.remove(bag)
    return figures


def medians(runs, key):
    return statistics.median(run[key] for run in runs)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", default="/tmp/bench_record")
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--window", type=float, default=20.0, help="wall seconds measured per run")
    parser.add_argument("--page", help="rewrite this page's bench-record section (docs/performance.md)")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    os.environ["ROS_MASTER_URI"] = "http://127.0.0.1:%d" % free_port()
    os.environ["ROS_HOSTNAME"] = "127.0.0.1"
    master = subprocess.Popen(["rosmaster", "--core", "-p", os.environ["ROS_MASTER_URI"].rsplit(":", 1)[1]],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        import rosgraph
        deadline = time.monotonic() + 30
        while not rosgraph.is_master_online():
            if time.monotonic() > deadline:
                raise RuntimeError("the ROS master did not come up")
            time.sleep(0.1)
        import rospy
        urdf = subprocess.run(["xacro", os.path.join(REPO, "smartwheelchair_model/urdf/smartwheelchair_model.urdf.xacro")],
                              check=True, capture_output=True, text=True).stdout
        rospy.set_param("/robot_description", urdf)
        rospy.init_node("bench_record", disable_signals=True)
        clock = Clock()
        figures = {"date": time.strftime("%Y-%m-%d"), "cpu": cpu_model(), "cores": os.cpu_count(),
                   "load_before": load(), "window_s": args.window, "repeat": args.repeat, "runs": {}}
        bag = os.path.join(tempfile.mkdtemp(dir=args.out), "run.bag")
        for pace in (0, 1):
            off, on = [], []
            for i in range(args.repeat):
                for recording in ((False, True) if i % 2 == 0 else (True, False)):
                    result = run_once(pace, bag if recording else None, args.window, clock)
                    (on if recording else off).append(result)
                    print("rtf %g, %s: %s" % (pace, "record" if recording else "plain", result), file=sys.stderr)
            figures["runs"]["rtf%d" % pace] = {"plain": off, "record": on}
        figures["load_after"] = load()
    finally:
        master.terminate()
        master.wait(timeout=30)
    with open(os.path.join(args.out, "bench_record.json"), "w") as file:
        json.dump(figures, file, indent=2)

    fast, paced = figures["runs"]["rtf0"], figures["runs"]["rtf1"]
    rtf_plain, rtf_record = medians(fast["plain"], "rtf"), medians(fast["record"], "rtf")
    cost = 1 - rtf_record / rtf_plain
    per_sim_plain = medians(fast["plain"], "main_cpu_per_sim_s")
    per_sim_record = medians(fast["record"], "main_cpu_per_sim_s")
    thread_cost = per_sim_record / per_sim_plain - 1
    core = medians(paced["record"], "process_cpu") - medians(paced["plain"], "process_cpu")
    writer = medians(paced["record"], "writer_cpu")
    bag_rate = medians(fast["record"] + paced["record"], "bag_bytes_per_sim_s")  # over the bag's own span
    lines = [
        "Measured by `scripts/bench_record.py` on %s, on a %d-core %s: the wheelchair standing in `home.world` "
        "with its lidar, `~record` with the default topics (ground truth at 50 Hz, lz4), against the same run "
        "without it; %d runs each, in alternating order, %g wall seconds measured after %g s; medians. The load "
        "average was %s before and %s after: on a shared machine the RTF follows the load, while the simulation "
        "thread's CPU time per sim second, which sets the RTF when the simulation has a core to itself, moves "
        "much less." % (
            figures["date"], figures["cores"], figures["cpu"], args.repeat, args.window, WARM_UP,
            " ".join("%.2f" % x for x in figures["load_before"]), " ".join("%.2f" % x for x in figures["load_after"])),
        "",
        "| figure | without | with `~record` | target | met |",
        "|---|---|---|---|---|",
        "| RTF at `~real_time_factor 0` | %.0f | %.0f (%+.1f %%) | at most 10 %% lower | %s |" % (
            rtf_plain, rtf_record, -100 * cost, "yes" if cost <= 0.10 else "**no**"),
        "| the simulation thread's CPU per sim second at RTF 0 [ms] | %.2f | %.2f (%+.1f %%) | at most +10 %% "
        "(RTF with a core to itself) | %s |" % (
            1000 * per_sim_plain, 1000 * per_sim_record, 100 * thread_cost, "yes" if thread_cost <= 0.10 else "**no**"),
        "| the process's CPU at RTF 1 [%% of a core] | %.1f | %.1f (%+.1f, of which the bag's writer thread %.1f) "
        "| at most +2 | %s |" % (
            100 * medians(paced["plain"], "process_cpu"), 100 * medians(paced["record"], "process_cpu"), 100 * core,
            100 * writer, "yes" if core <= 0.02 else "**no**"),
        "| bag size | | %.0f kB per sim minute | | |" % (bag_rate * 60 / 1000),
        "",
        "```",
        "source devel/setup.bash && scripts/bench_record.py --repeat %d --window %g" % (args.repeat, args.window),
        "```",
    ]
    print("\n".join(lines))
    if args.page:
        write_section(args.page, "bench-record", lines,
                      lambda text, section: text.replace("\n## Scenarios and sweeps\n", "\n## Recording\n" + section
                                                          + "\n\n## Scenarios and sweeps\n", 1))


if __name__ == "__main__":
    main()
