# tests/capture.cmake — the capture SPU and `tessera replay` (issue 12,
# item 5): captures replay bit-identically through a chain and as the app
# node of graphs (pack, a 2x2 tilesort wall, replicate), frame ranges and
# loops, --info against a print trace, print floats=hex against the %g
# trace, answers captured from a server
# replayed with none, malformed files refused naming file and offset, the
# capture decoder's fuzz corpus, and glxgears captured under Xvfb. Windows
# are 64x48 and runs a few frames: about 5 s in all.
set(CAPTURE_TEST_DIR ${CMAKE_CURRENT_SOURCE_DIR}/capture)
set(CAPTURE_OUT ${CMAKE_BINARY_DIR}/test-out/capture)
file(MAKE_DIRECTORY ${CAPTURE_OUT})

add_executable(capture_asks ${CAPTURE_TEST_DIR}/asks_driver.c)
target_link_libraries(capture_asks PRIVATE tessera tessera_gl)

foreach(mode_name
    "chain;capture_replay_through_render_every_frame_bit_identical"
    "graphs;capture_replay_as_graph_app_pack_wall_2x2_replicate_every_frame_bit_identical"
    "ranges;capture_replay_frames_ranges_and_loops_bit_identical"
    "info;capture_replay_info_counts_equal_a_print_trace_of_the_run"
    "hexfloats;capture_replay_print_floats_hex_exact_and_equal_to_the_g_trace")
  list(GET mode_name 0 mode)
  list(GET mode_name 1 name)
  add_test(NAME ${name}
           COMMAND bash ${CAPTURE_TEST_DIR}/replay.sh ${mode} $<TARGET_FILE:tessera_cli> $<TARGET_FILE:spheres>
                   ${CAPTURE_TEST_DIR} ${CAPTURE_OUT}/${mode})
  set_tests_properties(${name} PROPERTIES TIMEOUT 120)
endforeach()

add_test(NAME capture_answers_from_a_server_replay_with_no_server
         COMMAND bash ${CAPTURE_TEST_DIR}/answers.sh $<TARGET_FILE:tessera_cli> $<TARGET_FILE:capture_asks>
                 ${CAPTURE_OUT}/answers)
set_tests_properties(capture_answers_from_a_server_replay_with_no_server PROPERTIES TIMEOUT 120)

add_test(NAME capture_bad_files_refused_in_one_line_naming_file_and_offset
         COMMAND bash ${CAPTURE_TEST_DIR}/bad.sh $<TARGET_FILE:tessera_cli> $<TARGET_FILE:capture_asks>
                 ${CAPTURE_OUT}/bad)
set_tests_properties(capture_bad_files_refused_in_one_line_naming_file_and_offset PROPERTIES TIMEOUT 120)

# The capture decoder's fuzz target (tests/fuzz/README.md, "Capture files").
tsr_add_fuzz_target(capture
  SOURCES ${CMAKE_SOURCE_DIR}/spus/capture/capfile.c
  FUZZ_SOURCES ${CMAKE_SOURCE_DIR}/core/wire/unpack.c ${CMAKE_SOURCE_DIR}/core/wire/pixel.c
    ${CMAKE_SOURCE_DIR}/core/util/error.c ${CMAKE_SOURCE_DIR}/core/util/log.c
    ${TESSERA_GEN_DIR}/src/unpack_gen.c ${TESSERA_GEN_DIR}/src/wire_tables_gen.c
    ${TESSERA_GEN_DIR}/src/dispatch_gen.c
  INCLUDES ${CMAKE_SOURCE_DIR}/spus/capture ${CMAKE_SOURCE_DIR}/core
  REPLAY_LIBS tessera
  LIBS m)

# glxgears, unmodified, captured under Xvfb by `tessera exec`.
if(TARGET tessera_faker_gl)
  add_test(NAME capture_glxgears_under_xvfb_replays_bit_identically_through_render_pack_wall_replicate
           COMMAND bash ${CAPTURE_TEST_DIR}/glxgears.sh $<TARGET_FILE:tessera_cli> ${CAPTURE_TEST_DIR}
                   ${CAPTURE_OUT}/glxgears)
  set_tests_properties(capture_glxgears_under_xvfb_replays_bit_identically_through_render_pack_wall_replicate
                       PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 120 ENVIRONMENT "FAKER_PRELOAD=${FAKER_PRELOAD}")
endif()

# piglit's GL 1.0-2.1 tests captured and replayed (issue 27, item 7;
# tests/piglit/capture_sweep.py, docs/conformance.md): each test of
# tests/piglit/choose.py's list that passes natively runs through
# `capture ! render` and must pass there; its capture replays into render
# alone with 0 differing answers and at least one glReadPixels reply.
# Parts in parallel, each on its own Xvfb (-displayfd: the server picks a
# free display, so no fixed display to lock); plain build only, as the
# other piglit parts (their CI budget: 8 minutes on two cores in all).
if(NOT TESSERA_SANITIZE AND TARGET tessera_faker_gl)
  find_program(TESSERA_PYTHON3 python3 PATHS /usr/bin NO_DEFAULT_PATH)
  set(PIGLIT_CAPTURE_PARTS 2)
  math(EXPR last "${PIGLIT_CAPTURE_PARTS} - 1")
  foreach(part RANGE ${last})
    set(name piglit_gl_1_0_to_2_1_tests_captured_replay_with_0_differing_answers_and_read_pixels_part_${part})
    add_test(NAME ${name}
             COMMAND sh -c "[ -d /usr/lib/x86_64-linux-gnu/piglit/bin ] || { echo 'SKIP: piglit is not installed (scripts/setup-debian installs it)'; exit 77; }; exec \"$0\" \"$@\""
                     ${TESSERA_PYTHON3} ${CMAKE_CURRENT_SOURCE_DIR}/piglit/capture_sweep.py
                     $<TARGET_FILE:tessera_cli> ${CMAKE_BINARY_DIR}/test-out/piglit-capture/part${part}
                     --shard ${part}/${PIGLIT_CAPTURE_PARTS})
    set_tests_properties(${name} PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 900 LABELS piglit)
  endforeach()
endif()

# Sanitizer builds: OSMesa/LLVM keep process-lifetime allocations
# (tests/lsan.supp); tessera's own are still checked.
if(TESSERA_SANITIZE)
  set_property(TEST
    capture_replay_through_render_every_frame_bit_identical
    capture_replay_as_graph_app_pack_wall_2x2_replicate_every_frame_bit_identical
    capture_replay_frames_ranges_and_loops_bit_identical
    capture_replay_info_counts_equal_a_print_trace_of_the_run
    capture_replay_print_floats_hex_exact_and_equal_to_the_g_trace
    capture_answers_from_a_server_replay_with_no_server
    capture_bad_files_refused_in_one_line_naming_file_and_offset
    APPEND PROPERTY ENVIRONMENT
    "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp:print_suppressions=0:use_tls=0")
endif()
