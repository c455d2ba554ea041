"""sweep MATRIX.yaml: every cell of a scenario matrix as a Ray task of one CPU, then one table and a picture."""
import argparse
import json
import math
import os
import shutil
import socket
import subprocess
import sys
import time

from bullet_sim_sweep.on_ray import Cells, SweepError, nodes_of, start_ray
from bullet_sim_sweep.progress import Progress
from bullet_sim_sweep.runs import status_of

DESCRIPTION = """\
Expands MATRIX.yaml (a scenario crossed with axes of values; see `scenario --help` and docs/scenarios.md) into
cells and runs each as `scenario --matrix MATRIX.yaml --index N`, a Ray task of one CPU pinned to one core,
spread over the cluster's nodes. Without --address it starts a local Ray instance with --cpus CPUs (default:
all of this machine's); --address HOST:PORT joins a running cluster (`ray start --head`, KubeRay, ...), whose
nodes must have this workspace at the same path and be started from a shell that sourced its devel/setup.bash
(a run's environment is its node's, with this shell's variables on top). Each run writes into a temporary
folder of its node, and its files come back through Ray into OUT/cells/NNNN, so OUT need not be shared.
It shows a bar for all runs (done, failed, left, time left) and one per node, runs again a run whose Ray worker
or node was lost (at most --retries times), and never runs again a run that ended: a failed check, a scenario
that could not run or one that crashed is reported with its exit code and log. A cell that Ray could not begin
(a worker that cannot load the task) is reported as never started, with the worker's error.
It writes OUT/results.csv and OUT/results.json (a row per cell: its axis values, status, node, attempts, every
check's value and every metric), OUT/summary.png (pass/fail per cell, the distribution of each metric) and
OUT/sweep.json (the counts, the runs per minute, each node's runs and runs per minute, lost nodes, runs begun
again).
Exit status: 0 every run passed, 1 a check failed, 2 a run could not run, crashed, timed out, never started or
was lost, or a bad argument or matrix (said in one line)."""

MAX_RETRIES = 100
REACH_TIMEOUT = 5.0  # [s] to open a connection to --address before Ray is asked to join it
WAIT_STEP = 1.0  # [s] between looks at the runs that ended
NODE_DEATH_WAIT_S = 30.0  # [s] the longest wait for Ray to say whether a node a run left is lost


class OneLineParser(argparse.ArgumentParser):
    def error(self, message):
        self.exit(2, "sweep: %s (sweep --help lists the arguments)\n" % message)


def positive_float(text):
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not math.isfinite(value) or value <= 0:
        raise argparse.ArgumentTypeError("[%s] is not a positive number of seconds" % text)
    return value


def bounded_int(low, high):
    def parse(text):
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError("[%s] is not a whole number" % text)
        if not low <= value <= high:
            raise argparse.ArgumentTypeError("[%s] is not in %d to %d" % (text, low, high))
        return value
    return parse


def parse_arguments(argv):
    parser = OneLineParser(prog="sweep", description=DESCRIPTION,
                           formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("matrix", help="the matrix file")
    parser.add_argument("--out", help="the sweep's folder (default sweep_out/<matrix name>)")
    parser.add_argument("--address", help="a running Ray cluster to join, HOST:PORT (default: a local instance)")
    parser.add_argument("--cpus", type=bounded_int(1, 4096),
                        help="CPUs of the local instance (default: all); not with --address")
    parser.add_argument("--retries", type=bounded_int(0, MAX_RETRIES), default=3,
                        help="runs again of a task whose worker or node was lost (default 3)")
    parser.add_argument("--timeout", type=positive_float, default=3600,
                        help="wall seconds a run may take (default 3600)")
    parser.add_argument("--video", action="store_true", help="each run also writes video.mp4")
    parser.add_argument("--scenario", help="the scenario executable (default: bullet_sim's, found by catkin)")
    parser.add_argument("--no-progress", action="store_true", help="no progress bars")
    args = parser.parse_args(argv)
    if args.cpus is not None and args.address:
        parser.error("--cpus is for the local instance; a cluster has its own")
    if not os.path.isfile(args.matrix):
        parser.error("the matrix [%s] is not a file" % args.matrix)
    if args.out and os.path.exists(args.out) and not os.path.isdir(args.out):
        parser.error("--out [%s] is a file, not a folder" % args.out)
    if args.address:
        host, _, port = args.address.rpartition(":")
        if not host or not port.isdigit() or not 1 <= int(port) <= 65535:
            parser.error("--address [%s] is not HOST:PORT" % args.address)
    return args


def scenario_executable(given):
    if given:
        if not (os.path.isfile(given) and os.access(given, os.X_OK)):
            raise SweepError("--scenario [%s] is not an executable file" % given)
        return os.path.abspath(given)
    from catkin.find_in_workspaces import find_in_workspaces
    found = find_in_workspaces(["libexec"], project="bullet_sim", path="scenario", first_match_only=True)
    if found:
        return found[0]
    if shutil.which("scenario"):
        return shutil.which("scenario")
    raise SweepError("cannot find bullet_sim's scenario executable: source devel/setup.bash, or give --scenario")


def list_cells(scenario, matrix):
    """The matrix's cells, as `scenario --matrix M --list` expands them (the one place that expands them)."""
    listed = subprocess.run([scenario, "--matrix", matrix, "--list"], capture_output=True, text=True)
    said = "; ".join(line.strip() for line in listed.stderr.splitlines() if line.strip())
    if listed.returncode != 0:
        raise SweepError(said or "scenario --list failed with exit code %d" % listed.returncode)
    try:
        return json.loads(listed.stdout)
    except ValueError:
        raise SweepError("scenario --list printed no cells for [%s]" % matrix)


def output_folder(given, name):
    out = os.path.abspath(given or os.path.join("sweep_out", name))
    try:
        os.makedirs(os.path.join(out, "cells"), exist_ok=True)
    except OSError as error:
        raise SweepError("cannot make the sweep's folder [%s]: %s" % (out, error.strerror or error))
    return out


def reach(address):
    """Fails in one line when nothing listens at --address (Ray itself would retry for a minute)."""
    host, _, port = address.rpartition(":")
    try:
        socket.create_connection((host.strip("[]"), int(port)), timeout=REACH_TIMEOUT).close()
    except OSError as error:
        raise SweepError("cannot reach a Ray cluster at %s: %s" % (address, error.strerror or error))


def write_cell(out, index, files):
    """A run's files, as it wrote them on its node, into OUT/cells/NNNN (emptied first)."""
    folder = os.path.join(out, "cells", "%04d" % index)
    shutil.rmtree(folder, ignore_errors=True)
    for name, data in files.items():
        path = os.path.join(folder, name)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "wb") as file:
            file.write(data)


