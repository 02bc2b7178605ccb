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

# --- the other decoders (issue 10, item 12) ----------------------------------
# One function per target NAME (tests/fuzz/fuzz_NAME.c, corpus in
# tests/fuzz/corpus-NAME/):
#  * fuzz_NAME_replay + ctest fuzz_NAME_corpus_replay (every build, any
#    compiler; a sanitizer run under -DTESSERA_SANITIZE=ON): replay.c over
#    the corpus through the target's fuzz_target_explain (fuzz_target.h);
#  * fuzz_NAME (only -DTESSERA_FUZZ=ON, clang) + ctest fuzz_NAME_runs_corpus:
#    the libFuzzer target. SOURCES (the code under test) are compiled into
#    it with the fuzzer instrumentation, as fuzz_unpack does, so coverage
#    measures the decoder; LIBS are linked as they are.
# SOURCES are compiled into the replay too (several are internal to their
# library), so both run the same code. Code the replay can take from a
# library instead goes in FUZZ_SOURCES (the libFuzzer target only) and
# that library in REPLAY_LIBS.
function(tsr_add_fuzz_target name)
  cmake_parse_arguments(F "" "" "SOURCES;FUZZ_SOURCES;LIBS;REPLAY_LIBS;INCLUDES;DEFINES" ${ARGN})
  set(harness ${TSR_FUZZ_DIR}/fuzz_${name}.c)
  set(corpus ${TSR_FUZZ_DIR}/corpus-${name})
  set(includes ${TSR_FUZZ_DIR} ${CMAKE_SOURCE_DIR}/include ${TESSERA_GEN_DIR}/include ${TESSERA_GEN_DIR}/src
    ${F_INCLUDES})
  add_executable(fuzz_${name}_replay ${TSR_FUZZ_DIR}/replay.c ${harness} ${F_SOURCES})
  add_dependencies(fuzz_${name}_replay tessera_generated)
  target_include_directories(fuzz_${name}_replay PRIVATE ${includes})
  target_compile_definitions(fuzz_${name}_replay PRIVATE TSR_FUZZ_TARGET ${F_DEFINES})
  target_link_libraries(fuzz_${name}_replay PRIVATE ${F_REPLAY_LIBS} ${F_LIBS})
  # Mesa's own leaks (render's OSMesa) are suppressed, ours are checked.
  set(env "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp:print_suppressions=0:use_tls=0")
  add_test(NAME fuzz_${name}_corpus_replay COMMAND fuzz_${name}_replay ${corpus})
  set_tests_properties(fuzz_${name}_corpus_replay PROPERTIES TIMEOUT 120 ENVIRONMENT "${env}")
  if(TESSERA_FUZZ)
    add_executable(fuzz_${name} ${harness} ${F_SOURCES} ${F_FUZZ_SOURCES})
    add_dependencies(fuzz_${name} tessera_generated)
    target_include_directories(fuzz_${name} PRIVATE ${includes})
    target_compile_definitions(fuzz_${name} PRIVATE ${F_DEFINES})
    target_compile_options(fuzz_${name} PRIVATE -fsanitize=fuzzer,address,undefined
      -fno-sanitize-recover=all -fno-omit-frame-pointer)
    target_link_options(fuzz_${name} PRIVATE -fsanitize=fuzzer,address,undefined)
    target_link_libraries(fuzz_${name} PRIVATE ${F_LIBS})
    add_test(NAME fuzz_${name}_runs_corpus COMMAND fuzz_${name} -runs=0 ${corpus})
    set_tests_properties(fuzz_${name}_runs_corpus PROPERTIES TIMEOUT 120 ENVIRONMENT "${env}")
  endif()
endfunction()

# The chain text parser, the option parser and the SPU loader (internal
# to libtessera); the loader finds the real SPU plugins of this build.
set(tsr_fuzz_chain_sources
  ${CMAKE_SOURCE_DIR}/core/spu/chain.c ${CMAKE_SOURCE_DIR}/core/spu/options.c
  ${CMAKE_SOURCE_DIR}/core/spu/spu_loader.c ${CMAKE_SOURCE_DIR}/core/spu/native.c ${CMAKE_SOURCE_DIR}/core/util/names.c
  ${CMAKE_SOURCE_DIR}/core/util/error.c ${CMAKE_SOURCE_DIR}/core/util/log.c
  ${TESSERA_GEN_DIR}/src/dispatch_gen.c)
set(tsr_fuzz_chain_defines TESSERA_BUILD_SPU_DIR="${TESSERA_SPU_BUILD_DIR}" TESSERA_INSTALL_SPU_DIR="")

tsr_add_fuzz_target(ctl
  SOURCES ${CMAKE_SOURCE_DIR}/mothership/ctl.c ${tsr_fuzz_chain_sources}
  INCLUDES ${CMAKE_SOURCE_DIR}/mothership ${CMAKE_SOURCE_DIR}/core/spu
  DEFINES ${tsr_fuzz_chain_defines}
  LIBS Threads::Threads ${CMAKE_DL_LIBS} m)

