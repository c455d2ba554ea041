#!/usr/bin/env python3
"""sweep's account of lost nodes: a node a run was begun again from is reported lost once Ray says it died,
even when Ray says so only after the sweep's last run; a node that stays alive (its worker was lost, not the
node) is not waited for beyond the bound."""
import unittest

import rostest
from bullet_sim_sweep import cli


class FakeRay:
    """ray.nodes() as Ray answers it: node `dies` reported alive for its first `alive_for` answers."""

    def __init__(self, dies, alive_for):
        self.dies, self.alive_for, self.answers = dies, alive_for, 0

    def nodes(self):
        self.answers += 1
        return [{"NodeID": node, "NodeManagerAddress": "127.0.0.1", "Resources": {"CPU": 1},
                 "Alive": node != self.dies or self.answers <= self.alive_for} for node in ("head", "second")]


class SweepNodes(unittest.TestCase):
    def setUp(self):
        self.wait, self.step = cli.NODE_DEATH_WAIT_S, cli.WAIT_STEP
        cli.WAIT_STEP = 0.01

    def tearDown(self):
        cli.NODE_DEATH_WAIT_S, cli.WAIT_STEP = self.wait, self.step

    def test_a_node_a_run_left_is_waited_for_until_ray_says_it_died(self):
        ray = FakeRay("second", alive_for=3)
        starts = [(0, "second", "b", 1.0), (1, "head", "a", 1.0), (0, "head", "a", 2.0)]
        nodes = cli.settled_nodes(ray, starts)
        self.assertFalse(nodes["second"]["alive"])
        self.assertTrue(nodes["head"]["alive"])
        self.assertEqual(ray.answers, 4)

    def test_no_run_begun_again_asks_once(self):
        ray = FakeRay("second", alive_for=3)
        nodes = cli.settled_nodes(ray, [(0, "second", "b", 1.0), (1, "head", "a", 1.0)])
        self.assertTrue(nodes["second"]["alive"])
        self.assertEqual(ray.answers, 1)

    def test_a_node_that_stays_alive_is_waited_for_at_most_the_bound(self):
        cli.NODE_DEATH_WAIT_S = 0.05
        ray = FakeRay("second", alive_for=10 ** 6)
        nodes = cli.settled_nodes(ray, [(0, "second", "b", 1.0), (0, "head", "a", 2.0)])
        self.assertTrue(nodes["second"]["alive"])  # its worker was lost, not the node
        self.assertLess(ray.answers, 100)


if __name__ == "__main__":
    rostest.rosrun("bullet_sim_bringup", "sweep_nodes", SweepNodes)
