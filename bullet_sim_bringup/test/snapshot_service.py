#!/usr/bin/env python3
"""rostest node: /gazebo/snapshot writes a PNG of the requested size under ~snapshot_dir, and refuses a path
outside it, a bad view and an oversized image with a message, while the node keeps running."""
import os
import shutil
import struct
import sys
import tempfile
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
                             ({"file": "x.png", "width": 5000}, "above 4096 x 4096"),
                             ({"file": "x.png", "height": 4294967295}, "size 0 x 4294967295 is above 4096 x 4096"),
                             ({"file": "x\0.png"}, "holds a NUL byte")):
            reply = self.snapshot(**request)
            self.assertFalse(reply.success, request)
            self.assertIn(why, reply.message)
        self.assertTrue(self.snapshot(file="snapshot_test/after.png", view="top").success)

    def test_refuses_a_way_out_through_a_symbolic_link(self):
        reply = self.snapshot(file="snapshot_test/inside.png", view="top")
        self.assertTrue(reply.success, reply.message)
        folder = os.path.dirname(reply.path)  # the real snapshot_test folder inside ~snapshot_dir
        outside = tempfile.mkdtemp(prefix="snapshot_outside_")
        try:
            for name, target in (("link_out", outside), ("file_out.png", os.path.join(outside, "x.png"))):
                link = os.path.join(folder, name)
                if os.path.lexists(link):
                    os.remove(link)
                os.symlink(target, link)
            for file in ("snapshot_test/link_out/x.png", "snapshot_test/file_out.png"):
                reply = self.snapshot(file=file, view="top")
                self.assertFalse(reply.success, file)
                self.assertIn("through a symbolic link", reply.message)
            self.assertEqual(os.listdir(outside), [])
        finally:
            shutil.rmtree(outside)
            for name in ("link_out", "file_out.png"):
                os.remove(os.path.join(folder, name))


if __name__ == "__main__":
    rospy.init_node("snapshot_service")
    rostest.rosrun("bullet_sim_bringup", "snapshot_service", SnapshotService, sys.argv)
