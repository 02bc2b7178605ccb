# tests/spec.cmake — tests of the GL command spec (spec/gl.yaml) and its
# loader (gen/spec.c). Included by tests/CMakeLists.txt.
get_filename_component(TSR_SPEC_YAML ${CMAKE_CURRENT_LIST_DIR}/../spec/gl.yaml ABSOLUTE)
set(TSR_SPEC_DATA ${CMAKE_CURRENT_LIST_DIR}/data)
set(TESSERA_GL_XML /usr/share/khronos-api/gl.xml CACHE FILEPATH
    "Khronos gl.xml registry (package khronos-api), for spec_matches_khronos")

add_library(tsr_test_glxml STATIC ${CMAKE_CURRENT_LIST_DIR}/spec/glxml.c ${CMAKE_CURRENT_LIST_DIR}/spec/spec_test_setup.c)
target_include_directories(tsr_test_glxml PUBLIC ${CMAKE_CURRENT_LIST_DIR}/spec)
target_link_libraries(tsr_test_glxml PUBLIC tsr_spec)

foreach(t spec_matches_khronos spec_enums_are_gl_enums spec_pname_counts_cover_gl21 spec_covers_gl21
          spec_covers_imports spec_opcodes_frozen spec_loader_rejects_bad_specs)
  add_executable(test_${t} ${CMAKE_CURRENT_LIST_DIR}/spec/${t}_test.c)
  target_link_libraries(test_${t} PRIVATE tsr_spec tsr_test_glxml)
endforeach()

add_test(NAME spec_matches_khronos COMMAND test_spec_matches_khronos ${TSR_SPEC_YAML} ${TESSERA_GL_XML})
add_test(NAME spec_enums_are_gl_enums COMMAND test_spec_enums_are_gl_enums ${TSR_SPEC_YAML} ${TESSERA_GL_XML})
add_test(NAME spec_pname_counts_cover_gl21
         COMMAND test_spec_pname_counts_cover_gl21 ${TSR_SPEC_YAML} ${TESSERA_GL_XML})
add_test(NAME spec_covers_gl21 COMMAND test_spec_covers_gl21 ${TSR_SPEC_YAML} ${TESSERA_GL_XML})
add_test(NAME spec_covers_imports COMMAND test_spec_covers_imports ${TSR_SPEC_YAML} ${TSR_SPEC_DATA}/gl_imports.txt)
add_test(NAME spec_opcodes_frozen COMMAND test_spec_opcodes_frozen ${TSR_SPEC_YAML} ${TSR_SPEC_DATA}/opcodes.txt)
add_test(NAME spec_loader_rejects_bad_specs COMMAND test_spec_loader_rejects_bad_specs)
