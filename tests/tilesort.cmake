# tests/tilesort.cmake — sort-first (spus/tilesort): real `tessera node`
# tile servers with the render SPU, real example programs, every frame
# gathered from the servers and compared with the native OSMesa reference
# (0 differing pixels), in every tiling the issue names: 2x1, 2x2, 3x3 (odd
# sizes), 4x4, irregular tiles, several tiles per server, load-balanced
# across frames, broadcast. examples/tilescenes draws the hard cases (lit
# and textured triangles, display lists, vertex arrays, wide lines and
# large points just outside tile edges, polygons crossing the eye plane,
# NaN/Inf vertices, window-covering and buffer-spanning primitives,
# glDrawPixels/glBitmap/glRect across tile borders) and the two where sort-
# first degrades towards broadcast (every primitive covers the window; a
# state change between every primitive); batch_bytes=4096 makes
# primitives span buffers. Bounded in time.
get_property(TILESORT_TESTS_BEFORE DIRECTORY PROPERTY TESTS)
set(TILESORT_SH ${CMAKE_CURRENT_SOURCE_DIR}/tilesort/tilesort.sh)
set(TILESORT_OUT ${CMAKE_BINARY_DIR}/test-out/tilesort)
set(TILESORT_BIN ${CMAKE_BINARY_DIR}/bin)

foreach(config 1x1 2x1 2x2 3x3 4x4 irregular multi balance broadcast)
  add_test(NAME tilesort_exact_tilescenes_${config}
    COMMAND ${TILESORT_SH} exact ${TILESORT_BIN} ${TILESORT_OUT}/scenes-${config}
            tilescenes 12 ${config} batch_bytes=4096)
endforeach()
foreach(example spheres isosurface texquads)
  foreach(config 2x2 3x3 balance)
    add_test(NAME tilesort_exact_${example}_${config}
      COMMAND ${TILESORT_SH} exact ${TILESORT_BIN} ${TILESORT_OUT}/${example}-${config} ${example} 3 ${config})
  endforeach()
endforeach()
# The wall graph through the mothership: tiles from the graph, tile PNGs and
# the assembled window exact, sort-first statistics in --stats.
if(TARGET tiles_driver)
  add_test(NAME tilesort_wall_graph_tiles_and_assembled_window_exact
    COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/tilesort/wall_graph.sh ${TILESORT_BIN}
            ${CMAKE_SOURCE_DIR}/examples/graphs/wall.yaml ${TILESORT_OUT}/wall $<TARGET_FILE:tiles_driver>)
endif()
add_test(NAME tilesort_bad_tile_is_a_clear_error
  COMMAND ${TILESORT_SH} bad ${TILESORT_BIN} ${TILESORT_OUT}/bad-tile 0:0:0:512 grid SERVER)
add_test(NAME tilesort_grid_of_non_grid_tiles_is_a_clear_error
  COMMAND ${TILESORT_SH} bad ${TILESORT_BIN} ${TILESORT_OUT}/bad-grid
          0:0:0:300:768,0:300:0:724:400,0:300:400:724:368 grid "columns and rows")

get_property(TILESORT_TESTS_AFTER DIRECTORY PROPERTY TESTS)
if(TILESORT_TESTS_BEFORE)
  list(REMOVE_ITEM TILESORT_TESTS_AFTER ${TILESORT_TESTS_BEFORE})
endif()
# llvmpipe single-threaded: up to 16 servers share two cores. Sanitizer
# builds suppress OSMesa/LLVM's process-lifetime allocations.
set(TILESORT_ENV "LP_NUM_THREADS=0")
if(TESSERA_SANITIZE)
  list(APPEND TILESORT_ENV "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp:print_suppressions=0")
endif()
set_tests_properties(${TILESORT_TESTS_AFTER} PROPERTIES
  TIMEOUT 240 LABELS tilesort FAIL_REGULAR_EXPRESSION "FAIL:" ENVIRONMENT "${TILESORT_ENV}")
