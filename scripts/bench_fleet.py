#!/usr/bin/env python3
"""Measures many robots in one world (issue 32) with `bench --robots` and writes docs/performance.md's section
"Many robots" (between <!-- bench-fleet:begin --> and <!-- bench-fleet:end -->), the README's summary of it
(between the same markers) and its plot, docs/images/bench_fleet.png: RTF against the number of robots,
log-log, beside the anchors' robot x RTF per core; and the issue's 20 wheelchairs among 200 loose boxes in
walled_boxes.world, 4 m apart (bench_fleet_boxes.json).

    source devel/setup.bash && /usr/bin/python3 scripts/bench_fleet.py [--robots 1,10,30,100] [--duration S]
                                                                        [--repeat K] [--out DIR] [--no-page]
    /usr/bin/python3 scripts/bench_fleet.py --from-json DIR/bench_fleet.json   # the page, README, plot again
    /usr/bin/python3 scripts/bench_fleet.py --from-json DIR/bench_fleet.json --only-boxes --out DIR
                                             # measure the walled world only; the fleets from the JSON

--from-json takes the walled world's figures from bench_fleet_boxes.json beside the JSON, when it is there.

bench runs in one process, the fleets in increasing size (so its peak memory at N is the largest fleet's so
far); every robot is the wheelchair with its lidar, driving v 0.3 m/s, w 0.3 rad/s in empty.world, 1.5 m apart.
The defaults take about 2 minutes on a quiet 2-core machine. Prints the table; the JSON goes to DIR.
"""
import argparse
import datetime
import json
import os
import shlex
import subprocess
import sys
import textwrap

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_machine import cpu_model, load_average  # noqa: E402
from readme_section import met, write_section  # noqa: E402

PAGE = os.path.join(REPO, "docs", "performance.md")
PLOT = os.path.join(REPO, "docs", "images", "bench_fleet.png")
README = os.path.join(REPO, "README.md")
HEADING = "## Many robots\n"
# Robot x RTF per core of the anchors: Stage runs about 1,000 simple 2D robots at real time on one core
# (Vaughan 2008); Gazebo's best reports are near 20 (30 UAVs at RTF 0.6).
ANCHORS = [("Stage (Vaughan 2008)", 1000), ("Gazebo (30 UAVs at RTF 0.6)", 20)]
# Issue 32's targets, and its "today" through the node (2026-11-26).
TARGET_RTF = {10: 100, 100: 5}
TODAY_RTF = {10: 24, 100: 2.0}
TARGET_COST_RATIO = 1.25
TARGET_SPAWN_S = 20
TARGET_RSS_MB = 1024
# The walled world: its robots stand on the places its boxes leave free (scripts/walled_boxes_world.py).
BOXES_WORLD, BOXES_ROBOTS, BOXES_SPACING, BOXES_TARGET_RTF = "walled_boxes.world", 20, 4, 10
BOXES_JSON = "bench_fleet_boxes.json"


def run_bench(arguments):
    command = ["rosrun", "bullet_sim", "bench"] + arguments
    print("==", " ".join(command), file=sys.stderr)
    result = subprocess.run(command, stdout=subprocess.PIPE, check=True, universal_newlines=True)
    return " ".join(shlex.quote(word) for word in command), json.loads(result.stdout)


def measure(args, arguments, name):
    """bench's JSON, with the command, the date, the machine and its load before and after; also in
    args.out/name."""
    load_before = load_average()
    command, report = run_bench(arguments)
    report.update(command=command, date=datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d"),
                  cores=os.cpu_count(), cpu=cpu_model(), load_before=load_before, load_after=load_average())
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, name), "w") as file:
        json.dump(report, file, indent=2)
    return report


def measure_fleets(args):
    return measure(args, ["--robots", args.robots, "--duration", "%g" % args.duration, "--repeat", str(args.repeat)],
                   "bench_fleet.json")


def measure_boxes(args):
    return measure(args, ["--robots", str(BOXES_ROBOTS), "--world", BOXES_WORLD, "--spacing", "%g" % BOXES_SPACING,
                          "--duration", "%g" % args.duration, "--repeat", str(args.repeat)], BOXES_JSON)


def process_cpu_ms(fleet):
    """CPU ms per sim s per robot on every thread (older JSON has the stepping thread's only)."""
    return fleet.get("process_cpu_ms_per_sim_s_per_robot", fleet["cpu_ms_per_sim_s_per_robot"])


