# tests/composite.cmake — sort-last compositing (tessera/dev/composite.h in
# core/image, the strategies in spus/binaryswap/strategies): kernels against
# plain reference loops on random and adversarial inputs, sparse against
# dense, codecs round trips and the worst-case size, and every strategy's
# schedule for 1..64 peers executed in one process over in-memory queues
# (one thread per peer) against a serial reference composite.
if(NOT TARGET tessera_composite_strategies)
  add_subdirectory(${CMAKE_SOURCE_DIR}/spus/binaryswap/strategies
                   ${CMAKE_BINARY_DIR}/spus/binaryswap/strategies)
endif()
add_executable(composite_tests ${CMAKE_CURRENT_SOURCE_DIR}/composite/composite_tests.c)
target_link_libraries(composite_tests PRIVATE tessera_composite_strategies tessera Threads::Threads m)

foreach(t
    composite_depth_kernel_matches_reference
    composite_over_kernel_matches_reference
    composite_nan_depth_never_wins
    composite_sparse_merge_equals_dense
    composite_split_at_run_edges
    composite_codecs_roundtrip
    composite_codec_worst_case_size
    composite_message_decoder_rejects_bad_input
    composite_schedules_hold_invariants
    binaryswap_odd_peer_counts
    composite_all_strategies_agree
    composite_odd_image_sizes
    composite_blank_peers
    composite_alpha_strategies_agree)
  string(REPLACE "composite_" "" arg ${t})
  add_test(NAME ${t} COMMAND composite_tests ${arg})
  set_tests_properties(${t} PROPERTIES TIMEOUT 300)
endforeach()
