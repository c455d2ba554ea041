#!/usr/bin/env python3
"""rostest node: the Yahboom car's camera publishes gazebo_ros_camera's topics (640 x 480 rgb8 at 30 Hz of sim
time, camera_info with the image's stamp and frame, set_camera_info), and turning the pan joint through its
command turns the view, which comes back when the pan does."""
import sys
import unittest

import numpy
import rospy
import rostest
from sensor_msgs.msg import CameraInfo, Image
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

from bringup_support import Collector

PAN_ANGLE = 0.8  # [rad]


def pixels(image):
    return numpy.frombuffer(image.data, dtype=numpy.uint8).reshape(image.height, image.width, 3).astype(int)


class CameraView(unittest.TestCase):
    def setUp(self):
        self.images = Collector("camera/image_raw", Image)
        self.infos = Collector("camera/camera_info", CameraInfo)
        self.pan = rospy.Publisher("pan_tilt/command", JointTrajectory, queue_size=1, latch=True)

    def image_after(self, stamp):
        """The first image stamped at least 1 s of sim time after `stamp`."""
        found = self.images.wait_for(lambda m: m and m[-1].header.stamp.to_sec() >= stamp + 1.0, 60,
                                     "an image 1 s after %.2f" % stamp)
        return found[-1]

    def command_pan(self, angle):
        self.pan.publish(JointTrajectory(joint_names=["jq1_Joint", "jq2_Joint"],
                                         points=[JointTrajectoryPoint(positions=[angle, 0.0])]))

    def test_topics_types_sizes_and_frames(self):
        images = self.images.wait_for(lambda m: len(m) >= 31, 60, "31 images")
        image = images[-1]
        self.assertEqual((image.width, image.height, image.encoding), (640, 480, "rgb8"))
        self.assertEqual(image.step, 640 * 3)
        self.assertEqual(image.header.frame_id, "jq2_Link")
        span = images[-1].header.stamp.to_sec() - images[0].header.stamp.to_sec()
        self.assertAlmostEqual((len(images) - 1) / span, 30, delta=1.5)
        infos = self.infos.wait_for(lambda m: m, 60, "a camera_info")
        info = infos[-1]
        self.assertEqual((info.width, info.height, info.header.frame_id), (640, 480, "jq2_Link"))
        self.assertIn(info.header.stamp, [i.header.stamp for i in self.images.messages])
        focal = 640 / (2 * numpy.tan(1.047 / 2))
        self.assertAlmostEqual(info.K[0], focal, places=6)
        rospy.wait_for_service("camera/set_camera_info", timeout=30)

    def test_the_pan_turns_the_view(self):
        self.command_pan(0.0)
        start = self.image_after(0.0)
        ahead = pixels(self.image_after(start.header.stamp.to_sec()))
        self.command_pan(PAN_ANGLE)
        turned = self.image_after(self.images.messages[-1].header.stamp.to_sec())
        self.command_pan(0.0)
        back = self.image_after(turned.header.stamp.to_sec())
        changed = numpy.mean(numpy.abs(pixels(turned) - ahead).sum(axis=2) > 30)
        returned = numpy.mean(numpy.abs(pixels(back) - ahead).sum(axis=2) > 30)
        self.assertGreater(changed, 0.2, "turning the pan by %.1f rad changed too little of the image" % PAN_ANGLE)
        self.assertLess(returned, 0.02, "the view did not come back with the pan")


if __name__ == "__main__":
    rospy.init_node("camera_view")
    rostest.rosrun("bullet_sim_bringup", "camera_view", CameraView, sys.argv)
