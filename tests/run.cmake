# tests/run.cmake — `tessera run`, `tessera mothership` and
# `tessera node --mothership` with real processes and sockets: example
# graphs compared frame by frame with the native reference, failures
# (kill -9 / SIGSTOP mid-stream) ending the run with the node named and no
# process left, several "machines" on one host, a run across network
# namespaces, and the CLI's errors. Every test is bounded in time.
# Included by tests/CMakeLists.txt.
get_property(RUN_TESTS_BEFORE DIRECTORY PROPERTY TESTS)
set(RUN_DIR ${CMAKE_CURRENT_SOURCE_DIR}/run)
set(RUN_OUT ${CMAKE_BINARY_DIR}/test-out/run)
set(RUN_BIN ${CMAKE_BINARY_DIR}/bin)
set(RUN_GRAPHS ${CMAKE_SOURCE_DIR}/examples/graphs)
file(MAKE_DIRECTORY ${RUN_OUT})

# One line per graph: run_graph.sh BIN GRAPH OUT FRAMES REFERENCE [ARGS...]
# compares every output the graph names with the reference, frame by frame.
macro(run_graph_test name graph frames)
  add_test(NAME ${name} COMMAND ${RUN_DIR}/run_graph.sh ${RUN_BIN} ${graph} ${RUN_OUT}/${name}
           ${frames} ${ARGN})
endmacro()
run_graph_test(run_graph_local_exact ${RUN_GRAPHS}/local.yaml 20 spheres-native --size 1024x768)
run_graph_test(run_graph_trace_exact ${RUN_GRAPHS}/trace.yaml 10 isosurface-native --size 1024x768)
run_graph_test(run_graph_tcp_exact ${RUN_GRAPHS}/tcp.yaml 20 spheres-native --size 1024x768)
run_graph_test(run_graph_unix_exact ${RUN_GRAPHS}/unix.yaml 20 spheres-native --size 1024x768)
if(TARGET spu_replicate)
  run_graph_test(run_graph_replicate_three_servers_exact ${RUN_GRAPHS}/replicate.yaml 20
                 spheres-native --size 1024x768)
endif()

# A network SPU that is not tessera's (tests/run/relay/relay.c), built out
# of tree against an install of this build, in a graph to a render server.
set(RUN_RELAY_CFLAGS "")
if(TESSERA_SANITIZE)
  set(RUN_RELAY_CFLAGS "-fsanitize=address,undefined -fno-omit-frame-pointer")
endif()
add_test(NAME run_graph_out_of_tree_relay_spu_exact
  COMMAND sh ${RUN_DIR}/relay_out_of_tree.sh ${CMAKE_COMMAND} ${CMAKE_BINARY_DIR} ${CMAKE_SOURCE_DIR}
          ${RUN_OUT}/relay ${CMAKE_C_COMPILER} "${RUN_RELAY_CFLAGS}")

# A group of peers (TSR_SPU_ROLE_PEERS): ranks and every peer's address,
# each peer's chain given once all of them listen (tests/run/peers/).
set(RUN_PLUGIN_DIR ${CMAKE_CURRENT_BINARY_DIR}/run_plugins)
add_library(run_test_peerprobe MODULE ${RUN_DIR}/peers/peerprobe.c)
target_link_libraries(run_test_peerprobe PRIVATE tessera tessera_client)
set_target_properties(run_test_peerprobe PROPERTIES PREFIX "" OUTPUT_NAME peerprobe_spu
  LIBRARY_OUTPUT_DIRECTORY ${RUN_PLUGIN_DIR} C_VISIBILITY_PRESET hidden)
add_test(NAME run_graph_peer_group_told_ranks_and_addresses
  COMMAND ${RUN_DIR}/peers/peers.sh ${RUN_BIN} ${RUN_PLUGIN_DIR} ${RUN_OUT}/peers)

add_test(NAME run_progress_summary_and_stats_json_agree
  COMMAND ${RUN_DIR}/stats.sh ${RUN_BIN} ${RUN_OUT}/stats ${RUN_GRAPHS}/tcp.yaml 20)
if(TARGET psubmit-native)
  run_graph_test(run_graph_psubmit_four_apps_exact ${RUN_GRAPHS}/psubmit.yaml 10
                 psubmit-native --size 1024x768)
endif()

foreach(c kill-server kill-app stop-server stop-app-node stop-app interrupt kill-mothership)
  string(REPLACE "-" "_" c_ ${c})
  add_test(NAME run_failure_${c_}_ends_run_names_node_leaves_nothing
    COMMAND ${RUN_DIR}/failures.sh ${c} ${RUN_BIN} ${RUN_OUT}/failure-${c})
endforeach()

foreach(c name env unknown-name)
  string(REPLACE "-" "_" c_ ${c})
  add_test(NAME run_mothership_separate_nodes_${c_}
    COMMAND ${RUN_DIR}/multi.sh ${c} ${RUN_BIN} ${RUN_OUT}/multi-${c} ${RUN_GRAPHS}/tcp.yaml)
endforeach()

add_test(NAME run_mothership_separate_nodes_server_killed_names_it
  COMMAND ${RUN_DIR}/multi.sh kill-server ${RUN_BIN} ${RUN_OUT}/multi-kill-server ${RUN_DIR}/long.yaml)

# A hostile node's DONE text reaches the terminal escaped (issue 10, defect 10).
add_executable(fake_node ${RUN_DIR}/fake_node_peer.c)
target_link_libraries(fake_node PRIVATE tessera_mothership tessera_net)
add_test(NAME run_node_done_message_escape_sequences_printed_escaped
  COMMAND ${RUN_DIR}/fake_node.sh ${RUN_BIN} $<TARGET_FILE:fake_node> ${RUN_OUT}/fake-node ${RUN_DIR}/long.yaml server)
