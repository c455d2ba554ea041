"""The sweep's side of Ray: joining or starting a cluster, a task per cell spread over its nodes, and where and
when each cell's runs began (a cell whose run began twice was run again after a lost worker or node)."""
import os
import re
import sys
import tempfile
import threading
import time

from bullet_sim_sweep.runs import LOG_TAIL, run_cell

STARTS_POLL_TIMEOUT = 5.0  # [s] the sweep waits for the record of starts once a second
STARTS_READY_TIMEOUT = 60.0  # [s] for that record's actor to start
JOIN_TIMEOUT = 60.0  # [s] for ray.init
ANSI = re.compile(r"\x1b\[[0-9;]*m")


class SweepError(Exception):
    """A bad argument, a bad matrix or a cluster that cannot be reached: said in one line, exit code 2."""


class Starts:
    """A Ray actor on the sweep's node: every run's start, as (cell, node id, host, time), in order."""

    def __init__(self):
        self.starts = []

    def begin(self, index, node, host):
        self.starts.append((index, node, host, time.time()))

    def since(self, count):
        return self.starts[count:]


def start_ray(address, cpus):
    """Ray, joined to the cluster at `address`, or a local instance of `cpus` CPUs."""
    if not address:
        # A local instance keeps to the loopback address rather than the machine's own IP.
        os.environ.setdefault("RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER", "0")
    import ray
    options = dict(include_dashboard=False, log_to_driver=False, logging_level="WARNING")
    if address:
        join(ray, address, options)
        return ray
    try:
        ray.init(num_cpus=cpus, **options)
    except Exception as error:  # Ray raises ConnectionError, RuntimeError or ValueError, with long texts
        raise SweepError("could not start a local Ray instance: %s" % first_line(error))
    return ray


def join(ray, address, options):
    """ray.init(address): Ray's warnings while it connects are held back (and shown once it has joined), and a
    listener that is no Ray cluster, on which Ray would wait for minutes, is said in one line after JOIN_TIMEOUT."""
    terminal = os.dup(2)
    held = tempfile.TemporaryFile()
    os.dup2(held.fileno(), 2)
    why = "could not join the Ray cluster at %s within %.0f s: is it a Ray %s cluster, with the same " \
          "RAY_AUTH_MODE?" % (address, JOIN_TIMEOUT, ray.__version__)
    watchdog = threading.Timer(JOIN_TIMEOUT, give_up, [terminal, why])
    watchdog.daemon = True
    watchdog.start()
    try:
        ray.init(address=address, **options)
    except Exception as error:  # Ray raises ConnectionError, RuntimeError or ValueError, with long texts
        raise SweepError("could not join the Ray cluster at %s: %s" % (address, first_line(error)))
    finally:
        watchdog.cancel()
        os.dup2(terminal, 2)
        os.close(terminal)
    held.seek(0)
    sys.stderr.write(held.read().decode(errors="replace"))
    held.close()


def give_up(terminal, message):
    os.write(terminal, ("sweep: %s\n" % message).encode())
    os._exit(2)


def first_line(error):
    lines = [line.strip() for line in ANSI.sub("", str(error)).splitlines() if line.strip()]
    return lines[0] if lines else type(error).__name__


def worker_error(error):
    """What Ray said about a task that gave no result, without colours: its last lines, which name the cause."""
    text = ANSI.sub("", str(error)).strip()
    lines = [line.strip() for line in text.splitlines() if line.strip() and not line.strip().startswith("^")]
    reason = lines[-1] if lines else type(error).__name__
    if "failed to import on the worker" in text:
        reason += (" (the worker could not load bullet_sim_sweep: start each Ray node from a shell that sourced "
                   "the workspace's devel/setup.bash)")
    return reason, text[-LOG_TAIL:]


def nodes_of(ray):
    """The cluster's nodes that can run cells: {node id: {address, cpus, alive}}."""
    return {node["NodeID"]: {"address": node["NodeManagerAddress"], "cpus": node["Resources"].get("CPU", 0),
                             "alive": node["Alive"]}
            for node in ray.nodes() if node["Resources"].get("CPU", 0) > 0 or not node["Alive"]}


class Cells:
    """Every cell as a Ray task of one CPU, spread over the nodes; gathers the runs as they end."""

    def __init__(self, ray, commands, env, timeout, retries):
        from ray.util.scheduling_strategies import NodeAffinitySchedulingStrategy
        self.ray = ray
        here = NodeAffinitySchedulingStrategy(ray.get_runtime_context().get_node_id(), soft=False)
        self.starts = ray.remote(Starts).options(num_cpus=0, scheduling_strategy=here).remote()
        self.began = []  # (cell, node id, host, time) in order
        # Up before the first run tells it where it began: a note to an actor still starting is lost with its run.
        self.new_starts(timeout=STARTS_READY_TIMEOUT)
        task = ray.remote(run_cell).options(num_cpus=1, max_retries=retries, retry_exceptions=False,
                                            scheduling_strategy="SPREAD")
        self.pending = {task.remote(index, command, env, timeout, self.starts): index
                        for index, command in commands.items()}

    def new_starts(self, timeout=STARTS_POLL_TIMEOUT):
        """The starts noted since the last call."""
        try:
            new = self.ray.get(self.starts.since.remote(len(self.began)), timeout=timeout)
        except (self.ray.exceptions.RayError, self.ray.exceptions.GetTimeoutError):
            return []
        self.began += new
        return new

    def ended(self, wait_s):
        """The cells whose task ended within `wait_s`: [(index, run)]."""
        ready, _ = self.ray.wait(list(self.pending), num_returns=len(self.pending), timeout=wait_s)
        runs = []
        for reference in ready:
            index = self.pending.pop(reference)
            try:
                runs.append((index, self.ray.get(reference)))
            except self.ray.exceptions.RayError as error:  # lost more than --retries times, or never loaded
                self.new_starts()
                reason, text = worker_error(error)
                began = isinstance(error, self.ray.exceptions.WorkerCrashedError) or any(
                    start[0] == index for start in self.began)  # its worker died while running it
                runs.append((index, {"exit_code": None, "timed_out": False, "wall_s": 0.0, "host": "", "node": "",
                                     "result": None, "files": {}, "no_run": reason, "began": began,
                                     "log": text}))
        return runs
