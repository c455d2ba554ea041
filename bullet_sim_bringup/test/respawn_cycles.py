#!/usr/bin/env python3
"""Deletes and respawns a ros_control arm 50 times (respawn_cycles.test): its controllers come back each time,
and the simulator's resident memory after the last cycle is within 5 % of what it was after the tenth."""
import unittest
import xmlrpc.client

import rosgraph
import rospy
import rostest
from controller_manager_msgs.srv import ListControllers, LoadController, SwitchController
from gazebo_msgs.srv import DeleteModel, SpawnModel
from geometry_msgs.msg import Pose, Quaternion

CYCLES = 50
SETTLED_CYCLE = 10  # allocators and caches have grown to their working size by then
CONTROLLERS = ["joint_state_controller", "arm_controller"]


def service(name, service_type):
    rospy.wait_for_service(name, timeout=60)
    return rospy.ServiceProxy(name, service_type)


def resident_kb(pid):
    with open("/proc/%d/status" % pid) as status:
        for line in status:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    raise AssertionError("no VmRSS for process %d" % pid)


class RespawnCycles(unittest.TestCase):
    def simulator_pid(self):
        master = rosgraph.Master("/respawn_cycles")
        code, _, pid = xmlrpc.client.ServerProxy(master.lookupNode("/gazebo")).getPid("/respawn_cycles")
        self.assertEqual(code, 1, "the simulator's node does not give its pid")
        return pid

    def cycle(self, description):
        spawn = service("/gazebo/spawn_urdf_model", SpawnModel)
        answer = spawn("arm", description, "/arm", Pose(orientation=Quaternion(0, 0, 0, 1)), "")
        self.assertTrue(answer.success, answer.status_message)
        load = service("/arm/controller_manager/load_controller", LoadController)
        for name in CONTROLLERS:
            self.assertTrue(load(name).ok, "load_controller %s" % name)
        switch = service("/arm/controller_manager/switch_controller", SwitchController)
        self.assertTrue(switch(CONTROLLERS, [], 2, False, 0.0).ok, "switch_controller")
        listed = service("/arm/controller_manager/list_controllers", ListControllers)().controller
        self.assertEqual(sorted((c.name, c.state) for c in listed), sorted((n, "running") for n in CONTROLLERS))
        self.assertTrue(service("/gazebo/delete_model", DeleteModel)("arm").success, "delete_model")

    def test_memory_stays_flat_over_respawns(self):
        rospy.init_node("respawn_cycles")
        description = rospy.get_param("/arm_description")
        pid = self.simulator_pid()
        settled = None
        for cycle in range(1, CYCLES + 1):
            self.cycle(description)
            if cycle == SETTLED_CYCLE:
                settled = resident_kb(pid)
        last = resident_kb(pid)
        print("resident memory: %d kB after cycle %d, %d kB after cycle %d" % (settled, SETTLED_CYCLE, last, CYCLES))
        self.assertLessEqual(last, settled * 1.05,
                             "resident memory grew from %d kB after cycle %d to %d kB after cycle %d"
                             % (settled, SETTLED_CYCLE, last, CYCLES))


if __name__ == "__main__":
    rostest.rosrun("bullet_sim_bringup", "respawn_cycles", RespawnCycles)
