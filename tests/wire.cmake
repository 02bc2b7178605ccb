# Wire format tests (engineer H2): one runner, one ctest per behaviour.
add_executable(wire_test ${CMAKE_CURRENT_SOURCE_DIR}/wire/wire_test.c ${TESSERA_GEN_TEST_SOURCES})
add_dependencies(wire_test tessera_generated spu_print spu_loopback)
target_include_directories(wire_test PRIVATE ${CMAKE_SOURCE_DIR}/core ${TESSERA_GEN_DIR}/src
                                              ${CMAKE_CURRENT_SOURCE_DIR}/wire)
target_link_libraries(wire_test PRIVATE tessera tessera_gl)

foreach(t
    wire_roundtrip_all_commands
    wire_vertex3f_is_13_bytes
    wire_extended_opcode_roundtrip
    wire_commands_exactly_fill_a_buffer
    wire_large_command_gets_its_own_buffer
    wire_begin_end_split_across_buffers
    wire_client_arrays_draw_arrays_rebuild
    wire_client_arrays_draw_elements_rebuild
    wire_enable_of_a_client_array_is_client_state
    wire_query_of_an_unknown_pname_is_invalid_enum_not_a_dropped_stream
    wire_setter_of_an_unknown_pname_is_invalid_enum_not_a_dropped_call
    wire_pixel_command_gl_refuses_is_its_gl_error_not_sent_nor_read
    wire_shader_source_roundtrip
    wire_pixel_store_shapes_image_payloads
    wire_unpack_rejects_unknown_opcode
    wire_unpack_rejects_truncated_command
    wire_unpack_rejects_length_beyond_buffer
    wire_unpack_rejects_count_overflow
    wire_unpack_rejects_negative_size
    wire_unpack_rejects_bad_header
    wire_unpack_survives_mutations
    wire_print_spu_traces_calls
    wire_reply_slot_hands_out_only_the_reply_asked_for
    wire_loop_shows_its_observer_every_buffer_and_reply_and_destroy_flushes)
  add_test(NAME ${t} COMMAND wire_test ${t} WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR})
endforeach()

# Seed corpus for the unpacker fuzzer (tests/fuzz): real buffers, each
# checked to decode. `wire_make_seeds DIR` writes them anywhere.
add_executable(wire_make_seeds ${CMAKE_CURRENT_SOURCE_DIR}/wire/make_seeds_test.c ${TESSERA_GEN_TEST_SOURCES})
add_dependencies(wire_make_seeds tessera_generated)
target_include_directories(wire_make_seeds PRIVATE ${CMAKE_SOURCE_DIR}/core ${TESSERA_GEN_DIR}/src)
target_link_libraries(wire_make_seeds PRIVATE tessera)
add_test(NAME wire_seed_corpus_decodes COMMAND wire_make_seeds ${CMAKE_CURRENT_BINARY_DIR}/wire_seeds)

# Pixel-store extents against real GL (links OSMesa, not libtessera_gl).
add_executable(wire_pixel_osmesa ${CMAKE_CURRENT_SOURCE_DIR}/wire/pixel_osmesa_test.c)
target_include_directories(wire_pixel_osmesa PRIVATE ${CMAKE_SOURCE_DIR}/core)
target_link_libraries(wire_pixel_osmesa PRIVATE tessera PkgConfig::OSMESA)
add_test(NAME wire_pixel_extents_match_osmesa COMMAND wire_pixel_osmesa)
add_test(NAME wire_glprocs_resolve_in_osmesa COMMAND wire_pixel_osmesa glprocs)
if(TESSERA_SANITIZE)
  # Mesa keeps process-lifetime caches that LeakSanitizer reports
  # (tests/lsan.supp); tessera's own allocations are still checked.
  set_tests_properties(wire_pixel_extents_match_osmesa wire_glprocs_resolve_in_osmesa PROPERTIES ENVIRONMENT
    "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp:print_suppressions=0:use_tls=0")
endif()