# The client's reply parser: the packer's reply decoding (core/wire,
# generated pack_gen.c), driven by the generated wire-test calls.
# fuzz_reply_seeds OUTDIR rewrites corpus-reply/ok-* with real replies.
set(tsr_fuzz_wire_sources
  ${CMAKE_SOURCE_DIR}/core/wire/pack.c ${CMAKE_SOURCE_DIR}/core/wire/pack_map.c ${CMAKE_SOURCE_DIR}/core/wire/pack_mirror.c
  ${CMAKE_SOURCE_DIR}/core/wire/pack_element.c ${CMAKE_SOURCE_DIR}/core/wire/pack_draws.c
  ${CMAKE_SOURCE_DIR}/core/wire/pack_buffer_get.c
  ${CMAKE_SOURCE_DIR}/core/wire/pixel.c ${CMAKE_SOURCE_DIR}/core/wire/select.c ${CMAKE_SOURCE_DIR}/core/wire/sized_get.c
  ${CMAKE_SOURCE_DIR}/core/wire/dlist.c ${CMAKE_SOURCE_DIR}/core/wire/unpack.c
  ${CMAKE_SOURCE_DIR}/core/util/map.c ${CMAKE_SOURCE_DIR}/core/util/error.c
  ${CMAKE_SOURCE_DIR}/core/util/log.c ${TESSERA_GEN_DIR}/src/pack_gen.c
  ${TESSERA_GEN_DIR}/src/unpack_gen.c ${TESSERA_GEN_DIR}/src/wire_tables_gen.c
  ${TESSERA_GEN_DIR}/src/dispatch_gen.c)
tsr_add_fuzz_target(reply
  SOURCES ${TESSERA_GEN_TEST_SOURCES}
  FUZZ_SOURCES ${tsr_fuzz_wire_sources}
  INCLUDES ${CMAKE_SOURCE_DIR}/core
  REPLAY_LIBS tessera
  LIBS m)
add_executable(fuzz_reply_seeds ${TSR_FUZZ_DIR}/fuzz_reply.c ${TESSERA_GEN_TEST_SOURCES})
add_dependencies(fuzz_reply_seeds tessera_generated)
target_compile_definitions(fuzz_reply_seeds PRIVATE TSR_FUZZ_SEEDS)
target_include_directories(fuzz_reply_seeds PRIVATE ${TSR_FUZZ_DIR} ${TESSERA_GEN_DIR}/src)
target_link_libraries(fuzz_reply_seeds PRIVATE tessera)

# The graph YAML loader (core/graph) with the SPU checks on.
tsr_add_fuzz_target(graph
  FUZZ_SOURCES ${CMAKE_SOURCE_DIR}/core/graph/graph.c ${CMAKE_SOURCE_DIR}/core/graph/graph_events.c
    ${CMAKE_SOURCE_DIR}/core/graph/graph_keys.c ${CMAKE_SOURCE_DIR}/core/graph/graph_rules.c
    ${CMAKE_SOURCE_DIR}/core/graph/groups.c ${CMAKE_SOURCE_DIR}/netlib/address.c ${tsr_fuzz_chain_sources}
  INCLUDES ${CMAKE_SOURCE_DIR}/core/spu
  DEFINES ${tsr_fuzz_chain_defines}
  REPLAY_LIBS tessera_graph
  LIBS PkgConfig::YAML Threads::Threads ${CMAKE_DL_LIBS} m)

# The chain text and option parsers, links checked against the real SPUs.
tsr_add_fuzz_target(chain
  SOURCES ${tsr_fuzz_chain_sources}
  INCLUDES ${CMAKE_SOURCE_DIR}/core/spu
  DEFINES ${tsr_fuzz_chain_defines}
  LIBS Threads::Threads ${CMAKE_DL_LIBS} m)

# The PNG reader of imgdiff (core/image). fuzz_png_seeds OUTDIR writes the
# ok-* seeds with the project's writer.
tsr_add_fuzz_target(png
  FUZZ_SOURCES ${CMAKE_SOURCE_DIR}/core/image/image.c ${CMAKE_SOURCE_DIR}/core/util/error.c
  REPLAY_LIBS tessera
  LIBS PkgConfig::PNG m)
add_executable(fuzz_png_seeds ${TSR_FUZZ_DIR}/fuzz_png.c)
target_compile_definitions(fuzz_png_seeds PRIVATE TSR_FUZZ_SEEDS)
target_include_directories(fuzz_png_seeds PRIVATE ${TSR_FUZZ_DIR})
target_link_libraries(fuzz_png_seeds PRIVATE tessera)

# The tessera extension commands into the render SPU (its sources compiled
# in and registered, so coverage measures its handlers). fuzz_ext_seeds
# OUTDIR writes the ok-* seeds with the real packer.
# The render plugin's sources (spus/render/CMakeLists.txt) but its class
# (plugin.c), compiled in: fuzz_render registers its own class with them.
set(tsr_fuzz_render_impl_sources)
foreach(tsr_file render contexts buffers multisample appfbo scissor textures pixels frame pages budget drawpixels xwindow)
  list(APPEND tsr_fuzz_render_impl_sources ${CMAKE_SOURCE_DIR}/spus/render/${tsr_file}.c)
