# The plugin folders: every folder under plugins/ is one plugin (or a family, as ros_control and its
# controllers), holding its headers, its sources, its tests (*_test.cpp) and its prose (README.md). Adding a
# folder adds the plugin: nothing else names it.

# The folders' names, their sources (tests left out) and their tests.
function(plugin_folders folders_out sources_out tests_out)
  file(GLOB entries LIST_DIRECTORIES true CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/plugins/*)
  set(folders)
  set(sources)
  set(tests)
  foreach(entry ${entries})
    if(NOT IS_DIRECTORY ${entry})
      continue()
    endif()
    get_filename_component(folder ${entry} NAME)
    if(NOT folder MATCHES "^[a-z][a-z0-9_]*$")
      message(FATAL_ERROR "plugin folder [${folder}]: name plugin folders in lower case with underscores, as "
                          "they name the C++ function that registers them")
    endif()
    list(APPEND folders ${folder})
    file(GLOB folder_sources CONFIGURE_DEPENDS ${entry}/*.cpp)
    foreach(source ${folder_sources})
      if(source MATCHES "_test\\.cpp$")
        list(APPEND tests ${source})
      else()
        list(APPEND sources ${source})
      endif()
    endforeach()
  endforeach()
  list(SORT folders)
  set(${folders_out} ${folders} PARENT_SCOPE)
  set(${sources_out} ${sources} PARENT_SCOPE)
  set(${tests_out} ${tests} PARENT_SCOPE)
endfunction()

# Writes the source that calls each folder's registration function (BULLET_SIM_PLUGIN_FOLDER) in turn. It is
# rewritten only when the folders change.
function(write_builtin_plugins path folders)
  set(declarations "")
  set(calls "")
  foreach(folder ${folders})
    string(APPEND declarations "void registerPluginFolder_${folder}(PluginRegistrar& registrar);\n")
    string(APPEND calls "  {\n    PluginRegistrar registrar(registry, \"${folder}\");\n"
                        "    registerPluginFolder_${folder}(registrar);\n  }\n")
  endforeach()
  file(CONFIGURE OUTPUT ${path} @ONLY CONTENT
"// Written by cmake/plugin_folders.cmake from the folders under plugins/: do not edit.
#include \"bullet_sim/plugins/registry.h\"

namespace bullet_sim {

${declarations}
void registerBuiltinPlugins(PluginRegistry& registry) {
${calls}}

}  // namespace bullet_sim
")
endfunction()
