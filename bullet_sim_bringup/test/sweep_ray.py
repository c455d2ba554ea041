#!/usr/bin/env python3
"""sweep on a Ray cluster of its own: `ray start --head --num-cpus 2` on 127.0.0.1 with its own ports and temp
dir, joined with --address, runs the 8 cells of drive_matrix.yaml with the results that running them one by one
gives; a run whose worker is lost runs again (or, with --retries 0, is reported lost); stopping the cluster
leaves no process of it behind."""
import csv
import json
import os
import subprocess
import tempfile
import unittest

import rospkg
import rostest

from sweep_support import RAY_ENV, SWEEP, processes_with, start_head, write_stand_in

MATRIX = os.path.join(rospkg.RosPack().get_path("bullet_sim"), "test/fixtures/scenarios/drive_matrix.yaml")


# A stand-in for `scenario` that loses its Ray worker on cell 0's first attempt and crashes on cell 1 (each
# attempt is counted in a file); every other call is the real scenario's.
FLAKY_SCENARIO = """#!/usr/bin/env python3
import os, signal, sys
arguments = sys.argv[1:]
if "--index" in arguments:
    index = int(arguments[arguments.index("--index") + 1])
    with open(os.path.join(%(folder)r, "attempts_%%d" %% index), "a") as file:
        file.write("x")
    with open(os.path.join(%(folder)r, "attempts_%%d" %% index)) as file:
        attempts = len(file.read())
    if index == 0 and attempts == 1:
        os.kill(os.getppid(), signal.SIGKILL)  # the Ray worker running this task (taskset exec'd into us)
        sys.exit(0)
    if index == 1:
        print("crashing on purpose", flush=True)
        os.kill(os.getpid(), signal.SIGSEGV)
os.execv(%(real)r, [%(real)r] + arguments)
"""


# A stand-in for `scenario` that loses its Ray worker on cell 0 and passes every other cell at once.
LOSING_SCENARIO = """#!/usr/bin/env python3
import os, signal, sys
arguments = sys.argv[1:]
if "--index" not in arguments:  # --list
    os.execv(%(real)r, [%(real)r] + arguments)
if arguments[arguments.index("--index") + 1] == "0":
    os.kill(os.getppid(), signal.SIGKILL)
"""


def write_flaky_scenario(folder):
    return write_stand_in(folder, "flaky_scenario", FLAKY_SCENARIO)


def without_timing(result):
    return {key: value for key, value in result.items() if key != "timing"}


class SweepOnRay(unittest.TestCase):
    def test_a_sweep_gives_the_results_of_runs_one_by_one(self):
        folder = tempfile.mkdtemp(prefix="sweep_ray_")
        temp_dir = os.path.join(folder, "ray")  # Ray keeps its sockets here: a short path
        self.assertEqual(processes_with(temp_dir), {})
        # A cluster of this machine alone, on the loopback address.
        env = dict(os.environ, RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER="0", **RAY_ENV)
        head, address = start_head(temp_dir, 2, env)
        try:
            out = os.path.join(folder, "sweep")
            sweep = subprocess.run(SWEEP + [MATRIX, "--address", address,
                                    "--out", out, "--no-progress"], env=env, capture_output=True, text=True,
                                   timeout=120)
            flaky = subprocess.run(SWEEP + [MATRIX, "--address", address,
                                    "--out", os.path.join(folder, "flaky"), "--no-progress", "--scenario",
                                    write_flaky_scenario(folder)], env=env, capture_output=True, text=True,
                                   timeout=120)
            lost = subprocess.run(SWEEP + [MATRIX, "--address", address, "--retries", "0",
                                   "--out", os.path.join(folder, "lost"), "--no-progress", "--scenario",
                                   write_stand_in(folder, "losing_scenario", LOSING_SCENARIO)], env=env,
                                  capture_output=True, text=True, timeout=120)
        finally:
            head.stop()
        self.assertEqual(processes_with(temp_dir), {})
        # v = 0.4 m/s falls 0.4 m short of the region and the final pose: a check fails, so the sweep exits 1.
        self.assertEqual(sweep.returncode, 1, sweep.stdout + sweep.stderr)
        self.assertIn("8 runs, 4 passed, 4 failed, 0 could not run or crashed", sweep.stdout)
        with open(os.path.join(out, "results.csv")) as file:
            rows = list(csv.DictReader(file))
        self.assertEqual([row["status"] for row in rows], ["fail"] * 4 + ["pass"] * 4)
        self.assertTrue(os.path.getsize(os.path.join(out, "summary.png")) > 0)
        with open(os.path.join(out, "results.json")) as file:
            self.assertEqual(len(json.load(file)), 8)
        self.check_retries(folder, flaky)
        self.check_lost(os.path.join(folder, "lost"), lost)
        for index in range(8):
            alone = os.path.join(folder, "alone", str(index))
            run = subprocess.run(["rosrun", "bullet_sim", "scenario", "--matrix", MATRIX, "--index", str(index),
                                  "--out", alone], capture_output=True, text=True, timeout=60)
            self.assertEqual(run.returncode, 0 if index >= 4 else 1, run.stdout + run.stderr)
            with open(os.path.join(alone, "result.json")) as file:
                expected = without_timing(json.load(file))
            with open(os.path.join(out, "cells", "%04d" % index, "result.json")) as file:
                self.assertEqual(without_timing(json.load(file)), expected)

    def check_retries(self, folder, flaky):
        """A lost worker's run ran again and counts; a crash ran once and is reported with its code and log."""
        self.assertEqual(flaky.returncode, 2, flaky.stdout + flaky.stderr)
        with open(os.path.join(folder, "attempts_0")) as file:
            self.assertEqual(file.read(), "xx")
        with open(os.path.join(folder, "attempts_1")) as file:
            self.assertEqual(file.read(), "x")
        with open(os.path.join(folder, "flaky", "results.json")) as file:
            rows = json.load(file)
        self.assertEqual(rows[0]["status"], "fail")  # v = 0.4 m/s: its checks, as without the lost worker
        self.assertEqual(rows[1]["status"], "crash")
        self.assertEqual(rows[1]["exit_code"], -11)  # SIGSEGV
        self.assertIn("crashing on purpose", rows[1]["log_tail"])
        self.assertIn("cell 1: crash (exit code -11)", flaky.stderr)

    def check_lost(self, out, lost):
        """With --retries 0, the run whose worker was lost is lost: it began once, and is no timeout."""
        self.assertEqual(lost.returncode, 2, lost.stdout + lost.stderr)
        with open(os.path.join(out, "results.json")) as file:
            row = json.load(file)[0]
        self.assertEqual((row["status"], row["attempts"]), ("lost", 1))
        self.assertIn("The worker died unexpectedly while executing this task", row["message"])
        self.assertIn("cell 0: lost: The worker died", lost.stderr)


if __name__ == "__main__":
    rostest.rosrun("bullet_sim_bringup", "sweep_ray", SweepOnRay)
