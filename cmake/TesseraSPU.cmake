# tessera_add_spu(NAME SOURCES src...)
# Builds spus/NAME as the plugin NAME_spu.so into the build tree's spus/
# directory (found by uninstalled builds) and installs it.
function(tessera_add_spu name)
  cmake_parse_arguments(ARG "" "" "SOURCES;LIBS" ${ARGN})
  set(target spu_${name})
  add_library(${target} MODULE ${ARG_SOURCES})
  target_link_libraries(${target} PRIVATE tessera ${ARG_LIBS})
  set_target_properties(${target} PROPERTIES
    PREFIX "" OUTPUT_NAME "${name}_spu"
    LIBRARY_OUTPUT_DIRECTORY ${TESSERA_SPU_BUILD_DIR}
    C_VISIBILITY_PRESET hidden)
  install(TARGETS ${target} LIBRARY DESTINATION ${TESSERA_SPU_INSTALL_DIR})
endfunction()
