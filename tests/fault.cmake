# tests/fault.cmake — failures found by the fault matrix (issue 10, item
# 13). Included by tests/CMakeLists.txt.
get_property(FAULT_TESTS_BEFORE DIRECTORY PROPERTY TESTS)
set(FAULT_DIR ${CMAKE_CURRENT_SOURCE_DIR}/fault)
set(FAULT_OUT ${CMAKE_BINARY_DIR}/test-out/fault)
file(MAKE_DIRECTORY ${FAULT_OUT})

# Found by the matrix, in every build: the matrix's wall_display graph
# (64x48 tiles) hung before its first window, because a tile server that
# never swaps left its frame barrier in an unflushed wire buffer.
if(TARGET spu_readback)
  add_test(NAME readback_small_tiles_frame_barrier_reaches_display_exact
    COMMAND ${FAULT_DIR}/small_tiles.sh ${CMAKE_BINARY_DIR}/bin ${FAULT_DIR}/wall_display.yaml
            ${FAULT_OUT}/small-tiles 20)
endif()

get_property(FAULT_TESTS_AFTER DIRECTORY PROPERTY TESTS)
if(FAULT_TESTS_BEFORE)
  list(REMOVE_ITEM FAULT_TESTS_AFTER ${FAULT_TESTS_BEFORE})
endif()
# One llvmpipe thread per renderer: two cells at once on two cores.
set(FAULT_ENV "LP_NUM_THREADS=0")
if(TESSERA_SANITIZE)
  list(APPEND FAULT_ENV "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp:print_suppressions=0")
endif()
set_tests_properties(${FAULT_TESTS_AFTER} PROPERTIES TIMEOUT 90 LABELS fault ENVIRONMENT "${FAULT_ENV}")
