#!/usr/bin/env python3
"""rostest node: `scenario --bag` records the wheelchair crossing test_room.world (reach_region.yaml); `rosbag play
--clock` of that bag then serves tf lookups (odom -> base_footprint, the fixed links of /tf_static, the wheels
robot_state_publisher placed) and scans that are the recording's own."""
import math
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import rosbag
import rospkg
import rospy
import rostest
import tf2_ros
from sensor_msgs.msg import LaserScan

from bringup_support import Collector


def recorded(bag_path):
    """The bag's scans by stamp, and every transform of /tf and /tf_static."""
    scans, moving, fixed = {}, [], []
    with rosbag.Bag(bag_path) as bag:
        for topic, message, _ in bag.read_messages(topics=["/scan", "/tf", "/tf_static"]):
            if topic == "/scan":
                scans[message.header.stamp] = message
            else:
                (moving if topic == "/tf" else fixed).extend(message.transforms)
    return scans, moving, fixed


class ReplayBag(unittest.TestCase):
    def setUp(self):
        self.out = tempfile.mkdtemp(prefix="replay_bag_")

    def tearDown(self):
        shutil.rmtree(self.out, ignore_errors=True)

    def assertSameTransform(self, served, expected, what):
        a, b = served.transform, expected.transform
        for axis in "xyz":
            self.assertAlmostEqual(getattr(a.translation, axis), getattr(b.translation, axis), delta=1e-6, msg=what)
        dot = sum(getattr(a.rotation, c) * getattr(b.rotation, c) for c in "xyzw")
        self.assertGreater(abs(dot), 1 - 1e-9, what)

    def test_rosbag_play_serves_the_recorded_transforms_and_scans(self):
        scenario = os.path.join(rospkg.RosPack().get_path("bullet_sim"), "test/fixtures/scenarios/reach_region.yaml")
        run = subprocess.run(["rosrun", "bullet_sim", "scenario", scenario, "--out", self.out, "--bag"],
                             capture_output=True, text=True, timeout=60)
        self.assertEqual(run.returncode, 0, run.stdout + run.stderr)
        bag_path = os.path.join(self.out, "run.bag")
        scans, moving, fixed = recorded(bag_path)
        self.assertEqual(len(scans), 33)  # 6 s at 5.5 Hz

        buffer = tf2_ros.Buffer(cache_time=rospy.Duration(60))
        tf2_ros.TransformListener(buffer)
        served = Collector("/scan", LaserScan)
        play = subprocess.Popen(["rosbag", "play", "--clock", "-q", "-d", "1", bag_path], stdout=subprocess.DEVNULL,
                                stderr=subprocess.PIPE, text=True)
        try:
            served.wait_for(lambda got: len(got) >= 3, 20, "the first scans")
            # A listener that comes after /tf_static was played gets it from the latch, as from a live system.
            late = tf2_ros.Buffer(cache_time=rospy.Duration(60))
            tf2_ros.TransformListener(late)
            _, errors = play.communicate(timeout=40)
        finally:
            play.kill()
        self.assertEqual(play.returncode, 0, errors)
        received = served.wait_for(lambda got: len(got) >= len(scans), 10, "the %d scans of the bag" % len(scans))

        for scan in received:
            self.assertIn(scan.header.stamp, scans)
            original = scans[scan.header.stamp]
            self.assertEqual(scan.header.frame_id, original.header.frame_id)
            self.assertEqual(list(scan.ranges), list(original.ranges))
        self.assertTrue(any(math.isfinite(r) for r in received[-1].ranges), "the walls are in the scans")

        odometry = [t for t in moving if t.header.frame_id == "odom"]
        links = [t for t in moving if t.header.frame_id != "odom"]
        self.assertEqual(len(odometry), 600)  # 100 Hz
        self.assertGreater(len(links), 0)
        for expected in odometry[::7] + links[::11]:
            lookup = buffer.lookup_transform(expected.header.frame_id, expected.child_frame_id, expected.header.stamp)
            self.assertSameTransform(lookup, expected, "%s -> %s at %s" % (
                expected.header.frame_id, expected.child_frame_id, expected.header.stamp.to_sec()))
        self.assertTrue(any(t.child_frame_id == "laser_Link" for t in fixed))
        for expected in fixed:
            for tf in (buffer, late):
                lookup = tf.lookup_transform(expected.header.frame_id, expected.child_frame_id, rospy.Time(0))
                self.assertSameTransform(lookup, expected, expected.child_frame_id)
        last = odometry[-1]
        self.assertGreater(last.transform.translation.x - odometry[0].transform.translation.x, 1.5, "the chair drove")


if __name__ == "__main__":
    rospy.init_node("replay_bag")
    rostest.rosrun("bullet_sim_bringup", "replay_bag", ReplayBag, sys.argv)
