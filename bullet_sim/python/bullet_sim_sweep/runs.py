"""One run of a matrix cell: `scenario --matrix M --index N` as a subprocess, pinned to one core of its node.

The same command is what a batch system runs per array index; here Ray schedules it as a task of one CPU. The run
writes into a temporary folder under its node's Ray temp dir, and its files travel back with its result, so the
sweep's folder needs no sharing between nodes.
"""
import fcntl
import json
import os
import shutil
import subprocess
import tempfile
import time

# Where the runs of one machine take their cores: one lock file per core, held for the run.
CORE_LOCKS = os.path.join(tempfile.gettempdir(), "bullet_sim_cores")
# The run's libraries stay on one thread: llvmpipe's rasteriser, OpenMP; Embree's TBB and the simulation's
# pool follow the affinity.
ONE_THREAD = {"LP_NUM_THREADS": "1", "OMP_NUM_THREADS": "1"}
LOG_TAIL = 4000  # characters of a failed run's log that its result carries


class CoreLock:
    """Holds the lock of a core of this machine that no other run holds, and pins to it.

    Ray runs at most as many one-CPU tasks on a node as it has CPUs, so with no more CPUs than cores a free
    one is always there; should none be (a node that claims more CPUs than it has), the run waits for one.
    """

    def __init__(self):
        self.core = None
        self.file = None

    def __enter__(self):
        os.makedirs(CORE_LOCKS, exist_ok=True)
        cores = sorted(os.sched_getaffinity(0))
        while self.core is None:
            for core in cores:
                handle = open(os.path.join(CORE_LOCKS, "core_%d.lock" % core), "w")
                try:
                    fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
                except OSError:
                    handle.close()
                    continue
                self.core, self.file = core, handle
                break
            else:
                # Every core is taken: block on the first one's lock until its run ends.
                handle = open(os.path.join(CORE_LOCKS, "core_%d.lock" % cores[0]), "w")
                fcntl.flock(handle, fcntl.LOCK_EX)
                self.core, self.file = cores[0], handle
        return self.core

    def __exit__(self, *exc):
        fcntl.flock(self.file, fcntl.LOCK_UN)
        self.file.close()


def note_start(starts, index, node):
    """Tells the sweep that cell `index` began on `node`, without waiting (a task waiting in ray.get gives its CPU
    back to Ray, which would start another run meanwhile)."""
    starts.begin.remote(index, node, os.uname().nodename)


def read_folder(folder):
    """Every file under `folder`: {relative path: bytes}."""
    files = {}
    for root, _, names in os.walk(folder):
        for name in names:
            path = os.path.join(root, name)
            with open(path, "rb") as file:
                files[os.path.relpath(path, folder)] = file.read()
    return files


def run_cell(index, command, env, timeout, starts):
    """Runs `command --out FOLDER` (cell `index` of a matrix) on one core of this node; returns what the table
    needs and the files the run wrote.

    A run is judged by its exit code: 0 pass, 1 a check failed, 2 could not run; anything else (a signal, a
    crash) is a crash. Neither is retried here: only a lost Ray worker or node makes Ray run the task again.
    The run's environment is its node's with the sweep's variables on top.
    """
    import ray
    context = ray.get_runtime_context()
    node = context.get_node_id()
    if not os.access(command[0], os.X_OK):  # else taskset's exit code 1 would read as a failed check
        return {"exit_code": None, "timed_out": False, "wall_s": 0.0, "host": os.uname().nodename, "node": node,
                "result": None, "files": {}, "began": False, "log": None,
                "no_run": "no scenario executable [%s] on this node (%s): is the workspace at the same path on "
                             "every node?" % (command[0], os.uname().nodename)}
    note_start(starts, index, node)
    # Under the node's Ray temp dir: what a lost worker leaves behind stays with the node's Ray files.
    runs = os.path.join(context.get_temp_dir(), "bullet_sim_runs")
    os.makedirs(runs, exist_ok=True)
    out = tempfile.mkdtemp(prefix="cell_%04d_" % index, dir=runs)
    started = time.monotonic()
    try:
        log_path = os.path.join(out, "scenario.log")
        with CoreLock() as core, open(log_path, "w") as log:
            # The run ends with its Ray worker (a lost node's runs must not run on beside their retries).
            pinned = ["setpriv", "--pdeathsig", "KILL", "taskset", "-c", str(core)] + command + ["--out", out]
            try:
                exit_code = subprocess.run(pinned, env=dict(os.environ, **env, **ONE_THREAD), stdout=log,
                                           stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
                                           timeout=timeout).returncode
            except subprocess.TimeoutExpired:
                exit_code = None
        run = {"exit_code": exit_code, "timed_out": exit_code is None, "wall_s": time.monotonic() - started,
               "core": core, "host": os.uname().nodename, "node": node, "result": None, "log": None,
               "files": read_folder(out)}
    finally:
        shutil.rmtree(out, ignore_errors=True)
    try:
        run["result"] = json.loads(run["files"].get("result.json", b""))
    except ValueError:
        pass
    if exit_code != 0:
        run["log"] = run["files"].get("scenario.log", b"").decode(errors="replace")[-LOG_TAIL:]
    return run


def status_of(run):
    """pass, fail (a check failed), error (could not run), crash (killed, or an exit code no run gives),
    timeout, never_started (Ray could not begin it: a worker that cannot load the task, a node lost before) or
    lost (it began, but its worker or node was lost more than --retries times)."""
    if run.get("no_run"):
        return "lost" if run["began"] else "never_started"
    if run["timed_out"]:
        return "timeout"
    return {0: "pass", 1: "fail", 2: "error"}.get(run["exit_code"], "crash")
