# tests/replicate.cmake — the replicate SPU (spus/replicate) sending one
# stream to three real `tessera node` servers (two TCP, one Unix socket):
# accuracy of every server's frames, replies, refused / absent / killed
# servers; and the statistics file of the stream clients (pack,
# replicate). Real processes and sockets; every test bounded in time.
# Included by tests/CMakeLists.txt (after node.cmake: uses node_driver).
get_property(REPLICATE_TESTS_BEFORE DIRECTORY PROPERTY TESTS)
set(REPLICATE_SH ${CMAKE_CURRENT_SOURCE_DIR}/replicate/replicate.sh)
set(REPLICATE_OUT ${CMAKE_BINARY_DIR}/test-out/replicate)
set(REPLICATE_BIN ${CMAKE_BINARY_DIR}/bin)

foreach(example spheres texquads isosurface)
  add_test(NAME replicate_three_servers_tcp_unix_exact_${example}
    COMMAND ${REPLICATE_SH} accuracy ${REPLICATE_BIN} ${REPLICATE_OUT}/accuracy-${example} ${example})
endforeach()
add_test(NAME replicate_server_bad_token_refused_names_it
  COMMAND ${REPLICATE_SH} refused ${REPLICATE_BIN} ${REPLICATE_OUT}/refused)
add_test(NAME replicate_server_absent_names_it
  COMMAND ${REPLICATE_SH} absent ${REPLICATE_BIN} ${REPLICATE_OUT}/absent)
add_test(NAME replicate_server_killed_app_exits_nonzero_naming_it
  COMMAND ${REPLICATE_SH} killed ${REPLICATE_BIN} ${REPLICATE_OUT}/killed)
add_test(NAME replicate_drop_goes_on_without_stopped_server
  COMMAND ${REPLICATE_SH} stopped-drop ${REPLICATE_BIN} ${REPLICATE_OUT}/stopped-drop)
if(TARGET node_driver)
  add_test(NAME replicate_replies_roundtrip_from_first_server
    COMMAND ${REPLICATE_SH} replies ${REPLICATE_BIN} ${REPLICATE_OUT}/replies $<TARGET_FILE:node_driver>)
endif()
# Option mistakes: one line naming the SPU instance and the problem.
set(REPLICATE_EXPECT ${CMAKE_CURRENT_SOURCE_DIR}/render/expect.sh)
add_test(NAME replicate_without_servers_is_a_clear_error
  COMMAND ${REPLICATE_EXPECT} 1 "" "replicate#1: option servers is required"
          ${REPLICATE_BIN}/spheres --frames 1 --chain replicate)
add_test(NAME replicate_same_server_twice_is_a_clear_error
  COMMAND ${REPLICATE_EXPECT} 1 "" "server tcp://127.0.0.1:1 is listed twice"
          ${REPLICATE_BIN}/spheres --frames 1 --chain "replicate servers=tcp://127.0.0.1:1,tcp://127.0.0.1:1")

add_test(NAME pack_stats_file_counts_frames_bytes_and_blocked_time
  COMMAND ${REPLICATE_SH} pack-blocked ${REPLICATE_BIN} ${REPLICATE_OUT}/pack-blocked)

# Late joiners (replicate late=..., client/join.h): server B joins the
# running stream and draws bit-identical frames from its first one on;
# spheres has (nested) display lists, texquads two textures bound in turn,
# shaders GLSL programs (one relinked from a new source before B joins,
# their shaders deleted, uniforms changing every frame).
set(REPLICATE_LATE_SH ${CMAKE_CURRENT_SOURCE_DIR}/replicate/late.sh)
foreach(example spheres texquads isosurface shaders)
  add_test(NAME replicate_late_server_joins_mid_stream_exact_${example}
    COMMAND ${REPLICATE_LATE_SH} join ${REPLICATE_BIN} ${REPLICATE_OUT}/late-${example} ${example})
endforeach()
# The display-list recorder the joiners use (tessera/dev/dlist.h), with the real
# packer, unpacker and state tracker.
add_executable(dlist_test ${CMAKE_CURRENT_SOURCE_DIR}/replicate/dlist_test.c)
add_dependencies(dlist_test tessera_generated)
target_include_directories(dlist_test PRIVATE ${CMAKE_SOURCE_DIR}/core ${TESSERA_GEN_DIR}/src)
target_link_libraries(dlist_test PRIVATE tessera m)
foreach(case define_all_is_byte_exact call_equals_direct immediate_and_delete)
  add_test(NAME replicate_late_dlist_${case} COMMAND dlist_test ${case})
endforeach()
add_test(NAME replicate_late_server_never_comes_run_finishes_one_line
  COMMAND ${REPLICATE_LATE_SH} never ${REPLICATE_BIN} ${REPLICATE_OUT}/late-never)
add_test(NAME replicate_late_server_also_listed_in_servers_is_a_clear_error
  COMMAND ${REPLICATE_EXPECT} 1 "" "server unix:/nonexistent/s.sock is listed twice"
          ${REPLICATE_BIN}/spheres --frames 1
          --chain "replicate servers=unix:/nonexistent/s.sock late=unix:/nonexistent/s.sock")

get_property(REPLICATE_TESTS_AFTER DIRECTORY PROPERTY TESTS)
if(REPLICATE_TESTS_BEFORE)
  list(REMOVE_ITEM REPLICATE_TESTS_AFTER ${REPLICATE_TESTS_BEFORE})
endif()
set(REPLICATE_ENV "")
# Sanitizer builds: OSMesa/LLVM keep process-lifetime allocations that
# LeakSanitizer reports; suppress those (tests/lsan.supp), check ours.
if(TESSERA_SANITIZE)
  set(REPLICATE_ENV "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp:print_suppressions=0:use_tls=0")
endif()
set_tests_properties(${REPLICATE_TESTS_AFTER} PROPERTIES TIMEOUT 120 LABELS replicate
  ENVIRONMENT "${REPLICATE_ENV}")
# isosurface computes its surfaces in the app: under the sanitizers the run
# plus 27 frame comparisons needs more than the replicate tests' 120 s.
set_tests_properties(replicate_late_server_joins_mid_stream_exact_isosurface PROPERTIES TIMEOUT 300)
# shaders: llvmpipe compiles its programs twice per server; same reason.
set_tests_properties(replicate_late_server_joins_mid_stream_exact_shaders PROPERTIES TIMEOUT 300)
