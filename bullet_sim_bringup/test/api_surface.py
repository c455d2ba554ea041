#!/usr/bin/env python3
"""rostest node: the topics, types, publishers and services of /gazebo match the YAML in ~api (its own ones exactly;
other nodes' publishers as listed)."""
import sys
import time
import unittest

import rosgraph
import rospy
import rostest
import yaml


def snapshot(master):
    publishers, subscribers, services = master.getSystemState()
    types = dict(master.getTopicTypes())
    return ({topic: set(nodes) for topic, nodes in publishers}, {topic: set(nodes) for topic, nodes in subscribers},
            {service for service, _ in services}, types)


class ApiSurface(unittest.TestCase):
    def test_gazebo_api_matches_the_yaml(self):
        with open(rospy.get_param("~api")) as f:
            api = yaml.safe_load(f)
        master = rosgraph.Master("/api_surface")
        deadline = time.monotonic() + 60
        while True:  # the master cannot notify changes: poll it until the system matches or time runs out
            publishers, subscribers, services, types = snapshot(master)
            problems = []
            for topic, spec in api["topics"].items():
                if types.get(topic) != spec["type"]:
                    problems.append("%s has type %s, not %s" % (topic, types.get(topic), spec["type"]))
                if set(spec.get("publishers", [])) != publishers.get(topic, set()):
                    problems.append("%s is published by %s" % (topic, sorted(publishers.get(topic, set()))))
                if not set(spec.get("subscribers", [])) <= subscribers.get(topic, set()):
                    problems.append("%s is subscribed by %s" % (topic, sorted(subscribers.get(topic, set()))))
            extra = sorted(t for t, nodes in publishers.items() if "/gazebo" in nodes and t not in api["topics"]
                           and t != "/rosout")
            if extra:
                problems.append("/gazebo publishes topics the YAML does not list: %s" % extra)
            missing = sorted(set(api["services"]) - services)
            if missing:
                problems.append("missing services %s" % missing)
            if not problems or time.monotonic() > deadline:
                break
            time.sleep(0.5)
        self.assertEqual(problems, [])


if __name__ == "__main__":
    rospy.init_node("api_surface")
    rostest.rosrun("bullet_sim_bringup", "api_surface", ApiSurface, sys.argv)
