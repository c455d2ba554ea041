#!/usr/bin/env python3
"""An RL-style episode as users write them against Gazebo, with gazebo_msgs and std_srvs only (nothing of
bullet_sim): speed the simulation up (max_update_rate 0, as openai_ros does), teleport the robot with
set_model_state by service and by topic, read it back from get_model_state and model_states, and reset.

usage: gazebo_msgs_episode.py [MODEL]; exits 0 when every step did what Gazebo does, else 1 with the reason."""
import math
import sys
import threading

import rospy
from gazebo_msgs.msg import ModelState, ModelStates, ODEPhysics
from gazebo_msgs.srv import GetModelState, GetPhysicsProperties, SetModelState, SetPhysicsProperties
from geometry_msgs.msg import Point, Pose, Quaternion, Twist, Vector3
from std_srvs.srv import Empty


class Episode:
    def __init__(self, model):
        self.model = model
        for name in ["set_model_state", "get_model_state", "set_physics_properties", "reset_simulation"]:
            rospy.wait_for_service("/gazebo/" + name, timeout=60)
        self.set_state = rospy.ServiceProxy("/gazebo/set_model_state", SetModelState)
        self.get_state = rospy.ServiceProxy("/gazebo/get_model_state", GetModelState)
        self.get_physics = rospy.ServiceProxy("/gazebo/get_physics_properties", GetPhysicsProperties)
        self.set_physics = rospy.ServiceProxy("/gazebo/set_physics_properties", SetPhysicsProperties)
        self.pause = rospy.ServiceProxy("/gazebo/pause_physics", Empty)
        self.unpause = rospy.ServiceProxy("/gazebo/unpause_physics", Empty)
        self.reset = rospy.ServiceProxy("/gazebo/reset_simulation", Empty)
        self.teleport_topic = rospy.Publisher("/gazebo/set_model_state", ModelState, queue_size=1, latch=True)
        self.states = None
        self.states_changed = threading.Condition()
        rospy.Subscriber("/gazebo/model_states", ModelStates, self.on_states, queue_size=1)

    def on_states(self, states):
        with self.states_changed:
            self.states = states
            self.states_changed.notify_all()

    def wait_in_model_states(self, x, y, timeout=30):
        """Waits until model_states shows the model at (x, y); returns its pose."""
        def there():
            if self.states is None or self.model not in self.states.name:
                return None
            pose = self.states.pose[self.states.name.index(self.model)]
            return pose if math.hypot(pose.position.x - x, pose.position.y - y) < 0.02 else None
        with self.states_changed:
            if not self.states_changed.wait_for(there, timeout):
                raise RuntimeError("model_states never showed %s at (%.2f, %.2f)" % (self.model, x, y))
            return there()

    def go_fast(self):
        """openai_ros's init_values: pause, set the physics with max_update_rate 0, unpause."""
        physics = self.get_physics()
        self.pause()
        ode = ODEPhysics(False, 0, 50, 1.3, 0.0, 0.001, 0.0, 0.0, 0.2, 20)
        answer = self.set_physics(physics.time_step, 0.0, Vector3(0.0, 0.0, -9.81), ode)
        if not answer.success:
            raise RuntimeError("set_physics_properties: " + answer.status_message)
        self.unpause()
        if self.get_physics().max_update_rate != 0.0:
            raise RuntimeError("max_update_rate is not 0 after setting it")

    def teleport_by_service(self, x, y, heading):
        state = ModelState(self.model, Pose(Point(x, y, 0.0), Quaternion(0, 0, math.sin(heading / 2),
                                                                         math.cos(heading / 2))),
                           Twist(), "world")
        answer = self.set_state(state)
        if not answer.success:
            raise RuntimeError("set_model_state: " + answer.status_message)
        got = self.get_state(self.model, "world")
        if not got.success or math.hypot(got.pose.position.x - x, got.pose.position.y - y) > 0.02:
            raise RuntimeError("get_model_state does not show the teleport: %s" % got)
        self.wait_in_model_states(x, y)

    def teleport_by_topic(self, x, y):
        state = ModelState(self.model, Pose(Point(x, y, 0.0), Quaternion(0, 0, 0, 1)), Twist(), "")
        self.teleport_topic.publish(state)
        self.wait_in_model_states(x, y)
        got = self.get_state(self.model, "")
        if math.hypot(got.pose.position.x - x, got.pose.position.y - y) > 0.02:
            raise RuntimeError("get_model_state does not show the topic's teleport: %s" % got.pose)

    def run(self):
        start = self.get_state(self.model, "world").pose.position
        self.go_fast()
        self.teleport_by_service(1.5, -0.5, math.pi / 2)
        self.teleport_by_topic(-1.0, 0.8)
        self.reset()
        self.wait_in_model_states(start.x, start.y)


def main():
    rospy.init_node("gazebo_msgs_episode")
    model = sys.argv[1] if len(sys.argv) > 1 else "wheelchair"
    try:
        Episode(model).run()
    except (RuntimeError, rospy.ROSException) as error:
        print("episode failed: %s" % error, file=sys.stderr)
        return 1
    print("episode done")
    return 0


if __name__ == "__main__":
    sys.exit(main())
