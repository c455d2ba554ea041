# Fails the configure step when a file includes a header of a layer above its own, at any include depth. The
# layers, from the bottom, each a folder under include/bullet_sim/ and src/:
#   common      diagnostics, limits, reading files, a pool of threads
#   assets      meshes, textures, materials, resource lookup (model://, package://), isolated import
#   model       URDF, <gazebo> tags, SDF worlds and models -> typed descriptions
#   sensing     exact batched ray casting
#   physics     descriptions -> Bullet bodies, the static world, the step
#   plugins     the plugin interface, its registry, and the plugins (plugins/<name>/, one folder each)
#   simulation  stepping, the robot and world lifecycle, Gazebo's world API
#   scene       a simulation as a plain Scene (building)
#   render      draws a plain Scene: besides its own headers it may include scene/scene.h, scene/camera.h,
#               scene/image.h and scene/scene_renderer.h (the interface it implements)
#   web         the live viewer: a page served over HTTP and a WebSocket (Boost.Beast)
#   tools       what the command-line tools share
#   doctor      urdf_doctor's checks
#   scenario    scenario files, runs, checks and reports
#   bench       the benchmark
#   ros         the only ROS code
set(BULLET_SIM_LAYERS common assets model sensing physics plugins simulation scene render web tools doctor scenario bench ros)

# The layer of a source or header path: its folder under include/bullet_sim, src or the package (plugins/).
function(layer_of path out)
  file(RELATIVE_PATH relative ${PROJECT_SOURCE_DIR} ${path})
  if(relative MATCHES "^(include/bullet_sim|src)/([a-z_]+)/")
    set(${out} ${CMAKE_MATCH_2} PARENT_SCOPE)
  elseif(relative MATCHES "^plugins/")
    set(${out} plugins PARENT_SCOPE)
  else()
    set(${out} "" PARENT_SCOPE)
  endif()
endfunction()

# The layer a quoted include names ("bullet_sim/model/model.h", "physics/contacts.h", "plugins/x/x.h"), or "".
function(included_layer header out)
  set(${out} "" PARENT_SCOPE)
  string(REGEX REPLACE "^bullet_sim/" "" header "${header}")
  if(header MATCHES "^([a-z_]+)/")
    list(FIND BULLET_SIM_LAYERS ${CMAKE_MATCH_1} rank)
    if(NOT rank EQUAL -1)
      set(${out} ${CMAKE_MATCH_1} PARENT_SCOPE)
    endif()
  endif()
endfunction()

function(layer_check)
  file(GLOB_RECURSE files CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/include/${PROJECT_NAME}/*.h
       ${PROJECT_SOURCE_DIR}/src/*.h ${PROJECT_SOURCE_DIR}/src/*.cpp ${PROJECT_SOURCE_DIR}/plugins/*.h
       ${PROJECT_SOURCE_DIR}/plugins/*.cpp)
  list(FILTER files EXCLUDE REGEX "_test\\.cpp$")  # a plugin's tests step a whole simulation
  foreach(path ${files})
    layer_of(${path} layer)
    if(layer STREQUAL "")
      message(FATAL_ERROR "${path} lies in no layer: put it under a layer's folder (cmake/layer_check.cmake)")
    endif()
    list(FIND BULLET_SIM_LAYERS ${layer} rank)
    file(STRINGS ${path} includes REGEX "^#include \"[^\"]+\"")
    foreach(line ${includes})
      string(REGEX REPLACE "^#include \"([^\"]+)\".*" "\\1" header "${line}")
      included_layer("${header}" used)
      if(used STREQUAL "")
        continue()  # a file beside it, or a generated message header
      endif()
      list(FIND BULLET_SIM_LAYERS ${used} used_rank)
      if(used_rank GREATER rank)
        message(FATAL_ERROR "layer ${layer} must not include a layer above it: ${path} has ${line}")
      endif()
      if(layer STREQUAL "render" AND NOT used STREQUAL "render" AND NOT header MATCHES "^(bullet_sim/)?scene/(scene|camera|image|scene_renderer)\\.h$")
        message(FATAL_ERROR "the renderer knows only the plain Scene: ${path} has ${line}")
      endif()
    endforeach()
  endforeach()
endfunction()
