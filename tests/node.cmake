# tests/node.cmake — the pack SPU and `tessera node` with real processes
# over real loopback sockets: accuracy of every example through
# app -> pack -> TCP/Unix -> node render, replies, and failures (bad token,
# no server, garbage client, node killed). Every test is bounded in time.
# Included by tests/CMakeLists.txt.
get_property(NODE_TESTS_BEFORE DIRECTORY PROPERTY TESTS)
set(NODE_TEST_DIR ${CMAKE_CURRENT_SOURCE_DIR}/node)
set(NODE_OUT ${CMAKE_BINARY_DIR}/test-out/node)
set(NODE_BIN ${CMAKE_BINARY_DIR}/bin)
file(MAKE_DIRECTORY ${NODE_OUT})

add_executable(node_driver ${NODE_TEST_DIR}/node_driver.c)
target_include_directories(node_driver PRIVATE ${CMAKE_SOURCE_DIR}/server ${CMAKE_SOURCE_DIR}/core)
target_link_libraries(node_driver PRIVATE tessera_gl tessera tessera_net)

add_executable(budget_driver ${NODE_TEST_DIR}/budget_driver.c)
target_include_directories(budget_driver PRIVATE ${CMAKE_SOURCE_DIR}/netlib)
target_link_libraries(budget_driver PRIVATE tessera tessera_net)

set(NODE_FRAMES 3)
foreach(example ${TESSERA_EXAMPLES})
  add_test(NAME node_pack_tcp_accuracy_${example}
    COMMAND ${NODE_TEST_DIR}/accuracy.sh ${NODE_BIN} ${example} ${NODE_OUT}/tcp-${example}
            ${NODE_FRAMES} tcp)
endforeach()
add_test(NAME node_pack_unix_accuracy_spheres
  COMMAND ${NODE_TEST_DIR}/accuracy.sh ${NODE_BIN} spheres ${NODE_OUT}/unix-spheres ${NODE_FRAMES} unix)
add_test(NAME node_two_concurrent_clients_each_exact
  COMMAND ${NODE_TEST_DIR}/two_clients.sh ${NODE_BIN} ${NODE_OUT}/two-clients 6)
add_test(NAME node_pack_replies_roundtrip
  COMMAND ${NODE_TEST_DIR}/replies.sh ${NODE_BIN} ${NODE_OUT}/replies $<TARGET_FILE:node_driver>)
add_test(NAME node_pack_refused_bad_token
  COMMAND ${NODE_TEST_DIR}/failures.sh bad-token ${NODE_BIN} ${NODE_OUT}/bad-token)
add_test(NAME node_pack_server_missing_clear_error
  COMMAND ${NODE_TEST_DIR}/failures.sh server-missing ${NODE_BIN} ${NODE_OUT}/server-missing)
add_test(NAME node_server_survives_garbage_client
  COMMAND ${NODE_TEST_DIR}/failures.sh garbage-client ${NODE_BIN} ${NODE_OUT}/garbage
          $<TARGET_FILE:node_driver>)
add_test(NAME node_server_killed_app_exits_nonzero
  COMMAND ${NODE_TEST_DIR}/failures.sh node-killed ${NODE_BIN} ${NODE_OUT}/killed)
add_test(NAME node_client_chain_failure_reaches_the_app
  COMMAND ${NODE_TEST_DIR}/failures.sh client-chain-fails ${NODE_BIN} ${NODE_OUT}/chain-fails)
add_test(NAME node_shared_stopped_client_dropped_named_after_idle_timeout
  COMMAND ${NODE_TEST_DIR}/failures.sh client-stopped ${NODE_BIN} ${NODE_OUT}/client-stopped)
add_test(NAME node_slow_server_full_window_clients_stay_alive
  COMMAND ${NODE_TEST_DIR}/failures.sh server-slow ${NODE_BIN} ${NODE_OUT}/server-slow)
add_test(NAME node_busy_client_computing_between_frames_not_dropped
  COMMAND ${NODE_TEST_DIR}/failures.sh client-busy ${NODE_BIN} ${NODE_OUT}/client-busy
          $<TARGET_FILE:node_driver>)
add_test(NAME node_unix_listen_replaces_only_stale_socket_keeps_files
  COMMAND ${NODE_TEST_DIR}/unix_path.sh ${NODE_BIN} ${NODE_OUT}/unix-path)
add_test(NAME node_server_stopped_app_exits_nonzero_after_timeout
  COMMAND ${NODE_TEST_DIR}/failures.sh node-stopped ${NODE_BIN} ${NODE_OUT}/stopped)

