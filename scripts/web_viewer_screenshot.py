#!/usr/bin/env python3
"""The README's picture of the live viewer: multi_robot.launch in home.world, against a ROS master of its own on a
free port, its page in headless Chromium looking over the three robots, with the Yahboom car's camera in the
panel.

usage: web_viewer_screenshot.py OUT.png   (after building, with devel/setup.bash sourced)"""
import os
import signal
import socket
import subprocess
import sys
import tempfile
import time

from selenium import webdriver
from selenium.webdriver.chrome.service import Service
from selenium.webdriver.common.by import By
from selenium.webdriver.support.ui import Select

FLAGS = ["--headless=new", "--enable-unsafe-swiftshader", "--no-sandbox", "--disable-gpu",
         "--disable-background-networking", "--disable-component-update", "--disable-sync", "--no-first-run",
         "--window-size=1280,800"]
VIEW = "v.camera.position.set(-1.9, -2.6, 2.9); v.controls.target.set(0.3, 0.4, 0.1);"


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def wait_until(condition, timeout, what):
    deadline = time.monotonic() + timeout
    while not condition():
        if time.monotonic() > deadline:
            sys.exit("timed out waiting for " + what)
        time.sleep(0.1)


def shoot(url, out):
    profile = tempfile.mkdtemp(prefix="web_viewer_screenshot_")
    options = webdriver.ChromeOptions()
    options.binary_location = "/usr/bin/chromium"
    for flag in FLAGS + ["--user-data-dir=" + profile]:
        options.add_argument(flag)
    driver = webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=options)
    try:
        driver.get(url)
        state = "return window.bulletSim && window.bulletSim."
        wait_until(lambda: driver.execute_script(state + "frames > 5"), 60, "the page's frames")
        Select(driver.find_element(By.ID, "camera")).select_by_value("yahboomcar/camera")
        wait_until(lambda: driver.execute_script(state + "images > 3"), 60, "the camera's images")
        driver.execute_script("const v = window.bulletSim.view; " + VIEW + " v.controls.update(); v.draw();")
        draws = driver.execute_script(state + "draws")
        wait_until(lambda: driver.execute_script(state + "draws") > draws + 2, 30, "the page to draw")
        driver.save_screenshot(out)
    finally:
        driver.quit()
        subprocess.run(["rm", "-rf", profile], check=False)


def main():
    out = os.path.abspath(sys.argv[1])
    master, web = free_port(), free_port()
    env = dict(os.environ, ROS_MASTER_URI="http://localhost:%d" % master)
    launch = subprocess.Popen(["roslaunch", "-p", str(master), "bullet_sim_bringup", "multi_robot.launch",
                               "web_port:=%d" % web], env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        url = "http://127.0.0.1:%d/" % web

        def serving():
            try:
                return socket.create_connection(("127.0.0.1", web), timeout=1).close() or True
            except OSError:
                return False
        wait_until(serving, 60, url)
        shoot(url, out)
    finally:
        launch.send_signal(signal.SIGINT)
        launch.wait(timeout=30)
    print("wrote " + out)


if __name__ == "__main__":
    main()
