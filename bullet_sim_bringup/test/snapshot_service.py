#!/usr/bin/env python3
"""rostest node: /gazebo/snapshot writes a PNG of the requested size under ~snapshot_dir, and refuses a path
outside it, a bad view and an oversized image with a message, while the node keeps running."""
import os
import struct
import sys
import unittest

import rospy
import rostest
from bullet_sim.srv import Snapshot


def png_size(path):
    with open(path, "rb") as f:
        header = f.read(24)
    assert header[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
    return struct.unpack(">II", header[16:24])


class SnapshotService(unittest.TestCase):
    def setUp(self):
        rospy.wait_for_service("/gazebo/snapshot", timeout=60)
        self.snapshot = rospy.ServiceProxy("/gazebo/snapshot", Snapshot)

    def test_writes_pngs_under_the_snapshot_dir(self):
        for view, width, height in (("chase", 0, 0), ("top", 320, 200), ("front", 160, 120)):
            reply = self.snapshot(file="snapshot_test/%s.png" % view, view=view, width=width, height=height)
            self.assertTrue(reply.success, reply.message)
            self.assertTrue(os.path.isabs(reply.path))
            self.assertEqual(png_size(reply.path), (width or 640, height or 480))

    def test_refuses_bad_requests_and_keeps_running(self):
        for request, why in (({"file": "../outside.png"}, "inside ~snapshot_dir"),
                             ({"file": "/tmp/outside.png"}, "inside ~snapshot_dir"),
                             ({"file": "x.png", "view": "sideways"}, "use chase, top, front, camera:NAME or depth:NAME"),
                             ({"file": "x.png", "width": 5000}, "above 4096 x 4096")):
            reply = self.snapshot(**request)
            self.assertFalse(reply.success, request)
            self.assertIn(why, reply.message)
        self.assertTrue(self.snapshot(file="snapshot_test/after.png", view="top").success)


if __name__ == "__main__":
    rospy.init_node("snapshot_service")
    rostest.rosrun("bullet_sim_bringup", "snapshot_service", SnapshotService, sys.argv)
