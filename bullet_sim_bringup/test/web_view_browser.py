#!/usr/bin/env python3
"""rostest node: the simulator's live viewer (~web_port) in a real browser. Headless Chromium, driven by Selenium,
opens the page: its 3D canvas draws the wheelchair in its colours where it stands; cmd_vel published here moves
it on the page; the teleop pad publishes cmd_vel; Pause stops sim time (the page's and /clock), Resume starts it
again and Reset brings the robot back. With ~screenshot_dir (the launch argument screenshot_dir), the screenshots
are kept there."""
import io
import os
import shutil
import sys
import tempfile
import time
import unittest
import urllib.request

import numpy
import rospy
import rostest
from geometry_msgs.msg import Twist
from PIL import Image
from rosgraph_msgs.msg import Clock
from selenium import webdriver
from selenium.webdriver.chrome.service import Service
from selenium.webdriver.common.action_chains import ActionChains
from selenium.webdriver.common.by import By

from bringup_support import Collector

CHROMIUM_FLAGS = ["--headless=new", "--enable-unsafe-swiftshader", "--no-sandbox", "--disable-gpu",
                  "--disable-background-networking", "--disable-component-update", "--disable-sync",
                  "--no-first-run", "--window-size=960,640"]
ROBOT = "wheelchair"


def wait_until(condition, timeout, what):
    """Polls `condition` until it returns something true; fails after `timeout` wall seconds."""
    deadline = time.monotonic() + timeout
    while True:
        value = condition()
        if value:
            return value
        if time.monotonic() > deadline:
            raise AssertionError("timed out after %.0f s waiting for %s" % (timeout, what))
        time.sleep(0.05)


def dark(pixels):
    """The wheelchair's black tyres, lit or not."""
    return pixels.max(axis=2) < 40


def blue(pixels):
    """Its lidar (Gazebo/Blue)."""
    r, g, b = (pixels[:, :, c].astype(int) for c in range(3))
    return (b > 100) & (b > 2 * numpy.maximum(r, g))


