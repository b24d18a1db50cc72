# suffuse_add_plugin(<name> SOURCES <src>... [OUTPUT_DIRECTORY <dir>])
#
# Builds a suffuse plugin: a MODULE library lib<name>.so that the core loads
# at run time (Boost.DLL), linked to suffuse::core, C++20, position
# independent, with hidden symbols except the entry point that
# SUFFUSE_PLUGIN_LIBRARY exports. Outside the suffuse sources it is compiled
# with the NDEBUG setting of the installed core (the loader refuses a debug
# plugin in a release core and the reverse), whatever CMAKE_BUILD_TYPE says,
# and, for a release core, at -O3 where no CMAKE_BUILD_TYPE is given.
#
# In the suffuse source tree the bundled plugins go next to the core and are
# installed with it. In a third-party project (find_package(Suffuse)) the
# library stays in the build tree, or in OUTPUT_DIRECTORY; point a scene's
# "plugin_paths" or SUFFUSE_PLUGIN_PATH at that directory.
function(suffuse_add_plugin name)
  cmake_parse_arguments(ARG "" "OUTPUT_DIRECTORY" "SOURCES" ${ARGN})
  if(NOT ARG_SOURCES)
    message(FATAL_ERROR "suffuse_add_plugin(${name}): no SOURCES")
  endif()
  add_library(${name} MODULE ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE suffuse::core)
  target_compile_features(${name} PRIVATE cxx_std_20)
  set_target_properties(${name} PROPERTIES PREFIX "lib" POSITION_INDEPENDENT_CODE ON
                        CXX_VISIBILITY_PRESET hidden VISIBILITY_INLINES_HIDDEN ON)
  if(NOT SUFFUSE_IN_SOURCE_TREE)
    # A third-party plugin: match the installed core, whatever CMAKE_BUILD_TYPE says.
    if(SUFFUSE_CORE_BUILD_TYPE STREQUAL "release")
      target_compile_definitions(${name} PRIVATE NDEBUG)
      # Optimised as the core is when no build type is given (CMake's
      # default then is no optimisation: the coupled-phase template's column
      # ran nine times slower, 46 s instead of 5).
      if(NOT CMAKE_BUILD_TYPE AND NOT CMAKE_CONFIGURATION_TYPES)
        target_compile_options(${name} PRIVATE -O3)
      endif()
    elseif(SUFFUSE_CORE_BUILD_TYPE STREQUAL "debug")
      target_compile_options(${name} PRIVATE -UNDEBUG)
    endif()
  endif()
  if(SUFFUSE_IN_SOURCE_TREE AND SUFFUSE_SANITIZE)
    target_compile_options(${name} PRIVATE -O1)  # as the core (framework/CMakeLists.txt)
  endif()
  if(ARG_OUTPUT_DIRECTORY)
    set_target_properties(${name} PROPERTIES LIBRARY_OUTPUT_DIRECTORY ${ARG_OUTPUT_DIRECTORY})
  elseif(DEFINED SUFFUSE_PLUGIN_OUTPUT_DIR)
    # A bundled plugin: built next to the core and installed with it.
    set_target_properties(${name} PROPERTIES LIBRARY_OUTPUT_DIRECTORY ${SUFFUSE_PLUGIN_OUTPUT_DIR})
    install(TARGETS ${name} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}/${SUFFUSE_PLUGIN_SUBDIR})
    set_property(GLOBAL APPEND PROPERTY SUFFUSE_BUNDLED_PLUGINS ${name})
  endif()
endfunction()
