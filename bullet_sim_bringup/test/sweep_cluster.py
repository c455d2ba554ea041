#!/usr/bin/env python3
"""sweep on a Ray cluster of two nodes that the test starts on this machine (`ray start --head` and `ray start
--address`, one CPU each, their own ports and temp dirs), joined with --address:
1. the cells run on both nodes (by the node id Ray reports per cell) and their files reach the sweep's folder;
2. the second node's raylet, killed by its PID while it runs a cell, costs the time to run that cell again on
   the head: no cell lost or counted twice, and the exit code, results.csv and sweep.json say so;
3. a node whose workers cannot import the sweep's module has its cells reported as never started, with the
   worker's error, never as timeouts.
The nodes register with the machine's address (Ray puts a node that others join on a reachable address, not on
the loopback); the test stops them by their PIDs, never with `ray stop`."""
import csv
import json
import os
import signal
import subprocess
import tempfile
import time
import unittest

import rospkg
import rostest

from sweep_support import POLL, RAY_ENV, SWEEP, processes_with, raylet_of, start_head, start_node, write_stand_in

MATRIX = os.path.join(rospkg.RosPack().get_path("bullet_sim"), "test/fixtures/scenarios/drive_matrix.yaml")
SWEEP_TIMEOUT = 120  # [s]
HOLD_TIMEOUT = 60  # [s] a held run waits for its node to be killed
LOST_RUN_TIMEOUT = 30  # [s] for a run on a killed node to end with its Ray worker
# A lost node is noticed after about period x threshold (Ray's defaults take 15 s and more).
FAST_HEALTH_CHECKS = {"RAY_health_check_period_ms": "500", "RAY_health_check_timeout_ms": "1000",
                      "RAY_health_check_failure_threshold": "4"}

# Stand-ins for `scenario` (`--list` is the real one's). Every run notes its node (the second node's raylet has
# SWEEP_TEST_NODE=second, which its workers inherit). The holding one's runs on the second node say their PID and
# wait, to be lost with their node; every other run passes at once.
PASSING_SCENARIO = """#!/usr/bin/env python3
import os, sys, time
arguments = sys.argv[1:]
if "--index" not in arguments:
    os.execv(%(real)r, [%(real)r] + arguments)
index = int(arguments[arguments.index("--index") + 1])
node = os.environ.get("SWEEP_TEST_NODE", "head")
with open(os.path.join(%(folder)r, "began_%%d" %% index), "a") as file:
    file.write(node + " ")
"""
HOLDING_SCENARIO = PASSING_SCENARIO + """
if node == "second":
    with open(os.path.join(%(folder)r, "held_%%d" %% index), "w") as file:
        file.write(str(os.getpid()))
    deadline = time.monotonic() + %(hold)d
    while time.monotonic() < deadline:
        time.sleep(0.1)
    sys.exit(3)
"""


def read_rows(out):
    with open(os.path.join(out, "results.csv")) as file:
        return list(csv.DictReader(file))


def read_summary(out):
    with open(os.path.join(out, "sweep.json")) as file:
        return json.load(file)


def pid_alive(pid):
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    return True


def ends_within(pid, seconds):
    """Whether process `pid` is gone within `seconds`: a lost node's Ray worker notices its raylet's death on its
    own time, and its run (killed with it) may outlive the sweep's retry of it by a moment on a busy machine."""
    deadline = time.monotonic() + seconds
    while pid_alive(pid) and time.monotonic() < deadline:
        time.sleep(POLL)
    return not pid_alive(pid)


def without_workspace_python(environment):
    """`environment` whose PYTHONPATH lacks this workspace's Python packages (bullet_sim_sweep among them)."""
    paths = [path for path in environment.get("PYTHONPATH", "").split(":")
             if path and not os.path.exists(os.path.join(path, "bullet_sim_sweep"))]
    return dict(environment, PYTHONPATH=":".join(paths))