# Per-client budgets (issue 10, defects 5 and 6): a hostile first client of
# a shared node is refused with one line naming it and the budget, the
# node stays under 1 GiB, and the next client's frames are exact.
macro(node_budget_test name case budget_re)
  add_test(NAME ${name} COMMAND ${NODE_TEST_DIR}/budget.sh ${case} ${NODE_BIN} ${NODE_OUT}/${name}
    $<TARGET_FILE:budget_driver> "${budget_re}" ${ARGN})
endmacro()
node_budget_test(node_budget_readpixels_huge_unread_refused_by_server_reply_limit readpixels
  "command ReadPixels .*over the reply budget max_reply_bytes=67104760")
node_budget_test(node_budget_pending_replies_unread_dropped readpixels-small
  "over the reply budget max_pending_reply_bytes=1048576" --max-pending-reply-bytes 1048576)
# The same in shared mode, three times over: a client that read pixels and
# was dropped, then the next client's WindowCreateTSR resizing the shared
# window, crashed the node in Mesa's glRenderbufferStorage in 10 of 10 runs
# before the render SPU kept left clients' contexts until the next resize
# (docs/render.md, "Several contexts, one window").
add_test(NAME node_shared_dropped_reader_then_resize_does_not_crash
  COMMAND sh -c "for i in 1 2 3; do \"$0\" readpixels-small \"$1\" \"$2/$i\" \"$3\" \"$4\" --max-pending-reply-bytes 1048576 || exit 1; done"
    ${NODE_TEST_DIR}/budget.sh ${NODE_BIN} ${NODE_OUT}/shared-dropped-reader $<TARGET_FILE:budget_driver>
    "over the reply budget max_pending_reply_bytes=1048576")
# A client granting a huge credit window has far more replies in flight
# than the node keeps sizes of; each one still counts against the budget.
node_budget_test(node_budget_pending_replies_many_small_unread_dropped readpixels-many
  "over the reply budget max_pending_reply_bytes=1048576" --max-pending-reply-bytes 1048576)
node_budget_test(node_budget_teximage_null_over_texture_budget teximage "max_texture_bytes=536870912")
node_budget_test(node_draw_arrays_no_arrays_over_vertex_budget draw-arrays "max_vertices=16777216")
node_budget_test(node_draw_arrays_past_vertex_buffer_refused vbo-arrays "lies past the 72 bytes of buffer 1")
node_budget_test(node_draw_elements_past_index_buffer_refused vbo-elements "lie past the 72 bytes of buffer 2")
node_budget_test(node_window_over_max_window_pixels_refused window "max_window_pixels=16777216")

# `tessera node` itself: help, usage errors, a bad chain, nobody coming.
set(NODE_EXPECT ${CMAKE_CURRENT_SOURCE_DIR}/render/expect.sh)
macro(node_cli_test name rc out_re err_re)
  add_test(NAME ${name} COMMAND ${NODE_EXPECT} ${rc} "${out_re}" "${err_re}" $<TARGET_FILE:tessera_cli> node ${ARGN})
endmacro()
node_cli_test(node_cli_help_exit_0 0 "usage: tessera node --listen ADDR --chain" "" --help)
node_cli_test(node_cli_without_listen_is_usage_error_exit_2 2 "" "--listen and --chain are required"
  --chain render)
node_cli_test(node_cli_bad_clients_is_usage_error_exit_2 2 "" "bad --clients '0'"
  --listen tcp://127.0.0.1:0 --chain render --clients 0)
node_cli_test(node_cli_unknown_spu_in_chain_exit_2 2 "" "chain: unknown SPU .rendr."
  --listen tcp://127.0.0.1:0 --chain rendr)
node_cli_test(node_cli_no_client_in_time_exit_1 1 "^listening on tcp://127.0.0.1:[1-9]"
  "0 of 1 clients connected to tcp://127.0.0.1:[0-9]+ within 300 ms"
  --listen tcp://127.0.0.1:0 --chain render --timeout-ms 300)

get_property(NODE_TESTS_AFTER DIRECTORY PROPERTY TESTS)
if(NODE_TESTS_BEFORE)
  list(REMOVE_ITEM NODE_TESTS_AFTER ${NODE_TESTS_BEFORE})
endif()
set(NODE_ENV "")
# Sanitizer builds: OSMesa/LLVM keep process-lifetime allocations that
# LeakSanitizer reports; suppress those (tests/lsan.supp), check ours.
if(TESSERA_SANITIZE)
  set(NODE_ENV "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp:print_suppressions=0:use_tls=0")
endif()
set_tests_properties(${NODE_TESTS_AFTER} PROPERTIES TIMEOUT 120 LABELS node ENVIRONMENT "${NODE_ENV}")