def fleet_rows(fleets):
    lines = ["| robots | RTF | robot x RTF | wall ms per sim s per robot | CPU ms per sim s per robot, "
             "stepping thread | CPU ms per sim s per robot, all threads | RTF with a core to itself | spawn | "
             "peak RSS | lidar scans per robot per s | worst pose error |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for fleet in fleets:
        cpu_ms = process_cpu_ms(fleet)
        lines.append("| %d | %.3g | %.0f | %.2f | %.2f | %.2f | %.3g | %.2f s | %.0f MB | %.2f | %.3f m |" % (
            fleet["robots"], fleet["rtf"], fleet["robot_rtf"], fleet["wall_ms_per_sim_s_per_robot"],
            fleet["cpu_ms_per_sim_s_per_robot"], cpu_ms, 1000 / (fleet["robots"] * cpu_ms), fleet["spawn_s"],
            fleet["peak_rss_mb"], fleet["lidar_scans_per_robot_per_s"], fleet["pose_error_max_m"]))
    return lines


def cost_ratio_row(ten, hundred):
    """The per-robot cost at 100 against 10, judged on the medians' CPU time (on a shared machine the wall time
    follows the others' load), with how far it moves between any run of each."""
    wall = hundred["wall_ms_per_sim_s_per_robot"] / ten["wall_ms_per_sim_s_per_robot"]
    cpu = process_cpu_ms(hundred) / process_cpu_ms(ten)
    runs = "process_cpu_ms_per_sim_s_per_robot_runs"
    spread, verdict = "", met(cpu <= TARGET_COST_RATIO)
    if runs in ten and runs in hundred:
        lowest, highest = min(hundred[runs]) / max(ten[runs]), max(hundred[runs]) / min(ten[runs])
        spread = "%.2fx to %.2fx between runs; " % (lowest, highest)
        if cpu <= TARGET_COST_RATIO < highest:
            verdict += " on the medians, not between every run"
    return ("per-robot cost at N = 100 against N = 10, CPU time of all threads",
            "%.2fx (%swall time: %.2fx)" % (cpu, spread, wall), "", "<= %.2fx" % TARGET_COST_RATIO, verdict)


def target_rows(by_count):
    """The issue's targets beside ours, each judged where we measured it."""
    rows = []
    for count, target in sorted(TARGET_RTF.items()):
        if count in by_count:
            rtf = by_count[count]["rtf"]
            rows.append(("%d wheelchairs, `empty.world`, RTF" % count, "%.3g" % rtf, "%.3g" % TODAY_RTF[count],
                         ">= %d" % target, met(rtf >= target)))
    if 10 in by_count and 100 in by_count:
        rows.append(cost_ratio_row(by_count[10], by_count[100]))
    if 100 in by_count:
        fleet = by_count[100]
        rows.append(("spawning 100 (bench, in-process: parse and spawn each)", "%.1f s" % fleet["spawn_s"], "",
                     "<= %d s (through the launch file and a scenario)" % TARGET_SPAWN_S,
                     met(fleet["spawn_s"] <= TARGET_SPAWN_S) + ", in-process only"))
        rows.append(("peak RSS with 100 (bench's process, not the node)", "%.0f MB" % fleet["peak_rss_mb"], "",
                     "<= 1 GB", met(fleet["peak_rss_mb"] <= TARGET_RSS_MB) + ", in-process only"))
    lines = ["| figure | ours | issue's today (through the node) | target | met |", "|---|---|---|---|---|"]
    return lines + ["| %s |" % " | ".join(row) for row in rows]


def boxes_lines(boxes):
    """The walled world's paragraph, its figures and its command."""
    fleet = boxes["fleets"][0]
    cpu_ms = process_cpu_ms(fleet)
    escaped = fleet["loose_escaped"]
    paragraph = (
        "**Among boxes.** `walled_boxes.world` (written by `scripts/walled_boxes_world.py`) is the issue's walled "
        "20 x 20 m world: walls 0.1 m thick and 1 m high, and %d loose boxes, 0.4 m cubes of 4 kg, at seeded places "
        "at least 1 m from the places of %d wheelchairs %g m apart, whose circles run into them. Measured on %s, "
        "load average %s before and %s after, %.0f s of driving as above, medians of %d runs. Every step of every "
        "run is watched: how high any box's centre rose (a cube balanced on a corner: 0.146 m; more, and it "
        "flew), how far any sank, whether any centre was once outside the walls, inside one or under the ground, "
        "and how far any robot rose and leaned."
        % (fleet["loose_bodies"], fleet["robots"], boxes["spacing_m"], boxes["date"], boxes["load_before"],
           boxes["load_after"], boxes["duration_s"], boxes["repeat"]))
    lines = textwrap.wrap(paragraph, 110) + [""]
    lines += ["| robots | boxes | RTF | robot x RTF | CPU ms per sim s per robot, all threads | RTF with a core to "
              "itself | boxes pushed (> 1 cm) | boxes asleep at the end | highest box rise | deepest box sink | boxes out of the walls, in "
              "one or under the ground | robots' rise, lean |",
              "|---|---|---|---|---|---|---|---|---|---|---|---|",
              "| %d | %d | %.3g | %.3g | %.1f | %.3g | %d | %s | %.3f m | %.1f mm | %s | %.1f mm, %.2f deg |" % (
                  fleet["robots"], fleet["loose_bodies"], fleet["rtf"], fleet["robot_rtf"], cpu_ms,
                  1000 / (fleet["robots"] * cpu_ms), fleet["loose_pushed"], fleet.get("loose_asleep_at_end", "-"),
                  fleet["loose_rise_max_m"],
                  1000 * fleet["loose_sink_max_m"], ", ".join(escaped) if escaped else "none",
                  1000 * fleet["robot_rise_max_m"], fleet["robot_tilt_max_deg"])]
    return lines + ["", "```", boxes["command"].replace(REPO + "/", ""), "```"]


def boxes_target_row(boxes):
    rtf = boxes["fleets"][0]["rtf"]
    return ("| 20 wheelchairs among 200 dynamic boxes in a walled 20 x 20 m world (`walled_boxes.world`), RTF "
            "| %.3g |  | >= %d | %s |" % (rtf, BOXES_TARGET_RTF, met(rtf >= BOXES_TARGET_RTF)))


def section(report, boxes=None):
    fleets = report["fleets"]
    by_count = {fleet["robots"]: fleet for fleet in fleets}
    paragraphs = [
        "Measured by `scripts/bench_fleet.py` on %s, on a %d-core %s (`nproc`, `/proc/cpuinfo`), load average "
        "(1, 5, 15 min) %s before and %s after: the machine is shared, and wall-time figures follow its load; "
        "CPU time does much less. \"RTF with a core to itself\" is 1000 / (N x CPU ms per sim s per robot, all "
        "threads): what the wall time would give if the work never waited and shared no core."
        % (report["date"], report["cores"], report["cpu"], report["load_before"], report["load_after"]),
        "`bench --robots N` spawns N wheelchairs (their xacro, expanded once; each robot's URDF parsed and "
        "spawned as the node's spawn service does) into `empty.world`, robot1 to robotN each in its own "
        "namespace, on a square grid 1.5 m apart. After %.1f s at rest every one drives v = %.1f m/s, "
        "w = %.1f rad/s for %.0f s of sim time, the command re-sent at 10 Hz of sim time as a teleop would, "
        "its 360-beam lidar scanning at its own 5.5 Hz; 1 ms steps, as fast as it goes. Bullet steps on one "
        "thread; %s. Medians of %d runs. The simulation runs in bench's process, without ROS: the issue's "
        "\"today\" figures were through the node."
        % (report["settle_s"], report["cmd"][0], report["cmd"][1], report["duration_s"],
           "a pool of %d threads (the stepping one included) casts each step's due lidar scans side by side "
           "(--lockstep)" % report.get("threads", 1) if report.get("lockstep")
           else "the lidar scans are cast on a thread of their own behind the next steps' physics, as in the node",
           report["repeat"]),
    ]
    lines = textwrap.wrap(paragraphs[0], 110) + [""] + textwrap.wrap(paragraphs[1], 110) + [""]
    targets = target_rows(by_count) + ([boxes_target_row(boxes)] if boxes else [])
    lines += fleet_rows(fleets) + [""] + targets + [""]
    lines += ["![RTF against the number of robots, log-log, ours beside the anchors](images/bench_fleet.png)", "",
              "```", report["command"].replace(REPO + "/", ""), "```"]
    return lines + ([""] + boxes_lines(boxes) if boxes else [])


def readme_lines(report, boxes=None):
    """The README's summary: the issue's targets beside ours, and the plot; the whole table stays in the page."""
    by_count = {fleet["robots"]: fleet for fleet in report["fleets"]}
    intro = ("Many robots in one world: `bench --robots N` drives N wheelchairs with 360-beam lidars in circles, "
             "measured by `scripts/bench_fleet.py` on %s on a %d-core %s. Every figure, and what the step costs, "
             "is in [Performance](docs/performance.md#many-robots), with how much they move from one run to the next "
             "on this shared machine." % (report["date"], report["cores"], report["cpu"]))
    targets = target_rows(by_count) + ([boxes_target_row(boxes)] if boxes else [])
    return textwrap.wrap(intro, 110) + [""] + targets + [
        "", "![RTF against the number of robots, log-log, ours beside Stage's and Gazebo's](docs/images/bench_fleet.png)"]


def place_in_readme(text, marked):
    """A README without the markers gets the summary under its own heading, before "## Documentation"."""
    return text.replace("\n## Documentation\n", "\n## How fast\n" + marked + "\n\n## Documentation\n", 1)


def plot(report, path, boxes=None):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fleets = report["fleets"]
    counts = [fleet["robots"] for fleet in fleets]
    figure, axes = plt.subplots(figsize=(7, 5), dpi=110)
    span = [1, 1000]
    styles = ["--", ":"]
    for (name, robot_rtf), style in zip(ANCHORS, styles):
        axes.plot(span, [robot_rtf / n for n in span], style, color="grey",
                  label="%s: %d robot x RTF per core" % (name, robot_rtf))
    axes.plot(counts, [fleet["rtf"] for fleet in fleets], "o-", color="tab:blue", linewidth=2,
              label="ours (bench --robots, %d threads), wall time" % report.get("threads", 1))
    for fleet in fleets:
        axes.annotate("%.3g" % fleet["rtf"], (fleet["robots"], fleet["rtf"]), textcoords="offset points",
                      xytext=(7, 5), fontsize=8, color="tab:blue")
    # The wall time follows the shared machine's load; the CPU time gives what a core to itself would.
    own_core = [1000 / (fleet["robots"] * process_cpu_ms(fleet)) for fleet in fleets]
    axes.plot(counts, own_core, "o--", color="tab:purple", linewidth=1.5,
              label="ours with a core to itself (from the CPU time of all threads)")
    for count, rtf in zip(counts, own_core):
        axes.annotate("%.3g" % rtf, (count, rtf), textcoords="offset points", xytext=(7, -12), fontsize=8,
                      color="tab:purple")  # below the wall-time figure, which it is near
    axes.plot(list(TODAY_RTF), list(TODAY_RTF.values()), "s", color="tab:orange", fillstyle="none",
              label="issue 32's today, through the node")
    axes.plot(list(TARGET_RTF), list(TARGET_RTF.values()), "*", color="tab:green", markersize=12,
              label="issue 32's targets")
    if boxes:
        fleet = boxes["fleets"][0]
        axes.plot([fleet["robots"]], [fleet["rtf"]], "D", color="tab:red",
                  label="ours, %d among %d loose boxes (walled_boxes.world)" % (fleet["robots"], fleet["loose_bodies"]))
        axes.annotate("%.3g" % fleet["rtf"], (fleet["robots"], fleet["rtf"]), textcoords="offset points",
                      xytext=(7, -10), fontsize=8, color="tab:red")
        axes.plot([fleet["robots"]], [BOXES_TARGET_RTF], "*", color="tab:red", markersize=12, fillstyle="none",
                  label="issue 32's target among boxes")
    axes.set_xscale("log")
    axes.set_yscale("log")
    axes.set_xlim(0.8, 1200)
    axes.set_xlabel("robots (wheelchairs with a 360-beam lidar, driving circles)")
    axes.set_ylabel("real-time factor")
    axes.set_title("Many robots in one world: RTF against N (%s)" % report["date"])
    axes.grid(True, which="both", alpha=0.3)
    axes.legend(fontsize=8)
    figure.tight_layout()
    figure.savefig(path)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--robots", default="1,10,30,100")
    parser.add_argument("--duration", type=float, default=20, help="sim seconds of driving per run")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--out", default="/tmp/bench_fleet", help="where the JSON goes")
    parser.add_argument("--no-page", action="store_true", help="leave docs/performance.md, the README and the plot alone")
    parser.add_argument("--from-json", help="measure nothing: the page, the README and the plot from this earlier run's JSON")
    parser.add_argument("--only-boxes", action="store_true",
                        help="measure the walled world only, the fleets from --from-json")
    args = parser.parse_args()
    if args.only_boxes and not args.from_json:
        parser.error("--only-boxes takes the fleets from --from-json DIR/bench_fleet.json")

    if args.from_json:
        with open(args.from_json) as file:
            report = json.load(file)
    else:
        report = measure_fleets(args)
    boxes_json = os.path.join(os.path.dirname(os.path.abspath(args.from_json)), BOXES_JSON) if args.from_json else None
    if args.only_boxes or not args.from_json:
        boxes = measure_boxes(args)
    elif os.path.exists(boxes_json):
        with open(boxes_json) as file:
            boxes = json.load(file)
    else:
        boxes = None
    lines = section(report, boxes)
    print("\n".join(lines))
    if args.no_page:
        return
    plot(report, PLOT, boxes)
    write_section(PAGE, "bench-fleet", lines, place)
    write_section(README, "bench-fleet", readme_lines(report, boxes), place_in_readme)


def place(text, marked):
    """A page without the markers gets the section, under its heading, before "## Cameras" (or at the end)."""
    block = HEADING + marked + "\n\n"
    if "\n## Cameras\n" in text:
        return text.replace("\n## Cameras\n", "\n" + block + "## Cameras\n", 1)
    return text.rstrip("\n") + "\n\n" + block


if __name__ == "__main__":
    main()
