# suffuse_add_plugin(NAME SOURCES src...): a plugin library, built as a module
# that the core loads at run time, placed where the core looks for plugins.
function(suffuse_add_plugin name)
  cmake_parse_arguments(ARG "" "OUTPUT_DIRECTORY" "SOURCES" ${ARGN})
  add_library(${name} MODULE ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE suffuse::core)
  set_target_properties(${name} PROPERTIES PREFIX "lib" CXX_VISIBILITY_PRESET hidden)
  if(ARG_OUTPUT_DIRECTORY)
    set_target_properties(${name} PROPERTIES LIBRARY_OUTPUT_DIRECTORY ${ARG_OUTPUT_DIRECTORY})
  elseif(DEFINED SUFFUSE_PLUGIN_OUTPUT_DIR)
    # A bundled plugin: built next to the core and installed with it.
    set_target_properties(${name} PROPERTIES LIBRARY_OUTPUT_DIRECTORY ${SUFFUSE_PLUGIN_OUTPUT_DIR})
    install(TARGETS ${name} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}/${SUFFUSE_PLUGIN_SUBDIR})
  endif()
endfunction()