set_tests_properties(run_node_done_message_escape_sequences_printed_escaped PROPERTIES TIMEOUT 90)

add_test(NAME run_netns_four_hosts_over_tcp
  COMMAND ${RUN_DIR}/netns.sh ${RUN_BIN} ${RUN_OUT}/netns)
set_tests_properties(run_netns_four_hosts_over_tcp PROPERTIES SKIP_RETURN_CODE 77)

# The CLI: help, usage errors and bad input, each one clear line.
set(RUN_EXPECT ${CMAKE_CURRENT_SOURCE_DIR}/render/expect.sh)
set(RUN_TESSERA $<TARGET_FILE:tessera_cli>)
macro(run_cli_test name rc out_re err_re)
  add_test(NAME ${name} COMMAND ${RUN_EXPECT} ${rc} "${out_re}" "${err_re}" ${ARGN})
endmacro()
run_cli_test(run_cli_help_exit_0 0 "usage: tessera run GRAPH" "" ${RUN_TESSERA} run --help)
run_cli_test(run_cli_mothership_help_exit_0 0 "usage: tessera mothership GRAPH --listen ADDR" ""
  ${RUN_TESSERA} mothership --help)
run_cli_test(run_cli_node_help_names_mothership_mode 0 "tessera node --mothership HOST:PORT" ""
  ${RUN_TESSERA} node --help)
run_cli_test(run_cli_bad_graph_exit_2_file_line_col 2 "" "bad.yaml:7:5: .*chian"
  ${RUN_TESSERA} run ${RUN_DIR}/bad.yaml)
run_cli_test(run_cli_inproc_server_refused_exit_2 2 ""
  "inproc.yaml:12:16: node 'server': transport inproc cannot be run as its own process yet"
  ${RUN_TESSERA} run ${RUN_DIR}/inproc.yaml --out ${RUN_OUT}/inproc)
# What check refuses, run refuses the same way; what check accepts, run runs.
run_cli_test(run_cli_option_list_for_string_refused_exit_2 2 ""
  "option_list_for_string.yaml:8:26: node 'app': render: option 'output': expected one string value, got a list"
  ${RUN_TESSERA} run ${CMAKE_CURRENT_SOURCE_DIR}/graph/bad/option_list_for_string.yaml --out ${RUN_OUT}/list-output)
add_test(NAME run_exec_with_1200_arguments_reaches_the_application
  COMMAND ${RUN_DIR}/many_args.sh ${RUN_TESSERA} ${RUN_OUT}/many-args)
# --out and --stats paths that cannot be used: one line, exit 2, before the run.
foreach(c out-is-a-file out-under-a-file stats-no-folder stats-is-a-folder)
  string(REPLACE "-" "_" c_ ${c})
  add_test(NAME run_cli_${c_}_refused_before_the_run
    COMMAND ${RUN_DIR}/cli_paths.sh ${c} ${RUN_TESSERA} ${RUN_GRAPHS}/local.yaml ${RUN_OUT}/cli-paths-${c})
endforeach()
run_cli_test(run_cli_missing_exec_names_node_and_program 1 ""
  "^tessera run: node .app.: exec .bin/no-such-program.: not found .looked in "
  timeout 60 ${RUN_TESSERA} run ${RUN_DIR}/missing-exec.yaml --out ${RUN_OUT}/missing-exec --no-progress)
run_cli_test(run_cli_mothership_without_listen_exit_2 2 "" "--listen ADDR is required"
  ${RUN_TESSERA} mothership ${RUN_GRAPHS}/tcp.yaml)
run_cli_test(run_cli_node_mothership_nobody_listens_bounded_exit_1 1 ""
  "cannot reach the mothership at tcp://127.0.0.1:1 within 500 ms"
  timeout 20 ${RUN_TESSERA} node --mothership 127.0.0.1:1 --name app --connect-timeout-ms 500)
run_cli_test(run_cli_node_mothership_needs_name_or_rank_exit_2 2 "" "needs --name NAME or --rank N"
  env -u OMPI_COMM_WORLD_RANK -u PMI_RANK -u SLURM_PROCID ${RUN_TESSERA} node --mothership 127.0.0.1:1)
run_cli_test(run_cli_node_rank_from_env_is_checked_exit_2 2 "" "bad rank 'x' from OMPI_COMM_WORLD_RANK"
  env OMPI_COMM_WORLD_RANK=x ${RUN_TESSERA} node --mothership 127.0.0.1:1)
run_cli_test(run_cli_node_mothership_with_chain_exit_2 2 "" "no --listen or --chain"
  ${RUN_TESSERA} node --mothership 127.0.0.1:1 --name a --chain render)

get_property(RUN_TESTS_AFTER DIRECTORY PROPERTY TESTS)
if(RUN_TESTS_BEFORE)
  list(REMOVE_ITEM RUN_TESTS_AFTER ${RUN_TESTS_BEFORE})
endif()
set(RUN_ENV "")
# Sanitizer builds: OSMesa/LLVM keep process-lifetime allocations (tests/lsan.supp).
if(TESSERA_SANITIZE)
  set(RUN_ENV "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp:print_suppressions=0:use_tls=0")
endif()
set_tests_properties(${RUN_TESTS_AFTER} PROPERTIES TIMEOUT 180 LABELS run ENVIRONMENT "${RUN_ENV}")
