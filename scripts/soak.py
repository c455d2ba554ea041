#!/usr/bin/env python3
"""scripts/soak.sh's load and checks (needs a running simulator with robot1..3, see scripts/soak.launch).

  soak.py [SIM_SECONDS]                     5 publishers at 1 kHz each on robot1..3/cmd_vel (round robin) for
                                            SIM_SECONDS of sim time (default 60); checks that the simulator
                                            keeps stepping, its RSS stays within 5 % after a warm-up, /clock never
                                            goes back, and every robot keeps publishing odom. Exit 1 on a failure.
  soak.py publish TOPIC LINEAR ANGULAR      one of those publishers (a process of its own, as real clients are)
"""
import os
import subprocess
import sys
import threading
import time
import xmlrpc.client

import rosgraph
import rospy
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Clock

PUBLISHERS = 5
RATE = 1000.0  # [Hz] per publisher
ROBOTS = ["robot1", "robot2", "robot3"]
COMMANDS = {"robot1": (0.5, 0.5), "robot2": (0.3, 0.5), "robot3": (0.2, 1.0)}  # circles of 1, 0.6, 0.2 m
WARM_UP = 10.0  # [s] of sim time before RSS counts: lidars, caches and queues fill first
RSS_TOLERANCE = 0.05
STALL = 2.0  # [s] of wall time without the clock advancing is a stall
WALL_LIMIT_FACTOR = 10  # the run may take ten times its sim time (a loaded 2-core machine) before it fails


def publish(topic, linear, angular):
    rospy.init_node("soak_publisher", anonymous=True, disable_signals=True)
    publisher = rospy.Publisher(topic, Twist, queue_size=10)
    twist = Twist()
    twist.linear.x, twist.angular.z = linear, angular
    period, sent, started = 1.0 / RATE, 0, time.monotonic()
    next_time = started
    try:
        while True:
            publisher.publish(twist)
            sent += 1
            next_time += period
            delay = next_time - time.monotonic()
            if delay > 0:
                time.sleep(delay)  # pacing the publishing rate, not waiting for anything
            else:
                next_time = time.monotonic()  # behind: do not burst to catch up
    except KeyboardInterrupt:
        pass
    print("%s: %.0f Hz" % (topic, sent / (time.monotonic() - started)), flush=True)
    rospy.signal_shutdown("done")


def rss_kib(pid):
    with open("/proc/%d/status" % pid) as status:
        for line in status:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    raise RuntimeError("no VmRSS for process %d" % pid)


class ClockWatch:
    def __init__(self):
        self.lock = threading.Lock()
        self.latest = 0.0
        self.backwards = 0
        self.advanced_at = None  # wall time of the latest step seen
        self.longest_stall = 0.0
        rospy.Subscriber("/clock", Clock, self.tick, queue_size=1000)

    def tick(self, message):
        now, stamp = time.monotonic(), message.clock.to_sec()
        with self.lock:
            if stamp < self.latest:
                self.backwards += 1
            if stamp > self.latest:
                if self.advanced_at is not None:
                    self.longest_stall = max(self.longest_stall, now - self.advanced_at)
                self.advanced_at, self.latest = now, stamp


def main(sim_seconds):
    deadline = time.monotonic() + 60
    while not rosgraph.is_master_online():
        if time.monotonic() > deadline:
            sys.exit("FAILED: no ROS master at %s after 60 s" % rosgraph.get_master_uri())
        time.sleep(0.2)
    rospy.init_node("soak")
    clock = ClockWatch()
    odometry = {robot: 0 for robot in ROBOTS}

    def counter(robot):
        def count(_):
            odometry[robot] += 1
        return count

    for robot in ROBOTS:
        rospy.Subscriber("/%s/odom" % robot, Odometry, counter(robot), queue_size=100)
    deadline = time.monotonic() + 120
    while not all(odometry.values()) or clock.latest == 0:
        if time.monotonic() > deadline:
            sys.exit("FAILED: no odom from %s after 120 s: are the robots spawned?" %
                     [r for r, n in odometry.items() if not n])
        time.sleep(0.1)
    pid = xmlrpc.client.ServerProxy(rosgraph.Master("/soak").lookupNode("/gazebo")).getPid("/soak")[2]

    publishers = [subprocess.Popen([sys.executable, os.path.abspath(__file__), "publish", "/%s/cmd_vel" % robot,
                                    str(COMMANDS[robot][0]), str(COMMANDS[robot][1])])
                  for robot in (ROBOTS[i % len(ROBOTS)] for i in range(PUBLISHERS))]
    start = clock.latest
    wall_start = time.monotonic()
    samples = []  # (sim time, RSS [KiB])
    odometry_at_warm_up = None
    failures = []
    try:
        while clock.latest < start + sim_seconds:
            if time.monotonic() - wall_start > WALL_LIMIT_FACTOR * sim_seconds:
                failures.append("only %.1f s of sim time in %.0f s of wall time" %
                                (clock.latest - start, time.monotonic() - wall_start))
                break
            if any(p.poll() is not None for p in publishers):
                failures.append("a publisher died")
                break
            if clock.latest >= start + WARM_UP:
                samples.append((clock.latest, rss_kib(pid)))
                if odometry_at_warm_up is None:
                    odometry_at_warm_up = dict(odometry)
            time.sleep(0.5)  # the sampling period of RSS
    finally:
        for publisher in publishers:
            publisher.send_signal(2)  # SIGINT: each prints its rate
        for publisher in publishers:
            publisher.wait(timeout=30)
    wall = time.monotonic() - wall_start

    rss = [kib for _, kib in samples]
    if not rss:
        failures.append("no RSS sample after the %.0f s warm-up" % WARM_UP)
    elif max(rss) > (1 + RSS_TOLERANCE) * min(rss):
        failures.append("RSS grew from %d to %d KiB after the warm-up (more than %.0f %%)" %
                        (min(rss), max(rss), 100 * RSS_TOLERANCE))
    if clock.backwards:
        failures.append("/clock went back %d times" % clock.backwards)
    if clock.longest_stall > STALL:
        failures.append("the clock stood still for %.1f s of wall time" % clock.longest_stall)
    for robot in ROBOTS:
        if odometry_at_warm_up and odometry[robot] <= odometry_at_warm_up[robot]:
            failures.append("%s stopped publishing odom" % robot)

    print("soak: %.1f s of sim time in %.1f s of wall time (real-time factor %.2f)" %
          (clock.latest - start, wall, (clock.latest - start) / wall))
    if rss:
        print("soak: simulator RSS after warm-up %d KiB, min %d, max %d, last %d (%d samples)" %
              (rss[0], min(rss), max(rss), rss[-1], len(rss)))
    print("soak: /clock went back %d times; longest wall time without a step %.3f s" %
          (clock.backwards, clock.longest_stall))
    print("soak: odom messages " + ", ".join("%s %d" % (r, odometry[r]) for r in ROBOTS))
    for failure in failures:
        print("FAILED: " + failure)
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    if len(sys.argv) == 5 and sys.argv[1] == "publish":
        publish(sys.argv[2], float(sys.argv[3]), float(sys.argv[4]))
    else:
        main(float(sys.argv[1]) if len(sys.argv) > 1 else 60.0)
