"""gazebo_ros.gazebo_interface: the helpers that scripts written for Gazebo import, with the originals' names
and arguments, calling the simulator's gazebo_msgs services. Each returns the service's `success` (None when
the call itself fails, as the originals do)."""
import rospy

from gazebo_msgs.msg import *  # noqa: F401,F403 - scripts import the messages through this module
from gazebo_msgs.srv import *  # noqa: F401,F403
from gazebo_msgs.srv import SetModelConfiguration, SpawnModel


def _call(gazebo_namespace, service, service_type, *request):
    name = gazebo_namespace + "/" + service
    rospy.loginfo("Waiting for service %s" % name)
    rospy.wait_for_service(name)
    try:
        rospy.loginfo("Calling service %s" % name)
        response = rospy.ServiceProxy(name, service_type)(*request)
        rospy.loginfo("%s status: %s" % (service, response.status_message))
        return response.success
    except rospy.ServiceException as error:
        rospy.logerr("Service call failed: %s" % error)
        return None


def spawn_sdf_model_client(model_name, model_xml, robot_namespace, initial_pose, reference_frame,
                           gazebo_namespace):
    return _call(gazebo_namespace, "spawn_sdf_model", SpawnModel, model_name, model_xml, robot_namespace,
                 initial_pose, reference_frame)


def spawn_urdf_model_client(model_name, model_xml, robot_namespace, initial_pose, reference_frame,
                            gazebo_namespace):
    return _call(gazebo_namespace, "spawn_urdf_model", SpawnModel, model_name, model_xml, robot_namespace,
                 initial_pose, reference_frame)


def set_model_configuration_client(model_name, model_param_name, joint_names, joint_positions,
                                   gazebo_namespace):
    return _call(gazebo_namespace, "set_model_configuration", SetModelConfiguration, model_name,
                 model_param_name, joint_names, joint_positions)
