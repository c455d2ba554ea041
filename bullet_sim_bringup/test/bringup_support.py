"""Helpers for the bringup's rostest nodes: bounded waits, the robot description's sensor tags."""
import math
import signal
import subprocess
import threading
import time
import xml.etree.ElementTree as ET

import rospy


class Collector:
    """Keeps every message of a topic; wait_for() blocks until a condition holds or a wall deadline passes."""

    def __init__(self, topic, message_type):
        self.messages = []
        self._changed = threading.Condition()
        # No queue limit: a full queue drops messages when the test falls behind (1 kHz topics on a busy machine).
        self._subscriber = rospy.Subscriber(topic, message_type, self._add, queue_size=None)

    def _add(self, message):
        with self._changed:
            self.messages.append(message)
            self._changed.notify_all()

    def wait_for(self, condition, timeout, what):
        deadline = time.monotonic() + timeout
        with self._changed:
            while not condition(self.messages):
                remaining = deadline - time.monotonic()
                if remaining <= 0:
                    raise AssertionError("timed out after %.0f s waiting for %s" % (timeout, what))
                self._changed.wait(remaining)
            return list(self.messages)

    def close(self):
        """Unsubscribes: the publisher sees its subscriber go."""
        self._subscriber.unregister()

    def wait_for_publisher(self, timeout):
        """Blocks until the topic's publisher is connected, polling every 10 ms up to `timeout` s of wall time."""
        deadline = time.monotonic() + timeout
        while self._subscriber.get_num_connections() == 0:
            if time.monotonic() > deadline:
                raise AssertionError("no publisher of %s within %.0f s" % (self._subscriber.name, timeout))
            time.sleep(0.01)


def interrupt(process, timeout):
    """Ends `process` as Ctrl-C would, killing it if it outlives SIGINT by `timeout` [s]; its exit code."""
    if process.poll() is None:
        process.send_signal(signal.SIGINT)
        try:
            process.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            process.kill()
    return process.wait(timeout=timeout)


def yaw(orientation):
    q = orientation
    return math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z))


def ray_sensor(robot_description):
    """The first <sensor type="ray"> of the URDF's <gazebo> blocks, with its plugin."""
    urdf = ET.fromstring(robot_description)
    for gazebo in urdf.findall("gazebo"):
        sensor = gazebo.find("sensor[@type='ray']")
        if sensor is not None:
            return sensor
    raise AssertionError("the robot description declares no ray sensor")