class WebViewBrowser(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.url = "http://127.0.0.1:%d/" % rospy.get_param("~port")
        wait_until(cls.serving, 40, "the viewer at " + cls.url + " (the simulator's log says why not: a busy port?)")
        cls.profile = tempfile.mkdtemp(prefix="web_view_chromium_")
        cls.shots = rospy.get_param("~screenshot_dir", "")
        if cls.shots:
            os.makedirs(cls.shots, exist_ok=True)
        options = webdriver.ChromeOptions()
        options.binary_location = "/usr/bin/chromium"
        for flag in CHROMIUM_FLAGS + ["--user-data-dir=" + cls.profile]:
            options.add_argument(flag)
        cls.driver = webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=options)
        cls.driver.get(cls.url)
        wait_until(lambda: cls.page("return s.frames > 0 && s.robots[%r] !== undefined && s.draws > 0" % ROBOT),
                   30, "the page's first frame of the %s" % ROBOT)
        cls.cmd_vel = rospy.Publisher("/cmd_vel", Twist, queue_size=10)

    @classmethod
    def tearDownClass(cls):
        cls.driver.quit()
        shutil.rmtree(cls.profile, ignore_errors=True)

    @classmethod
    def serving(cls):
        try:
            with urllib.request.urlopen(cls.url, timeout=2) as reply:
                return reply.status == 200
        except OSError:
            return False

    @classmethod
    def page(cls, expression):
        """Evaluates JavaScript with `s` bound to the page's state (window.bulletSim)."""
        return cls.driver.execute_script("const s = window.bulletSim; " + expression)

    def screenshot(self, name):
        """The page as drawn after the frames received so far, as an RGB array, in CSS pixels."""
        draws = self.page("return s.draws")
        wait_until(lambda: self.page("return s.draws") > draws, 10, "the page to draw again")
        png = self.driver.get_screenshot_as_png()
        if self.shots:
            with open(os.path.join(self.shots, name + ".png"), "wb") as f:
                f.write(png)
        image = Image.open(io.BytesIO(png)).convert("RGB")
        scale = self.page("return window.devicePixelRatio")
        if scale != 1:
            image = image.resize((round(image.width / scale), round(image.height / scale)))
        return numpy.asarray(image)

    def robot_box(self):
        left, top, right, bottom = self.page("return s.screenBox(%r)" % ROBOT)
        return int(left), int(top), int(right) + 1, int(bottom) + 1

    def without_panel(self, mask):
        """`mask` with the control panel (whose text is black too) cleared."""
        cleared = mask.copy()
        panel = self.page("const r = document.getElementById('panel').getBoundingClientRect(); "
                          "return [r.left, r.top, r.right, r.bottom]")
        cleared[:int(panel[3]) + 2, :int(panel[2]) + 2] = False
        return cleared

    def outside(self, mask, box):
        """`mask` with the robot's box and the panel cleared."""
        outside = self.without_panel(mask)
        left, top, right, bottom = box
        outside[max(top, 0):max(bottom, 0), max(left, 0):max(right, 0)] = False
        return outside

    def drive(self, linear, until, what):
        twist = Twist()
        twist.linear.x = linear
        try:
            wait_until(lambda: self.cmd_vel.publish(twist) or until(), 30, what)
        finally:
            self.cmd_vel.publish(Twist())

    def robot(self):
        return self.page("return s.robots[%r]" % ROBOT)

    def latch(self, flag, condition):
        """From now on the page checks `condition` every 10 ms; window[flag] turns true once it has held.
        For states too brief to catch through chromedriver's round trips, slow while Chromium draws."""
        self.page("window[%r] = false; const poll = setInterval(() => { const s = window.bulletSim; "
                  "if (%s) { window[%r] = true; clearInterval(poll); } }, 10);" % (flag, condition, flag))

    def test_a_canvas_draws_the_robot_in_its_colours_where_it_stands(self):
        pixels = self.screenshot("robot")
        self.assertGreater(len(numpy.unique(pixels.reshape(-1, 3), axis=0)), 50, "the canvas is blank")
        box = self.robot_box()
        left, top, right, bottom = box
        self.assertTrue(0 <= left < right <= pixels.shape[1] and 0 <= top < bottom <= pixels.shape[0],
                        "the robot is outside the view: %s" % (box,))
        inside = pixels[top:bottom, left:right]
        self.assertGreater(dark(inside).sum(), 200, "no black tyres where the robot stands")
        self.assertGreater(blue(inside).sum(), 10, "no blue lidar where the robot stands")
        self.assertLess(self.outside(dark(pixels), box).sum(), 20, "black where the robot is not")
        self.assertLess(self.outside(blue(pixels), box).sum(), 5, "lidar blue where the robot is not")

    def test_b_cmd_vel_moves_the_robot_on_the_page(self):
        start = self.robot()
        before = self.screenshot("before_driving")
        self.drive(0.5, lambda: self.robot()["x"] > start["x"] + 0.6, "the robot to move 0.6 m on the page")
        end = self.robot()
        self.assertLess(abs(end["y"] - start["y"]), 0.15, "it drove straight")
        after = self.screenshot("after_driving")
        # The tyres moved across the screen as the robot's position projects.
        expected = numpy.subtract(self.page("return s.project(%f, %f, 0.3)" % (end["x"], end["y"])),
                                  self.page("return s.project(%f, %f, 0.3)" % (start["x"], start["y"])))
        # The panel's black text stays put: counted, it pulled the tyres' centroid towards it (CI saw 0.48).
        moved = numpy.subtract(numpy.argwhere(self.without_panel(dark(after))).mean(axis=0)[::-1],
                               numpy.argwhere(self.without_panel(dark(before))).mean(axis=0)[::-1])
        self.assertGreater(numpy.linalg.norm(expected), 20, "a move too small to see")
        along = numpy.dot(moved, expected) / numpy.dot(expected, expected)
        self.assertTrue(0.7 < along < 1.3,
                        "the tyres moved %s px on screen, the robot's position %s px" % (moved, expected))

    def test_c_teleop_pad_publishes_cmd_vel(self):
        commands = Collector("/cmd_vel", Twist)
        start = self.robot()
        button = self.driver.find_element(By.ID, "forward")
        ActionChains(self.driver).click_and_hold(button).perform()
        try:
            commands.wait_for(lambda m: any(abs(c.linear.x - 0.5) < 1e-9 for c in m), 20,
                              "the pad's forward command (0.5 m/s) on /cmd_vel")
            wait_until(lambda: self.robot()["x"] > start["x"] + 0.2, 20, "the pad to drive the robot forward")
        finally:
            ActionChains(self.driver).release(button).perform()
        count = len(commands.messages)
        commands.wait_for(lambda m: any(c.linear.x == 0 and c.angular.z == 0 for c in m[count - 1:]), 10,
                          "a stop when the pad is let go")

    def test_d_pause_stops_sim_time_and_reset_brings_the_robot_back(self):
        self.driver.find_element(By.ID, "pause").click()
        wait_until(lambda: self.page("return s.paused"), 10, "the page to show the simulation paused")
        frames = self.page("return s.frames")
        shown = self.driver.find_element(By.ID, "time").text
        clock = Collector("/clock", Clock)
        # Frames and /clock keep coming while paused: 10 more frames (a third of a second), the same time.
        wait_until(lambda: self.page("return s.frames") >= frames + 10, 10, "frames while paused")
        clocks = clock.wait_for(lambda m: len(m) >= 2, 10, "/clock while paused")
        self.assertEqual(self.driver.find_element(By.ID, "time").text, shown)
        self.assertEqual(self.driver.find_element(By.ID, "state").text, "paused")
        self.assertEqual(clocks[0].clock, clocks[-1].clock)

        self.driver.find_element(By.ID, "resume").click()
        paused_at = self.page("return s.time")
        wait_until(lambda: self.page("return s.time") > paused_at + 0.1, 10, "sim time to run again")
        self.assertGreater(self.robot()["x"], 0.5)
        # At real time the page shows a time under 1 s for only a wall second after the reset.
        self.latch("resetSeen", "s.time < 1.0 && Math.abs(s.robots[%r].x) < 0.05" % ROBOT)
        self.driver.find_element(By.ID, "reset").click()
        wait_until(lambda: self.page("return window.resetSeen"), 10,
                   "reset_simulation: time from the start, the robot back at its spawn pose")


if __name__ == "__main__":
    rospy.init_node("web_view_browser")
    rostest.rosrun("bullet_sim_bringup", "web_view_browser", WebViewBrowser, sys.argv)
