# tests/fuzz.cmake — fuzzing the unpacker.
#  * fuzz_corpus_replay (every build, any compiler): runs each file of
#    tests/fuzz/corpus through the fuzz entry point; under
#    -DTESSERA_SANITIZE=ON that is a sanitizer run of the whole corpus.
#  * fuzz_seed_writer: writes the ok-*/bad-* seeds with the real packer.
#  * fuzz_unpack (only -DTESSERA_FUZZ=ON, clang): the libFuzzer target.
set(TSR_FUZZ_DIR ${CMAKE_CURRENT_SOURCE_DIR}/fuzz)

# The harness decodes into the generated recording table (wire_test_gen.c).
add_executable(fuzz_corpus_replay ${TSR_FUZZ_DIR}/replay.c ${TSR_FUZZ_DIR}/fuzz_unpack_one.c
  ${TESSERA_GEN_TEST_SOURCES})
add_dependencies(fuzz_corpus_replay tessera_generated)
target_include_directories(fuzz_corpus_replay PRIVATE ${TSR_FUZZ_DIR} ${CMAKE_SOURCE_DIR}/core
  ${TESSERA_GEN_DIR}/src)
target_link_libraries(fuzz_corpus_replay PRIVATE tessera)
add_test(NAME fuzz_corpus_replay COMMAND fuzz_corpus_replay ${TSR_FUZZ_DIR}/corpus)
set_tests_properties(fuzz_corpus_replay PROPERTIES TIMEOUT 300)

# The seed writer packs each scenario with the real packer and checks every
# seed through the fuzz entry point before writing it (valid streams must
# decode, the malformed ones must be rejected). As a test it writes into the
# build tree; `fuzz_seed_writer tests/fuzz/corpus` refreshes the corpus.
add_executable(fuzz_seed_writer ${TSR_FUZZ_DIR}/seed_writer.c ${TSR_FUZZ_DIR}/fuzz_unpack_one.c
  ${TESSERA_GEN_TEST_SOURCES})
add_dependencies(fuzz_seed_writer tessera_generated)
target_include_directories(fuzz_seed_writer PRIVATE ${TSR_FUZZ_DIR} ${CMAKE_SOURCE_DIR}/core
  ${TESSERA_GEN_DIR}/src)
target_link_libraries(fuzz_seed_writer PRIVATE tessera)
set(tsr_fuzz_seed_out ${CMAKE_CURRENT_BINARY_DIR}/fuzz_seeds)
file(MAKE_DIRECTORY ${tsr_fuzz_seed_out})
add_test(NAME fuzz_seeds_pack_decode_and_malformed_rejected
  COMMAND fuzz_seed_writer ${tsr_fuzz_seed_out})

if(TESSERA_FUZZ)
  if(NOT CMAKE_C_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "TESSERA_FUZZ needs clang (libFuzzer): configure with CC=clang")
  endif()
  # libFuzzer is guided by coverage of the code under test, so the target
  # compiles the unpacker's own sources (runtime + generated decoder, and
  # what they call) with the fuzzer instrumentation; the shared libtessera
  # stays as it is and no global flag is needed. Only these files: coverage
  # then measures the decoder, not the rest of the library.
  set(tsr_fuzz_core_sources
    ${CMAKE_SOURCE_DIR}/core/wire/unpack.c ${CMAKE_SOURCE_DIR}/core/wire/pixel.c
    ${CMAKE_SOURCE_DIR}/core/util/error.c ${CMAKE_SOURCE_DIR}/core/util/log.c
    ${TESSERA_GEN_DIR}/src/unpack_gen.c ${TESSERA_GEN_DIR}/src/wire_tables_gen.c
    ${TESSERA_GEN_DIR}/src/dispatch_gen.c ${TESSERA_GEN_TEST_SOURCES})
  add_executable(fuzz_unpack ${TSR_FUZZ_DIR}/fuzz_unpack.c ${TSR_FUZZ_DIR}/fuzz_unpack_one.c
    ${tsr_fuzz_core_sources})
  add_dependencies(fuzz_unpack tessera_generated)
  target_include_directories(fuzz_unpack PRIVATE ${TSR_FUZZ_DIR} ${CMAKE_SOURCE_DIR}/core
    ${CMAKE_SOURCE_DIR}/include ${TESSERA_GEN_DIR}/include ${TESSERA_GEN_DIR}/src)
  target_compile_options(fuzz_unpack PRIVATE -fsanitize=fuzzer,address,undefined
    -fno-sanitize-recover=all -fno-omit-frame-pointer)
  target_link_options(fuzz_unpack PRIVATE -fsanitize=fuzzer,address,undefined)
  target_link_libraries(fuzz_unpack PRIVATE m)

  # A short run in the suite proves the target starts and survives the
  # corpus (the long run is manual: see tests/fuzz/README.md).
  add_test(NAME fuzz_unpack_runs_corpus
    COMMAND fuzz_unpack -runs=0 ${TSR_FUZZ_DIR}/corpus)
  set_tests_properties(fuzz_unpack_runs_corpus PROPERTIES TIMEOUT 300)
endif()

# --- Command buffers into render (tests/fuzz/fuzz_render.c) -------------------
# Decoded wire buffers run into a real OSMesa render SPU with per-client
# budgets on (issue 10, item 12). fuzz_render_seeds writes the seeds with
# the real packer; fuzz_render_replay replays tests/fuzz/corpus-render in
# every build; under TESSERA_FUZZ, fuzz_render is the libFuzzer target, with
# the unpacker and render.c compiled into it with the fuzzer's coverage.
set(tsr_fuzz_render_corpus ${TSR_FUZZ_DIR}/corpus-render)
foreach(mode replay seeds)
  add_executable(fuzz_render_${mode} ${TSR_FUZZ_DIR}/fuzz_render.c)
  string(TOUPPER ${mode} tsr_mode)
  target_compile_definitions(fuzz_render_${mode} PRIVATE FUZZ_RENDER_${tsr_mode})
  target_link_libraries(fuzz_render_${mode} PRIVATE tessera_render_core tessera)
