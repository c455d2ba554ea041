"""sweep MATRIX.yaml: every cell of a scenario matrix as a Ray task of one CPU, then one table and a picture."""
import argparse
import json
import os
import shutil
import subprocess
import sys
import time

from bullet_sim_sweep import report
from bullet_sim_sweep.runs import run_cell, status_of

DESCRIPTION = """\
Expands MATRIX.yaml (a scenario crossed with axes of values; see `scenario --help` and the README) into its
cells and runs each as `scenario --matrix MATRIX.yaml --index N --out OUT/cells/NNNN`, a Ray task of one CPU
pinned to one core. Without --address it starts a local Ray instance with --cpus CPUs (default: all of this
machine's); --address HOST:PORT joins a running cluster (`ray start --head`, KubeRay, ...), whose workers must
see the same workspace paths. It shows done, failed and left with an estimate of the time left, retries a run
whose Ray worker or node was lost (at most --retries times), and never retries a run that ended: a failed
check, a scenario that could not run or one that crashed is reported with its exit code and log.
It writes OUT/results.csv and OUT/results.json (a row per cell: its axis values, status, every check's value
and every metric), OUT/summary.png (pass/fail per cell, the distribution of each metric) and OUT/sweep.json
(the counts and the runs per minute).
Exit status: 0 every run passed, 1 a check failed, 2 a run could not run, crashed or timed out."""


