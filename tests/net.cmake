# tests/net.cmake — netlib (tessera/dev/net.h) over real sockets, threads and
# processes. Included by tests/CMakeLists.txt.
set(NET_TEST_SRC ${CMAKE_CURRENT_SOURCE_DIR}/net)
add_executable(net_test ${NET_TEST_SRC}/net_test.c)
add_executable(net_flow_test ${NET_TEST_SRC}/net_flow_test.c)
add_executable(net_stall_server ${NET_TEST_SRC}/net_stall_server_peer.c)
add_executable(net_auth_test ${NET_TEST_SRC}/net_auth_test.c)
foreach(t net_test net_flow_test net_stall_server net_auth_test)
  target_link_libraries(${t} PRIVATE tessera_net PkgConfig::SODIUM Threads::Threads)
endforeach()

foreach(pair
    "net_tcp_roundtrip_ipv4:tcp_roundtrip_ipv4"
    "net_tcp_roundtrip_ipv6:tcp_roundtrip_ipv6"
    "net_unix_roundtrip:unix_roundtrip"
    "net_tcp_connect_by_host_name_tries_every_address:connect_by_host_name"
    "net_inproc_roundtrip:inproc_roundtrip"
    "net_inproc_send_blocks_until_release:inproc_credits"
    "net_large_message_64bit_length_rejected_over_max:large_message_rejected"
    "net_malformed_frames_fail_only_their_connection:malformed_frames"
    "net_handshake_version_mismatch_refused_both_sides:version_mismatch"
    "net_handshake_bad_token_refused:bad_token"
    "net_port_in_use_clear_error:port_in_use"
    "net_connect_refused_clear_error:connect_refused"
    "net_handshake_timeout_silent_peer:handshake_timeout"
    "net_connect_timeout_unanswered_syn:connect_timeout"
    "net_idle_timeout_detects_silent_peer:idle_timeout"
    "net_many_clients_one_server:many_clients"
    "net_recv_any_serves_clients_round_robin:recv_any_round_robin"
    "net_destroy_with_open_connections_is_bounded_and_clean:destroy_open_connections"
    "net_tcp_direct_writes_under_credit_exhaustion_exact:tcp_direct_writes"
    "net_unix_direct_writes_under_credit_exhaustion_exact:unix_direct_writes"
    "net_tcp_direct_write_rest_finished_by_io_thread_exact:tcp_direct_write_rest"
    "net_peer_closes_during_direct_writes_fails_send_in_time:peer_closes_during_direct_writes"
    "net_peer_name_and_refuse_reason_escaped:peer_text_escaped")
  string(REPLACE ":" ";" pair "${pair}")
  list(GET pair 0 name)
  list(GET pair 1 sub)
  add_test(NAME ${name} COMMAND net_test ${sub})
  set_tests_properties(${name} PROPERTIES TIMEOUT 30 LABELS net)
endforeach()
set_tests_properties(net_tcp_roundtrip_ipv6 net_connect_timeout_unanswered_syn
  PROPERTIES SKIP_RETURN_CODE 77)

# Shared memory between the ends of a Unix-socket connection (net.h,
# SHARED MEMORY; issue 11, item 7).
add_executable(net_shm_test ${NET_TEST_SRC}/net_shm_test.c)
target_link_libraries(net_shm_test PRIVATE tessera_net PkgConfig::SODIUM Threads::Threads)
foreach(pair
    "net_shm_unix_messages_travel_through_the_ring_exact:roundtrip"
    "net_shm_receiver_reads_the_senders_memory_no_copy:zero_copy"
    "net_shm_ring_space_is_the_credit:ring_is_the_credit"
    "net_shm_ring_reuses_its_start_while_one_is_held:ring_reuses_its_start"
    "net_shm_sender_waiting_for_releases_writes_at_the_ring_start:wait_returned"
    "net_shm_receiver_drops_released_pages_only_when_asked:drop_released"
    "net_shm_only_when_both_ask_and_only_on_unix:negotiation"
    "net_shm_lying_peer_fails_only_its_connection_naming_it:lying_peer")
  string(REPLACE ":" ";" pair "${pair}")
  list(GET pair 0 name)
  list(GET pair 1 sub)
  add_test(NAME ${name} COMMAND net_shm_test ${sub})
  set_tests_properties(${name} PROPERTIES TIMEOUT 60 LABELS net)
endforeach()

add_test(NAME net_flow_control_stalled_receiver
         COMMAND net_flow_test stall $<TARGET_FILE:net_stall_server>)
add_test(NAME net_receiver_killed_while_sender_blocked_fails_send
         COMMAND net_flow_test kill $<TARGET_FILE:net_stall_server>)
set_tests_properties(net_flow_control_stalled_receiver
  net_receiver_killed_while_sender_blocked_fails_send PROPERTIES TIMEOUT 60 LABELS net)