class SweepOnTwoNodes(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.folder = tempfile.mkdtemp(prefix="sweep_cluster_")
        cls.head_dir = os.path.join(cls.folder, "head")  # Ray keeps its sockets here: short paths
        cls.second_dir = os.path.join(cls.folder, "second")
        cls.env = dict(os.environ, **RAY_ENV, **FAST_HEALTH_CHECKS)
        cls.env.pop("RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER", None)  # "0" would refuse a second node
        cls.nodes = []
        try:
            head, cls.address = start_head(cls.head_dir, 1, cls.env)
            cls.nodes.append(head)
            cls.nodes.append(start_node(cls.address, cls.second_dir, 1, dict(cls.env, SWEEP_TEST_NODE="second")))
        except Exception:
            cls.tearDownClass()
            raise
        cls.head_id = raylet_of(cls.head_dir)[1]
        cls.second_raylet, cls.second_id = raylet_of(cls.second_dir)

    @classmethod
    def tearDownClass(cls):
        for node in reversed(cls.nodes):
            node.stop()
            assert processes_with(node.temp_dir) == {}, processes_with(node.temp_dir)

    def sweep(self, name, *options):
        out = os.path.join(self.folder, name)
        command = SWEEP + [MATRIX, "--address", self.address, "--out", out,
                   "--no-progress"]
        return out, subprocess.Popen(command + list(options), env=self.env, stdout=subprocess.PIPE,
                                     stderr=subprocess.PIPE, text=True)

    def test_1_cells_run_on_both_nodes(self):
        out, sweep = self.sweep("both")
        stdout, stderr = sweep.communicate(timeout=SWEEP_TIMEOUT)
        self.assertEqual(sweep.returncode, 1, stdout + stderr)  # v = 0.4 m/s falls short of the region
        self.assertIn("8 runs, 4 passed, 4 failed, 0 could not run or crashed", stdout)
        rows = read_rows(out)
        self.assertEqual([row["status"] for row in rows], ["fail"] * 4 + ["pass"] * 4)
        self.assertEqual({row["node"] for row in rows}, {self.head_id, self.second_id})
        for row in rows:  # each run wrote into a temporary folder of its node: its files came back through Ray
            self.assertTrue(os.path.isfile(os.path.join(out, "cells", "%04d" % int(row["index"]), "result.json")))
        for temp_dir in (self.head_dir, self.second_dir):  # where the runs wrote, emptied once the files left
            self.assertEqual(os.listdir(os.path.join(temp_dir, "bullet_sim_runs")), [])
        nodes = {node["node_id"]: node for node in read_summary(out)["nodes"]}
        self.assertEqual(set(nodes), {self.head_id, self.second_id})
        for node_id, node in nodes.items():
            self.assertEqual(node["runs"], sum(row["node"] == node_id for row in rows))
            self.assertGreater(node["runs_per_min"], 0)
            self.assertFalse(node["lost"])

    def test_2_a_lost_node_costs_its_running_cell_run_again(self):
        notes = os.path.join(self.folder, "holding")
        os.makedirs(notes)
        stand_in = write_stand_in(notes, "holding_scenario", HOLDING_SCENARIO.replace(
            "%(hold)d", str(HOLD_TIMEOUT)))
        out, sweep = self.sweep("lost", "--scenario", stand_in)
        try:
            held = self.wait_for_a_held_run(sweep, notes)
            os.kill(self.second_raylet, signal.SIGKILL)
            stdout, stderr = sweep.communicate(timeout=SWEEP_TIMEOUT)
        finally:
            if sweep.poll() is None:
                sweep.kill()
        index, pid = held
        self.assertTrue(ends_within(pid, LOST_RUN_TIMEOUT), "the lost node's run is still running")
        self.assertEqual(sweep.returncode, 0, stdout + stderr)  # as without the loss: every run passed
        self.assertIn("8 runs, 8 passed, 0 failed, 0 could not run or crashed", stdout)
        self.assertIn("1 lost, 1 runs begun again", stdout)
        rows = read_rows(out)
        self.assertEqual(sorted(int(row["index"]) for row in rows), list(range(8)))  # each cell once
        self.assertEqual([row["status"] for row in rows], ["pass"] * 8)
        with open(os.path.join(notes, "began_%d" % index)) as file:
            self.assertEqual(file.read().split(), ["second", "head"])
        again = rows[index]
        self.assertEqual((again["attempts"], again["node"]), ("2", self.head_id))
        self.assertEqual(again["began_on"].split(), [self.second_id, self.head_id])
        summary = read_summary(out)
        self.assertEqual(summary["lost_nodes"], [self.second_id])
        self.assertEqual(summary["began_again"], [{"index": index, "began_on": [self.second_id, self.head_id]}])
        self.assertEqual(sum(node["runs"] for node in summary["nodes"]), 8)
        self.assertEqual((summary["passed"], summary["failed"], summary["other"]), (8, 0, 0))

    def wait_for_a_held_run(self, sweep, notes):
        """(cell, pid) of the run the second node holds (as the stand-in notes in `notes`), once it holds one."""
        deadline = time.monotonic() + HOLD_TIMEOUT
        while time.monotonic() < deadline and sweep.poll() is None:
            held = [name for name in os.listdir(notes) if name.startswith("held_")]
            if held:
                with open(os.path.join(notes, held[0])) as file:
                    pid = file.read()
                if pid:
                    return int(held[0].split("_")[1]), int(pid)
            time.sleep(POLL)
        self.fail("the second node held no run: %s" % (sweep.communicate(timeout=SWEEP_TIMEOUT),))

    def test_3_cells_whose_worker_cannot_import_the_sweep_never_started(self):
        third_dir = os.path.join(self.folder, "third")
        self.nodes.append(start_node(self.address, third_dir, 1, without_workspace_python(self.env)))
        third_id = raylet_of(third_dir)[1]
        os.makedirs(os.path.join(self.folder, "passing"))
        stand_in = write_stand_in(os.path.join(self.folder, "passing"), "passing_scenario", PASSING_SCENARIO)
        out, sweep = self.sweep("never", "--retries", "0", "--scenario", stand_in)
        stdout, stderr = sweep.communicate(timeout=SWEEP_TIMEOUT)
        self.assertEqual(sweep.returncode, 2, stdout + stderr)
        rows = read_rows(out)
        never = [row for row in rows if row["status"] == "never_started"]
        self.assertTrue(never, stdout + stderr)
        for row in never:
            self.assertIn("No module named 'bullet_sim_sweep'", row["message"])
            self.assertIn("cell %s: never started: ModuleNotFoundError" % row["index"], stderr)
        for row in rows:
            if row["status"] != "never_started":
                self.assertEqual(row["status"], "pass")
                self.assertNotEqual(row["node"], third_id)
        summary = read_summary(out)
        self.assertEqual(summary["statuses"].get("never_started"), len(never))
        self.assertNotIn("timeout", summary["statuses"])
        self.assertIn(third_id, {node["node_id"] for node in summary["nodes"]})
        self.assertEqual(summary["lost_nodes"], [])  # the second, lost before this sweep, is not this sweep's loss


if __name__ == "__main__":
    rostest.rosrun("bullet_sim_bringup", "sweep_cluster", SweepOnTwoNodes)