endforeach()
set(tsr_fuzz_render_sources ${CMAKE_SOURCE_DIR}/spus/render/plugin.c ${tsr_fuzz_render_impl_sources})
tsr_add_fuzz_target(ext
  SOURCES ${tsr_fuzz_render_sources}
  INCLUDES ${CMAKE_SOURCE_DIR}/spus/render
  LIBS tessera PkgConfig::RENDER_X11 ${CMAKE_DL_LIBS} m)
add_executable(fuzz_ext_seeds ${TSR_FUZZ_DIR}/fuzz_ext.c ${tsr_fuzz_render_sources})
add_dependencies(fuzz_ext_seeds tessera_generated)
target_compile_definitions(fuzz_ext_seeds PRIVATE TSR_FUZZ_SEEDS)
target_include_directories(fuzz_ext_seeds PRIVATE ${TSR_FUZZ_DIR} ${CMAKE_SOURCE_DIR}/spus/render)
target_link_libraries(fuzz_ext_seeds PRIVATE tessera PkgConfig::RENDER_X11 ${CMAKE_DL_LIBS} m)

# --- Command buffers into render (tests/fuzz/fuzz_render.c) -------------------
# Decoded wire buffers run into a real OSMesa render SPU with per-client
# budgets on (issue 10, item 12). fuzz_render_seeds writes the seeds with
# the real packer; fuzz_render_replay replays tests/fuzz/corpus-render in
# every build; under TESSERA_FUZZ, fuzz_render is the libFuzzer target, with
# the unpacker and render.c compiled into it with the fuzzer's coverage.
set(tsr_fuzz_render_corpus ${TSR_FUZZ_DIR}/corpus-render)
foreach(mode replay seeds)
  add_executable(fuzz_render_${mode} ${TSR_FUZZ_DIR}/fuzz_render.c ${tsr_fuzz_render_impl_sources})
  add_dependencies(fuzz_render_${mode} tessera_generated)
  string(TOUPPER ${mode} tsr_mode)
  target_compile_definitions(fuzz_render_${mode} PRIVATE FUZZ_RENDER_${tsr_mode})
  target_include_directories(fuzz_render_${mode} PRIVATE ${CMAKE_SOURCE_DIR}/spus/render)
  target_link_libraries(fuzz_render_${mode} PRIVATE tessera PkgConfig::RENDER_X11 ${CMAKE_DL_LIBS} m)
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
    ENVIRONMENT "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp:print_suppressions=0:use_tls=0")
endif()

if(TESSERA_FUZZ)
  add_executable(fuzz_render ${TSR_FUZZ_DIR}/fuzz_render.c
    ${tsr_fuzz_render_impl_sources}
    ${CMAKE_SOURCE_DIR}/core/wire/unpack.c ${CMAKE_SOURCE_DIR}/core/wire/pixel.c
    ${TESSERA_GEN_DIR}/src/unpack_gen.c ${TESSERA_GEN_DIR}/src/wire_tables_gen.c)
  add_dependencies(fuzz_render tessera_generated)
  target_compile_definitions(fuzz_render PRIVATE FUZZ_RENDER_FUZZER)
  target_include_directories(fuzz_render PRIVATE ${CMAKE_SOURCE_DIR}/spus/render ${CMAKE_SOURCE_DIR}/core
    ${CMAKE_SOURCE_DIR}/include ${TESSERA_GEN_DIR}/include ${TESSERA_GEN_DIR}/src)
  target_compile_options(fuzz_render PRIVATE -fsanitize=fuzzer,address,undefined
    -fno-sanitize-recover=all -fno-omit-frame-pointer)
  target_link_options(fuzz_render PRIVATE -fsanitize=fuzzer,address,undefined)
  target_link_libraries(fuzz_render PRIVATE tessera PkgConfig::RENDER_X11 ${CMAKE_DL_LIBS} m)
  add_test(NAME fuzz_render_runs_corpus COMMAND fuzz_render -runs=0 ${tsr_fuzz_render_corpus})
  # OSMesa keeps process-lifetime allocations LeakSanitizer would report.
  set_tests_properties(fuzz_render_runs_corpus PROPERTIES TIMEOUT 300
    ENVIRONMENT "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp:print_suppressions=0:use_tls=0")
endif()

# ---- netlib frames and handshake (tests/fuzz/fuzz_net.c) -------------------
#  * fuzz_net_corpus_replay (every build): runs each seed of
#    tests/fuzz/corpus_net through real netlib connections.
#  * fuzz_net (only -DTESSERA_FUZZ=ON, clang): the libFuzzer target.
# Both compile netlib's sources into the program (its internal encoders make
# the seeds and the correct handshakes; the fuzzer's coverage is netlib's).
set(tsr_fuzz_net_sources ${TSR_FUZZ_DIR}/fuzz_net.c)
foreach(f address.c auth.c conn.c conn_listen.c conn_send.c direct.c frame.c inproc.c loop.c shm.c socket.c
    socket_admit.c socket_handshake.c socket_read.c stream.c)
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