# Who holds a place on a listener and who gets in (issue 10, defects 7, 14).
foreach(pair
    "net_idle_connections_do_not_lock_out_clients:idle_flood"
    "net_handshake_token_never_on_the_wire:token_not_on_the_wire"
    "net_handshake_replayed_client_proof_refused:replayed_proof"
    "net_handshake_fake_server_refused_by_client:fake_server"
    "net_handshake_client_without_token_refused_by_server:client_without_token_knowledge"
    "net_address_is_local_only_for_loopback:address_scope")
  string(REPLACE ":" ";" pair "${pair}")
  list(GET pair 0 name)
  list(GET pair 1 sub)
  add_test(NAME ${name} COMMAND net_auth_test ${sub})
  set_tests_properties(${name} PROPERTIES TIMEOUT 60 LABELS net)
endforeach()

# A standalone node without --token on an address other hosts reach
# refuses to start unless --insecure; on loopback it warns (defect 14).
set(NET_EXPECT ${CMAKE_CURRENT_SOURCE_DIR}/render/expect.sh)
add_test(NAME node_cli_no_token_non_loopback_refused_without_insecure_exit_2
  COMMAND ${NET_EXPECT} 2 "" "refusing to listen on tcp://0.0.0.0:0 without --token.*--insecure"
          $<TARGET_FILE:tessera_cli> node --listen tcp://0.0.0.0:0 --chain render)
add_test(NAME node_cli_no_token_non_loopback_starts_with_insecure_and_warns
  COMMAND ${NET_EXPECT} 1 "^listening on tcp://0.0.0.0:[1-9]" "warning: --insecure: anyone who reaches it"
          $<TARGET_FILE:tessera_cli> node --listen tcp://0.0.0.0:0 --chain render --insecure --timeout-ms 300)
add_test(NAME node_cli_no_token_loopback_warns
  COMMAND ${NET_EXPECT} 1 "^listening on tcp://127.0.0.1:[1-9]" "warning: no --token: any local user can connect to it .tcp://127.0.0.1:[1-9]"
          $<TARGET_FILE:tessera_cli> node --listen tcp://127.0.0.1:0 --chain render --timeout-ms 300)
add_test(NAME node_cli_token_non_loopback_starts_without_warning
  COMMAND ${NET_EXPECT} 1 "^listening on tcp://0.0.0.0:[1-9]" "^tessera node: 0 of 1 clients"
          $<TARGET_FILE:tessera_cli> node --listen tcp://0.0.0.0:0 --chain render --token t0k --timeout-ms 300)
set_tests_properties(node_cli_no_token_non_loopback_refused_without_insecure_exit_2
  node_cli_no_token_non_loopback_starts_with_insecure_and_warns node_cli_no_token_loopback_warns
  node_cli_token_non_loopback_starts_without_warning PROPERTIES TIMEOUT 60 LABELS net)

# The mothership's control listener is netlib's too: the same flood, the
# nodes of a real run must still join (defect 7).
add_test(NAME net_mothership_idle_connections_do_not_lock_out_nodes
  COMMAND ${NET_TEST_SRC}/mothership_flood.sh ${CMAKE_BINARY_DIR}/bin
          ${CMAKE_BINARY_DIR}/test-out/net/mothership-flood ${CMAKE_SOURCE_DIR}/examples/graphs/tcp.yaml
          $<TARGET_FILE:net_auth_test>)
set_tests_properties(net_mothership_idle_connections_do_not_lock_out_nodes PROPERTIES TIMEOUT 120 LABELS net)

# Sort-last peers on one host (issue 11, item 7): their own per-pair
# statistics prove unix: peers exchange images through shared memory, and
# that shm=0 and tcp:// peers do not; every frame exact.
set(NET_SORTLAST_ENV "LP_NUM_THREADS=0")
if(TESSERA_SANITIZE) # OSMesa/LLVM keep state for the process lifetime
  list(APPEND NET_SORTLAST_ENV "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp:print_suppressions=0:use_tls=0")
endif()
foreach(pair
    "binaryswap_same_host_unix_peers_use_shared_memory_exact:unix"
    "binaryswap_same_host_shm_off_uses_the_unix_socket_exact:noshm"
    "binaryswap_same_host_tcp_peers_use_tcp_exact:tcp")
  string(REPLACE ":" ";" pair "${pair}")
  list(GET pair 0 name)
  list(GET pair 1 mode)
  add_test(NAME ${name} COMMAND ${NET_TEST_SRC}/binaryswap_transport.sh ${mode} ${CMAKE_BINARY_DIR}/bin
           ${CMAKE_BINARY_DIR}/test-out/net/${name})
  set_tests_properties(${name} PROPERTIES TIMEOUT 120 LABELS net FAIL_REGULAR_EXPRESSION "FAIL:"
                       ENVIRONMENT "${NET_SORTLAST_ENV}")
endforeach()
