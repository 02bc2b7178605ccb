# tests/state.cmake — the state tracker (core/state*.c): coverage of the
# spec, diffs into real OSMesa contexts (directly and through the real
# packer/unpacker) queried back against the tracker's own answers, zero-byte
# diffs of unchanged state, context switches, many renderers, lazy textures,
# shaders and programs.
add_executable(state_test ${CMAKE_CURRENT_SOURCE_DIR}/state/state_test.c ${TESSERA_GEN_TRACE_SOURCES})
add_dependencies(state_test tessera_generated)
target_include_directories(state_test PRIVATE ${CMAKE_SOURCE_DIR}/core ${TESSERA_GEN_DIR}/src)
target_link_libraries(state_test PRIVATE tessera ${CMAKE_DL_LIBS} m)

add_test(NAME state_covers_spec COMMAND state_test covers_spec)
add_test(NAME state_diff_into_osmesa_queries_back_equal COMMAND state_test diff_matches_osmesa 200)
add_test(NAME state_unchanged_state_diffs_to_zero_bytes COMMAND state_test unchanged_is_zero_bytes 100)
add_test(NAME state_context_switch_emits_only_differing_groups COMMAND state_test switch_only_differing_groups 20)
add_test(NAME state_many_renderers_grow_dirty_bits COMMAND state_test many_renderers)
add_test(NAME state_textures_sent_lazily_and_once COMMAND state_test lazy_textures)
add_test(NAME state_image_units_past_the_coordinate_units_diffed_and_walked_cheaply COMMAND state_test image_units)
add_test(NAME state_list_compile_does_not_change_state COMMAND state_test list_compile)
add_test(NAME state_diff_sends_every_buffer_with_data_bound_or_not_once
         COMMAND state_test buffers_unbound_reach_renderer)
add_test(NAME state_get_count_table_matches_the_gets COMMAND state_test get_count_table)
add_test(NAME state_matrices_bit_identical_and_lit_pixels_equal COMMAND state_test matrices_bit_identical 200)
add_test(NAME state_multmatrix_of_the_identity_keeps_the_matrix_class
         COMMAND state_test multmatrix_of_the_identity_keeps_the_matrix_class)
add_test(NAME state_long_matrix_history_keeps_the_matrix_class
         COMMAND state_test long_matrix_history_keeps_the_matrix_class)
# Shaders and programs: random object/uniform sequences diffed into a fresh
# OSMesa context equal OSMesa given the calls (status, locations, uniform
# values, pixels), with different driver names on both sides.
add_test(NAME state_glsl_programs_diff_into_osmesa_equal_direct COMMAND state_test glsl_diff_matches_osmesa 120)
add_test(NAME state_glsl_programs_sent_lazily_and_once COMMAND state_test glsl_lazy)
set_tests_properties(state_diff_into_osmesa_queries_back_equal state_glsl_programs_diff_into_osmesa_equal_direct
  PROPERTIES TIMEOUT 600)
if(TESSERA_SANITIZE)
  # Mesa keeps process-lifetime caches that LeakSanitizer reports
  # (tests/lsan.supp); tessera's own allocations are still checked.
  set_tests_properties(state_diff_into_osmesa_queries_back_equal state_matrices_bit_identical_and_lit_pixels_equal
    state_multmatrix_of_the_identity_keeps_the_matrix_class state_long_matrix_history_keeps_the_matrix_class
    state_glsl_programs_diff_into_osmesa_equal_direct
    PROPERTIES ENVIRONMENT
    "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp:print_suppressions=0:use_tls=0")
endif()
