# Fails the configure step when a file includes a header of a layer above its own. The layers, from the
# bottom: description, sensing, physics, plugins, simulation, scene (building), render, tools, ros. The
# renderer knows only the plain Scene: besides its own headers it may include scene/scene.h,
# scene/camera.h, scene/image.h and scene/scene_renderer.h (the interface it implements).
set(BULLET_SIM_LAYERS description sensing physics plugins simulation scene render tools ros)

# The layer of a source or header path: its folder under include/bullet_sim or src, or "simulation".
function(layer_of path out)
  if(path MATCHES "/(include/bullet_sim|src)/([a-z_]+)/")
    set(${out} ${CMAKE_MATCH_2} PARENT_SCOPE)
  else()
    set(${out} simulation PARENT_SCOPE)
  endif()
endfunction()

function(layer_check)
  file(GLOB_RECURSE files ${PROJECT_SOURCE_DIR}/include/${PROJECT_NAME}/*.h ${PROJECT_SOURCE_DIR}/src/*.h
       ${PROJECT_SOURCE_DIR}/src/*.cpp)
  foreach(path ${files})
    layer_of(${path} layer)
    list(FIND BULLET_SIM_LAYERS ${layer} rank)
    file(STRINGS ${path} includes REGEX "^#include \"(bullet_sim/)?[a-z_]+(/[a-z_]+)?\\.h\"")
    foreach(line ${includes})
      string(REGEX REPLACE "^#include \"(bullet_sim/)?([^\"]+)\"" "\\2" header "${line}")
      if(header MATCHES "^([a-z_]+)/")
        set(used ${CMAKE_MATCH_1})
      elseif(header STREQUAL "simulation.h")
        set(used simulation)
      else()
        continue()  # a file beside it, or a generated message header
      endif()
      list(FIND BULLET_SIM_LAYERS ${used} used_rank)
      if(used_rank EQUAL -1)
        continue()
      endif()
      if(used_rank GREATER rank)
        message(FATAL_ERROR "layer ${layer} must not include a layer above it: ${path} has ${line}")
      endif()
      if(layer STREQUAL "render" AND NOT used STREQUAL "render" AND NOT header MATCHES "^scene/(scene|camera|image|scene_renderer)\\.h$")
        message(FATAL_ERROR "the renderer knows only the plain Scene: ${path} has ${line}")
      endif()
    endforeach()
  endforeach()
endfunction()
