#!/usr/bin/env python3
"""sweep answers every bad argument and bad matrix file with one line on stderr that names the value, and exit
code 2, before any Ray starts: a row per case."""
import os
import socket
import subprocess
import tempfile
import unittest

import rospkg
import rostest

MATRIX = os.path.join(rospkg.RosPack().get_path("bullet_sim"), "test/fixtures/scenarios/drive_matrix.yaml")
SCENARIO = os.path.join(rospkg.RosPack().get_path("bullet_sim"), "test/fixtures/scenarios/reach_region.yaml")
RUN_TIMEOUT = 30  # [s]


def closed_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]  # nothing listens once it is closed


def cases(folder):
    """(arguments, what the line must say)."""
    a_file = os.path.join(folder, "a_file")
    not_executable = os.path.join(folder, "not_executable")
    for path in (a_file, not_executable):
        with open(path, "w") as file:
            file.write("x\n")

    def matrix(name, text):
        path = os.path.join(folder, name)
        with open(path, "w") as file:
            file.write(text)
        return path

    port = closed_port()
    return [
        ([], "the following arguments are required: matrix"),
        (["nope.yaml"], "the matrix [nope.yaml] is not a file"),
        ([folder], "the matrix [%s] is not a file" % folder),
        ([MATRIX, "--out", a_file], "--out [%s] is a file, not a folder" % a_file),
        ([MATRIX, "--out", os.path.join(a_file, "sub")], "cannot make the sweep's folder [%s/sub]" % a_file),
        ([MATRIX, "--cpus", "0"], "argument --cpus: [0] is not in 1 to 4096"),
        ([MATRIX, "--cpus", "two"], "argument --cpus: [two] is not a whole number"),
        ([MATRIX, "--cpus", "2", "--address", "127.0.0.1:6379"], "--cpus is for the local instance"),
        ([MATRIX, "--retries", "-1"], "argument --retries: [-1] is not in 0 to 100"),
        ([MATRIX, "--retries", "1e9"], "argument --retries: [1e9] is not a whole number"),
        ([MATRIX, "--timeout", "nan"], "argument --timeout: [nan] is not a positive number of seconds"),
        ([MATRIX, "--timeout", "inf"], "argument --timeout: [inf] is not a positive number of seconds"),
        ([MATRIX, "--timeout", "-5"], "argument --timeout: [-5] is not a positive number of seconds"),
        ([MATRIX, "--timeout", "soon"], "argument --timeout: [soon] is not a positive number of seconds"),
        ([MATRIX, "--address", "headnode"], "--address [headnode] is not HOST:PORT"),
        ([MATRIX, "--address", "127.0.0.1:99999"], "--address [127.0.0.1:99999] is not HOST:PORT"),
        ([MATRIX, "--address", ":6379"], "--address [:6379] is not HOST:PORT"),
        ([MATRIX, "--address", "127.0.0.1:%d" % port],
         "cannot reach a Ray cluster at 127.0.0.1:%d: Connection refused" % port),
        ([MATRIX, "--scenario", os.path.join(folder, "nope")], "--scenario [%s/nope] is not an executable file"
         % folder),
        ([MATRIX, "--scenario", not_executable], "--scenario [%s] is not an executable file" % not_executable),
        ([MATRIX, "--bogus"], "unrecognized arguments: --bogus"),
        ([matrix("missing.yaml", "scenario: nope.yaml\naxes: {seed: [1]}\n")],
         "scenario [%s/nope.yaml] is not a file" % folder),
        ([matrix("wraps.yaml", "scenario: %s\naxes: {seed: {from: 9223372036854775807, count: 2}}\n" % SCENARIO)],
         "axes.seed: {from: 9223372036854775807, count: 2} goes past the largest whole number"),
        ([matrix("huge.yaml", "scenario: %s\naxes: {seed: {from: 1, count: 1000000000}}\n" % SCENARIO)],
         "count 1 to 100000"),
        ([matrix("negative.yaml", "scenario: %s\naxes: {seed: {from: -5, count: 2}}\n" % SCENARIO)],
         "seed: [-5] is out of range"),
        ([matrix("wide.yaml", "scenario: %s\naxes: {seed: {from: 1, count: 1001}, duration: {from: 1, count: 1000}}\n"
                 % SCENARIO)], "more than 1000000 cells"),
        ([matrix("empty.yaml", "")], "expected scenario: FILE and axes"),
        ([matrix("garbage.yaml", "scenario: [\n")], "garbage.yaml"),
    ]


class SweepArguments(unittest.TestCase):
    def test_every_bad_argument_is_one_line_and_exit_code_2(self):
        folder = tempfile.mkdtemp(prefix="sweep_arguments_")
        sweep = subprocess.run(["catkin_find", "--first-only", "bullet_sim", "sweep"], capture_output=True,
                               text=True, check=True).stdout.strip()  # what rosrun runs
        for arguments, expected in cases(folder):
            with self.subTest(arguments=arguments):
                run = subprocess.run([sweep] + arguments, cwd=folder, capture_output=True, text=True,
                                     timeout=RUN_TIMEOUT)
                self.assertEqual(run.returncode, 2, run.stderr)
                self.assertEqual(run.stdout, "")
                lines = run.stderr.splitlines()
                self.assertEqual(len(lines), 1, run.stderr)
                self.assertTrue(lines[0].startswith("sweep: "), run.stderr)
                self.assertIn(expected, lines[0])
        self.assertNotIn("sweep_out", os.listdir(folder))  # refused before the sweep made its folder


if __name__ == "__main__":
    rostest.rosrun("bullet_sim_bringup", "sweep_arguments", SweepArguments)
