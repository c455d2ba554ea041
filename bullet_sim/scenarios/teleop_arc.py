#!/usr/bin/env python3
"""A small teleop node, as a user writes one: it publishes cmd_vel from sim time, v and w between ~start and
~stop [s], zero outside, at ~rate [Hz of sim time]. The launch scenario examples drive the robot with it."""
import rospy
from geometry_msgs.msg import Twist


def main():
    rospy.init_node("teleop_arc")
    v = rospy.get_param("~v", 0.5)
    w = rospy.get_param("~w", 0.0)
    start = rospy.get_param("~start", 1.0)
    stop = rospy.get_param("~stop", 5.0)
    publisher = rospy.Publisher("cmd_vel", Twist, queue_size=1)
    rate = rospy.Rate(rospy.get_param("~rate", 10.0))
    while not rospy.is_shutdown():
        now = rospy.get_time()
        command = Twist()
        if start <= now < stop:
            command.linear.x = v
            command.angular.z = w
        publisher.publish(command)
        try:
            rate.sleep()
        except rospy.ROSInterruptException:
            break


if __name__ == "__main__":
    main()
