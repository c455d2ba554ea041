#!/usr/bin/env python3
"""rostest node: the simulator builds and sends a topic's messages only while someone subscribes to it (it
counts roscpp's connects and disconnects), so a subscriber that comes late, and one that comes back after
unsubscribing, must still hear every topic: the wheelchair's /odom, /scan and /tf, first after a second of sim
time with nobody listening, then again after each subscriber has gone."""
import sys
import unittest

import rospy
import rostest
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import LaserScan
from tf2_msgs.msg import TFMessage

from bringup_support import Collector

TOPICS = (("/odom", Odometry), ("/scan", LaserScan), ("/tf", TFMessage))


class LateListener(unittest.TestCase):
    def test_late_and_returning_subscribers_hear_every_topic(self):
        clock = Collector("/clock", Clock)
        clock.wait_for(lambda m: m and m[-1].clock.to_sec() > 1.0, 60, "a second of sim time")
        clock.close()
        for visit in ("late", "back again"):
            for topic, kind in TOPICS:
                heard = Collector(topic, kind)
                heard.wait_for(lambda m: len(m) >= 3, 30, "three messages on %s, subscribing %s" % (topic, visit))
                heard.close()


if __name__ == "__main__":
    rospy.init_node("late_listener")
    rostest.rosrun("bullet_sim_bringup", "late_listener", LateListener, sys.argv)
