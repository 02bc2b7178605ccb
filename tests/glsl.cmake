# tests/glsl.cmake — GLSL programs through sort-first (issue 4 items 1, 2):
# examples/shaders (a vertex+fragment program with per-frame uniforms, a
# fragment-only program relinked at frame 3, fixed-function lines) through
# tilesort on real `tessera node` tile servers, every gathered frame
# compared with shaders-native (0 differing pixels). The programs reach each
# server in its state diff, the first time a buffer it gets draws with
# them; names are the tracker's, mapped by every server's render SPU
# (tessera/glsl_names.h). Late joiners with programs: tests/replicate.cmake.
# The tracker itself: tests/state.cmake (state_glsl_*).
get_property(GLSL_TESTS_BEFORE DIRECTORY PROPERTY TESTS)
set(GLSL_OUT ${CMAKE_BINARY_DIR}/test-out/glsl)
foreach(config 3x3 balance)
  add_test(NAME tilesort_exact_shaders_${config}
    COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/tilesort/tilesort.sh exact ${CMAKE_BINARY_DIR}/bin
            ${GLSL_OUT}/shaders-${config} shaders 6 ${config})
endforeach()
get_property(GLSL_TESTS_AFTER DIRECTORY PROPERTY TESTS)
if(GLSL_TESTS_BEFORE)
  list(REMOVE_ITEM GLSL_TESTS_AFTER ${GLSL_TESTS_BEFORE})
endif()
set(GLSL_ENV "LP_NUM_THREADS=0")
if(TESSERA_SANITIZE)
  list(APPEND GLSL_ENV "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp:print_suppressions=0:use_tls=0")
endif()
set_tests_properties(${GLSL_TESTS_AFTER} PROPERTIES
  TIMEOUT 240 LABELS tilesort FAIL_REGULAR_EXPRESSION "FAIL:" ENVIRONMENT "${GLSL_ENV}")
