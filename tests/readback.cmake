# tests/readback.cmake — the readback SPU (spus/readback): a renderer that
# streams its frame's tile images to a display node. The wall with a
# display node runs in tests/tilesort.cmake
# (tilesort_wall_display_node_assembles_exact_window); here: readback
# without tiles against a real `tessera node` display (both its own PNGs
# and the display's bit-identical to the native reference), and its
# mistakes as one clear line with a non-zero exit. Bounded in time.
get_property(READBACK_TESTS_BEFORE DIRECTORY PROPERTY TESTS)
set(READBACK_SH ${CMAKE_CURRENT_SOURCE_DIR}/readback/readback.sh)
set(READBACK_OUT ${CMAKE_BINARY_DIR}/test-out/readback)
set(READBACK_EXPECT ${CMAKE_CURRENT_SOURCE_DIR}/render/expect.sh)

# readback inherits render (loaded as its super): it too resolves no GL symbol.
add_test(NAME readback_spu_has_no_gl_imports
  COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/render/no_gl_imports.sh $<TARGET_FILE:spu_readback>)
# Its own options, then render's (its super's), in that order: the listing
# as one line, matched by grep (a CMake regex over the long listing
# backtracks for minutes).
add_test(NAME readback_spus_lists_its_options
  COMMAND sh -c "TESSERA_SPU_PATH= \"$0\" spus readback | tr '\\n' '|' | grep -E '^readback [(]inherits render[)][|]  renders like render.*[|]  options:[|]    tiles .*[|]    server .*[|]    rank .*[|]  inherited from render:[|]    output .*[|]    window .*[|]    window_output '" $<TARGET_FILE:tessera_cli>)
add_test(NAME readback_whole_window_to_display_exact
  COMMAND ${READBACK_SH} window ${CMAKE_BINARY_DIR}/bin ${READBACK_OUT}/window)
add_test(NAME readback_without_server_is_a_clear_error
  COMMAND ${READBACK_EXPECT} 1 "" "readback#1: option server is required"
          $<TARGET_FILE:spheres> --frames 1 --chain "readback")
# Port 1 on loopback: nothing listens there.
add_test(NAME readback_unreachable_display_exits_nonzero_naming_it
  COMMAND ${READBACK_EXPECT} 1 "" "readback#1: display tcp://127.0.0.1:1: .*connection refused"
          $<TARGET_FILE:spheres> --frames 1 --chain "readback server=tcp://127.0.0.1:1")
add_test(NAME readback_unreachable_display_drop_goes_on
  COMMAND ${READBACK_EXPECT} 0 "" "on_error=drop: tile images are not sent"
          $<TARGET_FILE:spheres> --frames 1 --chain "readback server=tcp://127.0.0.1:1 on_error=drop")

get_property(READBACK_TESTS_AFTER DIRECTORY PROPERTY TESTS)
if(READBACK_TESTS_BEFORE)
  list(REMOVE_ITEM READBACK_TESTS_AFTER ${READBACK_TESTS_BEFORE})
endif()
set(READBACK_ENV "LP_NUM_THREADS=0")
if(TESSERA_SANITIZE)
  list(APPEND READBACK_ENV "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp:print_suppressions=0:use_tls=0")
endif()
set_tests_properties(${READBACK_TESTS_AFTER} PROPERTIES
  TIMEOUT 120 LABELS readback FAIL_REGULAR_EXPRESSION "FAIL:" ENVIRONMENT "${READBACK_ENV}")