def run_all(ray, args, scenario, cells, out):
    """Submits every cell and gathers the runs as they end; returns them by index, and the starts."""
    matrix = os.path.abspath(args.matrix)
    commands = {cell["index"]: [scenario, "--matrix", matrix, "--index", str(cell["index"])] +
                (["--video"] if args.video else []) for cell in cells}
    nodes = {node: state for node, state in nodes_of(ray).items() if state["alive"]}
    tasks = Cells(ray, commands, dict(os.environ), args.timeout, args.retries)
    progress = Progress(len(cells), nodes, not args.no_progress)
    begun = time.monotonic()
    runs = {}
    try:
        while tasks.pending:
            for index, node, _, _ in tasks.new_starts():
                progress.began(index, node)
            for index, run in tasks.ended(WAIT_STEP):
                write_cell(out, index, run.pop("files"))
                run["ended_s"] = time.monotonic() - begun
                runs[index] = run
                progress.ended(index, run["node"], status_of(run))
            for node, state in nodes_of(ray).items():
                if not state["alive"]:
                    progress.lost(node)
            progress.refresh()
        tasks.new_starts()
    finally:
        progress.close()
    return runs, tasks.began


def settled_nodes(ray, starts):
    """The cluster's nodes once Ray has settled whether each node a run was begun again from is lost: a run
    leaves its node when its worker or its node is lost, and Ray tells the two apart only when the node's health
    checks fail, which may come after the sweep's last run (bounded by NODE_DEATH_WAIT_S)."""
    nodes_per_cell = {}
    for index, node, *_ in starts:
        nodes_per_cell.setdefault(index, []).append(node)
    left = {node for began_on in nodes_per_cell.values() for node in began_on[:-1]}
    deadline = time.monotonic() + NODE_DEATH_WAIT_S
    while True:
        nodes = nodes_of(ray)
        if not any(nodes.get(node, {}).get("alive") for node in left) or time.monotonic() > deadline:
            return nodes
        time.sleep(WAIT_STEP)


def main(argv=None):
    args = parse_arguments(sys.argv[1:] if argv is None else argv)
    try:
        return sweep(args)
    except SweepError as error:
        print("sweep: %s" % error, file=sys.stderr)
        return 2


def sweep(args):
    scenario = scenario_executable(args.scenario)
    listing = list_cells(scenario, args.matrix)
    if args.address:
        reach(args.address)
    out = output_folder(args.out, listing["name"])
    started = time.monotonic()
    ray = start_ray(args.address, args.cpus)
    try:
        nodes_at_start = nodes_of(ray)
        ray_ready = time.monotonic()
        runs, starts = run_all(ray, args, scenario, listing["cells"], out)
        finished = time.monotonic()
        nodes_at_end = settled_nodes(ray, starts)
    finally:
        ray.shutdown()
    from bullet_sim_sweep import report  # matplotlib: not needed to refuse a bad argument
    rows = [report.row_of(cell["index"], cell["values"], status_of(runs[cell["index"]]), runs[cell["index"]],
                          [start for start in starts if start[0] == cell["index"]]) for cell in listing["cells"]]
    report.write_table(rows, os.path.join(out, "results.csv"), os.path.join(out, "results.json"))
    report.write_summary(rows, listing["axes"], "%s: %d runs" % (listing["name"], len(rows)),
                         os.path.join(out, "summary.png"))
    nodes = {node: dict(nodes_at_end[node], cpus=nodes_at_start.get(node, nodes_at_end[node])["cpus"])
             for node in nodes_at_end}  # a lost node has no CPUs left
    alive_at_start = {node for node, state in nodes_at_start.items() if state["alive"]}
    summary = report.sweep_summary(rows, starts, nodes, alive_at_start, ray_ready - started, finished - ray_ready)
    summary.update(matrix=os.path.abspath(args.matrix), address=args.address, cpus=args.cpus, retries=args.retries)
    with open(os.path.join(out, "sweep.json"), "w") as file:
        json.dump(summary, file, indent=2)
        file.write("\n")
    report.print_summary(listing["name"], summary, rows, os.path.join(out, "results.csv"))
    statuses = [row["status"] for row in rows]
    if all(s == "pass" for s in statuses):
        return 0
    return 1 if all(s in ("pass", "fail") for s in statuses) else 2