endforeach()
add_test(NAME fuzz_render_corpus_replay_budgets_on COMMAND fuzz_render_replay ${tsr_fuzz_render_corpus})
set(tsr_fuzz_render_seed_out ${CMAKE_CURRENT_BINARY_DIR}/fuzz_render_seeds)
file(MAKE_DIRECTORY ${tsr_fuzz_render_seed_out})
add_test(NAME fuzz_render_seeds_pack_and_budgets_refuse
  COMMAND fuzz_render_seeds ${tsr_fuzz_render_seed_out})
set_tests_properties(fuzz_render_corpus_replay_budgets_on fuzz_render_seeds_pack_and_budgets_refuse
  PROPERTIES TIMEOUT 300)
if(TESSERA_SANITIZE)
  set_tests_properties(fuzz_render_corpus_replay_budgets_on fuzz_render_seeds_pack_and_budgets_refuse PROPERTIES
    ENVIRONMENT "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp:print_suppressions=0")
endif()

if(TESSERA_FUZZ)
  add_executable(fuzz_render ${TSR_FUZZ_DIR}/fuzz_render.c
    ${CMAKE_SOURCE_DIR}/spus/render/render.c ${CMAKE_SOURCE_DIR}/spus/render/budget.c
    ${CMAKE_SOURCE_DIR}/spus/render/pages.c
    ${CMAKE_SOURCE_DIR}/core/wire/unpack.c ${CMAKE_SOURCE_DIR}/core/wire/pixel.c
    ${TESSERA_GEN_DIR}/src/unpack_gen.c ${TESSERA_GEN_DIR}/src/wire_tables_gen.c)
  add_dependencies(fuzz_render tessera_generated)
  target_compile_definitions(fuzz_render PRIVATE FUZZ_RENDER_FUZZER)
  target_include_directories(fuzz_render PRIVATE ${CMAKE_SOURCE_DIR}/spus/render ${CMAKE_SOURCE_DIR}/core
    ${CMAKE_SOURCE_DIR}/include ${TESSERA_GEN_DIR}/include ${TESSERA_GEN_DIR}/src)
  target_compile_options(fuzz_render PRIVATE -fsanitize=fuzzer,address,undefined
    -fno-sanitize-recover=all -fno-omit-frame-pointer)
  target_link_options(fuzz_render PRIVATE -fsanitize=fuzzer,address,undefined)
  target_link_libraries(fuzz_render PRIVATE tessera ${CMAKE_DL_LIBS} m)
  add_test(NAME fuzz_render_runs_corpus COMMAND fuzz_render -runs=0 ${tsr_fuzz_render_corpus})
  # OSMesa keeps process-lifetime allocations LeakSanitizer would report.
  set_tests_properties(fuzz_render_runs_corpus PROPERTIES TIMEOUT 300
    ENVIRONMENT "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp:print_suppressions=0")
endif()

# ---- netlib frames and handshake (tests/fuzz/fuzz_net.c) -------------------
#  * fuzz_net_corpus_replay (every build): runs each seed of
#    tests/fuzz/corpus_net through real netlib connections.
#  * fuzz_net (only -DTESSERA_FUZZ=ON, clang): the libFuzzer target.
# Both compile netlib's sources into the program (its internal encoders make
# the seeds and the correct handshakes; the fuzzer's coverage is netlib's).
set(tsr_fuzz_net_sources ${TSR_FUZZ_DIR}/fuzz_net.c)
foreach(f address.c auth.c conn.c direct.c frame.c inproc.c loop.c socket.c stream.c)
  list(APPEND tsr_fuzz_net_sources ${CMAKE_SOURCE_DIR}/netlib/${f})
endforeach()
add_executable(fuzz_net_replay ${tsr_fuzz_net_sources})
target_compile_definitions(fuzz_net_replay PRIVATE FUZZ_NET_REPLAY)
target_include_directories(fuzz_net_replay PRIVATE ${CMAKE_SOURCE_DIR}/netlib)
target_link_libraries(fuzz_net_replay PRIVATE tessera PkgConfig::UV PkgConfig::SODIUM Threads::Threads)
add_test(NAME fuzz_net_corpus_replay COMMAND fuzz_net_replay ${TSR_FUZZ_DIR}/corpus_net)
set_tests_properties(fuzz_net_corpus_replay PROPERTIES TIMEOUT 120)

if(TESSERA_FUZZ)
  add_executable(fuzz_net ${tsr_fuzz_net_sources})
  target_include_directories(fuzz_net PRIVATE ${CMAKE_SOURCE_DIR}/netlib)
  target_compile_options(fuzz_net PRIVATE -fsanitize=fuzzer,address,undefined
    -fno-sanitize-recover=all -fno-omit-frame-pointer)
  target_link_options(fuzz_net PRIVATE -fsanitize=fuzzer,address,undefined)
  target_link_libraries(fuzz_net PRIVATE tessera PkgConfig::UV PkgConfig::SODIUM Threads::Threads)
  add_test(NAME fuzz_net_runs_corpus COMMAND fuzz_net -runs=0 ${TSR_FUZZ_DIR}/corpus_net)
  set_tests_properties(fuzz_net_runs_corpus PROPERTIES TIMEOUT 300)
endif()
