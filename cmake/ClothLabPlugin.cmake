# clothlab_add_plugin(<name> SOURCES <src>...)
#
# Builds a ClothLab plugin: a MODULE library named <name>.so that links the SDK and
# exports exactly one symbol, clothlab_plugin_entry (hidden visibility + version script).
# Used in-tree and installed for out-of-tree plugin projects (find_package(ClothLab)).
set(_CLOTHLAB_PLUGIN_CMAKE_DIR "${CMAKE_CURRENT_LIST_DIR}")

function(clothlab_add_plugin name)
  cmake_parse_arguments(PLUGIN "" "OUTPUT_DIRECTORY" "SOURCES" ${ARGN})
  if(NOT PLUGIN_SOURCES)
    message(FATAL_ERROR "clothlab_add_plugin(${name}): SOURCES is required")
  endif()
  add_library(${name} MODULE ${PLUGIN_SOURCES})
  if(TARGET ClothLab::sdk)
    target_link_libraries(${name} PRIVATE ClothLab::sdk)
  else()
    target_link_libraries(${name} PRIVATE clothlab_sdk)
  endif()
  set(version_script "${_CLOTHLAB_PLUGIN_CMAKE_DIR}/clothlab_plugin.map")
  set_target_properties(${name} PROPERTIES
    PREFIX ""
    C_VISIBILITY_PRESET hidden
    CXX_VISIBILITY_PRESET hidden
    VISIBILITY_INLINES_HIDDEN ON
    LINK_DEPENDS "${version_script}")
  target_link_options(${name} PRIVATE "LINKER:--version-script=${version_script}"
                      "LINKER:--no-undefined")
  if(PLUGIN_OUTPUT_DIRECTORY)
    set_target_properties(${name} PROPERTIES LIBRARY_OUTPUT_DIRECTORY "${PLUGIN_OUTPUT_DIRECTORY}")
  elseif(DEFINED CLOTHLAB_PLUGIN_OUTPUT_DIR)
    set_target_properties(${name} PROPERTIES LIBRARY_OUTPUT_DIRECTORY "${CLOTHLAB_PLUGIN_OUTPUT_DIR}")
    # The built-in plugins, which the Python package ships (python/CMakeLists.txt).
    set_property(GLOBAL APPEND PROPERTY CLOTHLAB_BUILTIN_PLUGINS ${name})
  endif()
endfunction()
