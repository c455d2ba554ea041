#!/usr/bin/env python3
"""Measures the scenario figures docs/performance.md reports (never asserted by tests): one run's wall time, sweep
throughput for timeline and launch scenarios, and the sweep's scaling from 1 to 2 CPUs.

    source devel/setup.bash && scripts/bench_scenarios.py [--out DIR] [--single N]

Uses bullet_sim/bench/scenarios (the wheelchair in home.world, its lidar on, 10 s of sim time). Prints a
Markdown table and writes DIR/bench_scenarios.json. Run it on a quiet machine: the load is printed with it.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_machine import cpu_model  # noqa: E402

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENARIOS = os.path.join(REPO, "bullet_sim", "bench", "scenarios")


def load():
    with open("/proc/loadavg") as file:
        return float(file.read().split()[0])


def single_runs(out, count):
    """Wall seconds from starting `scenario` to its exit, result.json written, the xacro cache warm."""
    scenario = os.path.join(SCENARIOS, "wheelchair_timeline.yaml")
    walls = []
    for i in range(count + 1):  # the first run fills the xacro cache and is not counted
        started = time.monotonic()
        subprocess.run(["rosrun", "bullet_sim", "scenario", scenario, "--out", os.path.join(out, "single")],
                       check=True, stdout=subprocess.DEVNULL)
        if i:
            walls.append(time.monotonic() - started)
    return walls


def sweep(matrix, out, cpus):
    """A sweep on a local Ray instance of `cpus` CPUs; its sweep.json."""
    folder = os.path.join(out, "%s_%dcpu" % (os.path.splitext(os.path.basename(matrix))[0], cpus))
    command = ["rosrun", "bullet_sim", "sweep", matrix, "--cpus", str(cpus), "--out", folder, "--no-progress"]
    subprocess.run(command, check=False, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    with open(os.path.join(folder, "sweep.json")) as file:
        return json.load(file)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", default="/tmp/bench_scenarios")
    parser.add_argument("--single", type=int, default=10, help="runs of one scenario to time")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    figures = {"date": time.strftime("%Y-%m-%d"), "cpu": cpu_model(), "cores": os.cpu_count(),
               "load_before": load()}
    walls = single_runs(args.out, args.single)
    figures["single_run_wall_s"] = {"median": statistics.median(walls), "min": min(walls), "max": max(walls)}
    timeline = os.path.join(SCENARIOS, "timeline_matrix.yaml")
    figures["timeline_sweep_2cpu"] = sweep(timeline, args.out, 2)
    figures["timeline_sweep_1cpu"] = sweep(timeline, args.out, 1)
    figures["scaling_1_to_2"] = (figures["timeline_sweep_2cpu"]["runs_per_min"] /
                                 figures["timeline_sweep_1cpu"]["runs_per_min"])
    figures["launch_sweep_2cpu"] = sweep(os.path.join(SCENARIOS, "teleop_matrix.yaml"), args.out, 2)
    figures["load_after"] = load()
    with open(os.path.join(args.out, "bench_scenarios.json"), "w") as file:
        json.dump(figures, file, indent=2)
    rows = [
        ("10 s timeline scenarios through `sweep`, 2 CPUs", "%.0f runs/min (%d of %d passed)" % (
            figures["timeline_sweep_2cpu"]["runs_per_min"], figures["timeline_sweep_2cpu"]["passed"],
            figures["timeline_sweep_2cpu"]["runs"]), ">= 120 runs/min",
         figures["timeline_sweep_2cpu"]["runs_per_min"] >= 120),
        ("the same as launch scenarios (own master, rospy teleop, RTF 0)", "%.0f runs/min (%d of %d passed)" % (
            figures["launch_sweep_2cpu"]["runs_per_min"], figures["launch_sweep_2cpu"]["passed"],
            figures["launch_sweep_2cpu"]["runs"]), ">= 20 runs/min",
         figures["launch_sweep_2cpu"]["runs_per_min"] >= 20),
        ("sweep scaling, 1 to 2 CPUs, each run on one core and one thread", "%.2fx (%.0f and %.0f runs/min)" % (
            figures["scaling_1_to_2"], figures["timeline_sweep_1cpu"]["runs_per_min"],
            figures["timeline_sweep_2cpu"]["runs_per_min"]), ">= 1.7x", figures["scaling_1_to_2"] >= 1.7),
        ("one `scenario` run, start to result.json (xacro cached)", "%.2f s (median of %d; %.2f to %.2f)" % (
            figures["single_run_wall_s"]["median"], len(walls), figures["single_run_wall_s"]["min"],
            figures["single_run_wall_s"]["max"]), "<= 0.6 s", figures["single_run_wall_s"]["median"] <= 0.6),
    ]
    print("Measured on %s, %s (%d cores), load average %.2f before and %.2f after; Ray started in %.1f s "
          "(not counted)." % (figures["date"], figures["cpu"], figures["cores"], figures["load_before"],
                              figures["load_after"], figures["timeline_sweep_2cpu"]["ray_start_s"]))
    print()
    print("| figure | measured | target | met |")
    print("|---|---|---|---|")
    for name, measured, target, met in rows:
        print("| %s | %s | %s | %s |" % (name, measured, target, "yes" if met else "**no**"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