def parse_arguments(argv):
    parser = argparse.ArgumentParser(prog="sweep", description=DESCRIPTION,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("matrix", help="the matrix file")
    parser.add_argument("--out", help="the sweep's folder (default sweep_out/<matrix name>)")
    parser.add_argument("--address", help="a running Ray cluster to join, HOST:PORT (default: a local instance)")
    parser.add_argument("--cpus", type=int, help="CPUs of the local instance (default: all); not with --address")
    parser.add_argument("--retries", type=int, default=3, help="runs again of a task whose worker was lost")
    parser.add_argument("--timeout", type=float, default=3600, help="wall seconds a run may take (default 3600)")
    parser.add_argument("--video", action="store_true", help="each run also writes video.mp4")
    parser.add_argument("--scenario", help="the scenario executable (default: bullet_sim's, found by catkin)")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    args = parser.parse_args(argv)
    if args.cpus is not None and args.address:
        parser.error("--cpus is for the local instance; a cluster has its own")
    if args.cpus is not None and args.cpus < 1:
        parser.error("--cpus must be at least 1")
    return args


def scenario_executable(given):
    if given:
        return os.path.abspath(given)
    from catkin.find_in_workspaces import find_in_workspaces
    found = find_in_workspaces(["libexec"], project="bullet_sim", path="scenario", first_match_only=True)
    if found:
        return found[0]
    if shutil.which("scenario"):
        return shutil.which("scenario")
    raise SystemExit("sweep: cannot find bullet_sim's scenario executable: source devel/setup.bash, or --scenario")


def list_cells(scenario, matrix):
    """The matrix's cells, as `scenario --matrix M --list` expands them (the one place that expands them)."""
    listed = subprocess.run([scenario, "--matrix", matrix, "--list"], capture_output=True, text=True)
    if listed.returncode != 0:
        raise SystemExit("sweep: %s" % (listed.stderr.strip() or "scenario --list failed"))
    return json.loads(listed.stdout)


LOOPBACK = ("127.0.0.1", "localhost", "::1", "[::1]")


def start_ray(args):
    host = args.address.rsplit(":", 1)[0] if args.address else "127.0.0.1"
    if host in LOOPBACK:
        # A cluster of this machine alone: Ray keeps to the loopback address rather than the machine's own IP.
        os.environ.setdefault("RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER", "0")
    import ray
    options = dict(include_dashboard=False, log_to_driver=False, logging_level="WARNING")
    if args.address:
        ray.init(address=args.address, **options)
    else:
        ray.init(num_cpus=args.cpus, **options)
    return ray


class Progress:
    """done, failed and left, with an estimate of the time left, on stderr."""

    def __init__(self, total, enabled):
        from tqdm import tqdm
        self.bar = tqdm(total=total, unit="run", disable=not enabled, file=sys.stderr, dynamic_ncols=True)
        self.failed = 0
        self.total = total

    def update(self, status):
        self.failed += status != "pass"
        self.bar.update(1)
        self.bar.set_postfix_str("failed %d, left %d" % (self.failed, self.total - self.bar.n))

    def close(self):
        self.bar.close()


def run_all(ray, args, scenario, cells, out):
    """Submits every cell and gathers the runs as they end; returns them by index."""
    task = ray.remote(run_cell).options(num_cpus=1, max_retries=args.retries, retry_exceptions=False)
    env = dict(os.environ)
    matrix = os.path.abspath(args.matrix)
    pending = {}
    for cell in cells:
        cell_out = os.path.join(out, "cells", "%04d" % cell["index"])
        command = [scenario, "--matrix", matrix, "--index", str(cell["index"]), "--out", cell_out]
        if args.video:
            command.append("--video")
        pending[task.remote(command, env, cell_out, args.timeout)] = cell["index"]
    progress = Progress(len(cells), not args.no_progress)
    runs = {}
    try:
        while pending:
            ready, _ = ray.wait(list(pending), num_returns=1, timeout=1.0)
            for reference in ready:
                index = pending.pop(reference)
                try:
                    runs[index] = ray.get(reference)
                except ray.exceptions.RayError as error:  # the worker or node was lost more than --retries times
                    runs[index] = {"exit_code": None, "wall_s": 0.0, "host": "", "result": None,
                                   "log": "lost by Ray after %d retries: %s" % (args.retries, error)}
                progress.update(status_of(runs[index]))
            progress.bar.refresh()
    finally:
        progress.close()
    return runs


def main(argv=None):
    args = parse_arguments(sys.argv[1:] if argv is None else argv)
    scenario = scenario_executable(args.scenario)
    listing = list_cells(scenario, args.matrix)
    out = os.path.abspath(args.out or os.path.join("sweep_out", listing["name"]))
    os.makedirs(out, exist_ok=True)
    started = time.monotonic()
    ray = start_ray(args)
    try:
        ray_ready = time.monotonic()
        runs = run_all(ray, args, scenario, listing["cells"], out)
        finished = time.monotonic()
    finally:
        ray.shutdown()
    rows = [report.row_of(cell["index"], cell["values"], status_of(runs[cell["index"]]), runs[cell["index"]])
            for cell in listing["cells"]]
    report.write_table(rows, os.path.join(out, "results.csv"), os.path.join(out, "results.json"))
    report.write_summary(rows, listing["axes"], "%s: %d runs" % (listing["name"], len(rows)),
                         os.path.join(out, "summary.png"))
    statuses = [row["status"] for row in rows]
    seconds = finished - ray_ready
    summary = {"matrix": os.path.abspath(args.matrix), "runs": len(rows), "passed": statuses.count("pass"),
               "failed": statuses.count("fail"), "other": len(rows) - statuses.count("pass") - statuses.count("fail"),
               "ray_start_s": ray_ready - started, "runs_s": seconds,
               "runs_per_min": 60 * len(rows) / seconds if seconds > 0 else None,
               "address": args.address, "cpus": args.cpus}
    with open(os.path.join(out, "sweep.json"), "w") as file:
        json.dump(summary, file, indent=2)
        file.write("\n")
    print("sweep %s: %d runs, %d passed, %d failed, %d could not run or crashed, in %.1f s (%.0f runs/min; "
          "Ray started in %.1f s); %s" % (listing["name"], len(rows), summary["passed"], summary["failed"],
                                          summary["other"], seconds, summary["runs_per_min"] or 0,
                                          summary["ray_start_s"], os.path.join(out, "results.csv")))
    for row in rows:
        if row["status"] not in ("pass", "fail"):
            print("  cell %d: %s (exit code %s): %s" % (row["index"], row["status"], row["exit_code"],
                                                       (row.get("log_tail") or "").strip()[-300:]), file=sys.stderr)
    if all(s == "pass" for s in statuses):
        return 0
    return 1 if all(s in ("pass", "fail") for s in statuses) else 2
