# Fails the configure step when a ROS-free library includes a ROS package's header or links a ROS library. The
# headers checked are the target's sources, every public header, and every private header outside src/ros.
set(BULLET_SIM_ROS_HEADER_REGEX
    "^[ \t]*#[ \t]*include[ \t]*[<\"](ros|roscpp|rosbag|tf|tf2_ros|actionlib|std_srvs|[a-z0-9_]+_msgs|urdf|image_transport|camera_info_manager|topic_tools|pluginlib|controller_manager|xmlrpcpp)/")

function(ros_free_check target)
  get_target_property(sources ${target} SOURCES)
  file(GLOB_RECURSE headers ${PROJECT_SOURCE_DIR}/include/${PROJECT_NAME}/*.h ${PROJECT_SOURCE_DIR}/src/*.h
       ${PROJECT_SOURCE_DIR}/plugins/*.h)
  list(FILTER headers EXCLUDE REGEX "/src/ros/")
  foreach(file ${sources} ${headers})
    get_filename_component(path ${file} ABSOLUTE BASE_DIR ${PROJECT_SOURCE_DIR})
    if(NOT EXISTS ${path})
      continue()  # a generated source
    endif()
    file(STRINGS ${path} ros_includes REGEX "${BULLET_SIM_ROS_HEADER_REGEX}")
    if(ros_includes)
      message(FATAL_ERROR "${target} must stay ROS-free, but ${path} has: ${ros_includes}")
    endif()
  endforeach()
  get_target_property(libraries ${target} LINK_LIBRARIES)
  foreach(library ${libraries})
    if(library MATCHES "roscpp|rosconsole|roslib|rosbag|tf2_ros|actionlib|catkin_LIBRARIES")
      message(FATAL_ERROR "${target} must stay ROS-free, but links ${library}")
    endif()
  endforeach()
endfunction()
