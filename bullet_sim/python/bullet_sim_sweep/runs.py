"""One run of a matrix cell: `scenario --matrix M --index N` as a subprocess, pinned to one core of its node.

The same command is what a batch system runs per array index; here Ray schedules it as a task of one CPU.
"""
import fcntl
import json
import os
import subprocess
import tempfile
import time

# Where the runs of one machine take their cores: one lock file per core, held for the run.
CORE_LOCKS = os.path.join(tempfile.gettempdir(), "bullet_sim_cores")
# The run's libraries stay on one thread: llvmpipe's rasteriser, OpenMP; Embree's TBB follows the affinity.
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


def run_cell(command, env, out, timeout):
    """Runs `command` (a scenario run writing into `out`) on one core; returns what the table needs.

    A run is judged by its exit code: 0 pass, 1 a check failed, 2 could not run; anything else (a signal, a
    crash) is a crash. Neither is retried here: only a lost Ray worker or node makes Ray run the task again.
    """
    os.makedirs(out, exist_ok=True)
    log_path = os.path.join(out, "scenario.log")
    started = time.monotonic()
    with CoreLock() as core, open(log_path, "w") as log:
        pinned = ["taskset", "-c", str(core)] + command
        try:
            exit_code = subprocess.run(pinned, env=dict(env, **ONE_THREAD), stdout=log, stderr=subprocess.STDOUT,
                                       stdin=subprocess.DEVNULL, timeout=timeout).returncode
        except subprocess.TimeoutExpired:
            exit_code = None
    result = {"exit_code": exit_code, "wall_s": time.monotonic() - started, "core": core,
              "host": os.uname().nodename, "result": None, "log": None}
    try:
        with open(os.path.join(out, "result.json")) as file:
            result["result"] = json.load(file)
    except (OSError, ValueError):
        pass
    if exit_code != 0:
        with open(log_path, errors="replace") as file:
            result["log"] = file.read()[-LOG_TAIL:]
    return result


def status_of(run):
    """pass, fail (a check failed), error (could not run), crash (killed, or an exit code no run gives) or
    timeout."""
    code = run["exit_code"]
    if code is None:
        return "timeout"
    return {0: "pass", 1: "fail", 2: "error"}.get(code, "crash")
