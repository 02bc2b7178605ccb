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
add_executable(composite_test ${CMAKE_CURRENT_SOURCE_DIR}/composite/composite_test.c
  ${CMAKE_CURRENT_SOURCE_DIR}/composite/fuzz_composite_message.c)
target_link_libraries(composite_test PRIVATE tessera_composite_strategies tessera Threads::Threads m)

foreach(t
    composite_depth_kernel_matches_reference
    composite_over_kernel_matches_reference
    composite_large_messages_any_alignment
    composite_nan_depth_never_wins
    composite_compress_runs_match_pixel_rule
    composite_sparse_merge_equals_dense
    composite_sparse_fold_equals_merges
    composite_split_at_run_edges
    composite_codecs_roundtrip
    composite_codec_worst_case_size
    composite_message_decoder_rejects_bad_input
    composite_encode_dense_equals_compress_encode
    composite_message_view_equals_decode
    composite_schedules_hold_invariants
    composite_link_bytes_hold_one_frame
    composite_executor_keeps_one_piece
    composite_filled_final_pieces_equal_gathered
    binaryswap_odd_peer_counts
    composite_all_strategies_agree
    composite_odd_image_sizes
    composite_blank_peers
    composite_alpha_strategies_agree
    composite_faults_name_the_peer
    composite_alpha_schedules_keep_order
    composite_over_float_kernel_matches_reference)
  string(REPLACE "composite_" "" arg ${t})
  add_test(NAME ${t} COMMAND composite_test ${arg})
  set_tests_properties(${t} PROPERTIES TIMEOUT 300)
endforeach()

# The image-message decoder's fuzz corpus (tests/composite/corpus), replayed
# in every build (under ASan in the sanitizer build); the seed writer
# refreshes it (`composite_test fuzz_seeds tests/composite/corpus`) and as a
# test proves the seeds still decode or are rejected as named.
add_test(NAME composite_message_fuzz_corpus_replay
  COMMAND composite_test fuzz_replay ${CMAKE_CURRENT_SOURCE_DIR}/composite/corpus)
file(MAKE_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR}/composite_seeds)
add_test(NAME composite_message_fuzz_seeds_decode_or_reject
  COMMAND composite_test fuzz_seeds ${CMAKE_CURRENT_BINARY_DIR}/composite_seeds)
if(TESSERA_FUZZ)
  # libFuzzer target over the image module's own sources (coverage then
  # measures the decoder and the sparse code, not the rest of libtessera).
  add_executable(fuzz_composite_message ${CMAKE_CURRENT_SOURCE_DIR}/composite/fuzz_composite_message.c
    ${CMAKE_SOURCE_DIR}/core/image/composite.c ${CMAKE_SOURCE_DIR}/core/image/composite_sparse.c
    ${CMAKE_SOURCE_DIR}/core/image/composite_message.c ${CMAKE_SOURCE_DIR}/core/util/error.c)
  target_include_directories(fuzz_composite_message PRIVATE ${CMAKE_SOURCE_DIR}/include ${TESSERA_GEN_DIR}/include)
  target_compile_definitions(fuzz_composite_message PRIVATE TSR_FUZZ_MAIN)
  target_compile_options(fuzz_composite_message PRIVATE -fsanitize=fuzzer,address,undefined
    -fno-sanitize-recover=all -fno-omit-frame-pointer)
  target_link_options(fuzz_composite_message PRIVATE -fsanitize=fuzzer,address,undefined)
  target_link_libraries(fuzz_composite_message PRIVATE m)
  add_test(NAME fuzz_composite_message_runs_corpus
    COMMAND fuzz_composite_message -runs=2000 -max_len=65536 ${CMAKE_CURRENT_SOURCE_DIR}/composite/corpus)
endif()
