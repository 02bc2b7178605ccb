# tests/binaryswap.cmake — sort-last compositing (issue 11): the examples'
# --part K/N shares, the binaryswap SPU against a real display node, the
# sort-last graphs under `tessera run`, and their mistakes as one clear
# line. Every accuracy test compares every frame with the single-process
# native render of the whole scene (0 differing pixels). Small windows;
# the full peer-count sweep runs in the plain build only.
get_property(BINARYSWAP_TESTS_BEFORE DIRECTORY PROPERTY TESTS)
set(BINARYSWAP_DIR ${CMAKE_CURRENT_SOURCE_DIR}/binaryswap)
set(BINARYSWAP_OUT ${CMAKE_BINARY_DIR}/test-out/binaryswap)
set(BINARYSWAP_EXPECT ${CMAKE_CURRENT_SOURCE_DIR}/render/expect.sh)

foreach(app spheres isosurface)
  add_test(NAME binaryswap_${app}_part_out_of_range_is_a_clear_error
    COMMAND ${BINARYSWAP_EXPECT} 2 "" "^${app}: bad --part \\(expected K/N"
            $<TARGET_FILE:${app}-native> --frames 1 --size 32x32 --part 2/2 --out "")
  add_test(NAME binaryswap_${app}_parts_each_draw_less_than_the_whole
    COMMAND ${BINARYSWAP_DIR}/parts.sh ${CMAKE_BINARY_DIR}/bin ${app} ${BINARYSWAP_OUT}/parts-${app})
endforeach()
add_test(NAME binaryswap_spheres_help_lists_part_and_overlap
  COMMAND ${BINARYSWAP_EXPECT} 0 "--overlap" "" $<TARGET_FILE:spheres-native> --help)
set_tests_properties(binaryswap_spheres_help_lists_part_and_overlap PROPERTIES
  PASS_REGULAR_EXPRESSION "--part K/N")

# Accuracy: both forms, every frame against the native whole scene, 0
# differing pixels (tests/binaryswap/exact.sh). The isosurface is split
# into N shares of its triangles; `overlap` is spheres --overlap, whose
# interpenetrating spheres are cut by the share borders. The full sweep of
# peer counts in the plain build; a sanitizer build runs N = 1 and 3.
set(BINARYSWAP_SH ${BINARYSWAP_DIR}/exact.sh)
if(TESSERA_SANITIZE)
  set(BINARYSWAP_COUNTS 1 3)
else()
  set(BINARYSWAP_COUNTS 1 2 3 4 5 7 8)
endif()
foreach(n ${BINARYSWAP_COUNTS})
  foreach(form insitu servers)
    add_test(NAME binaryswap_${form}_depth_exact_n${n}
      COMMAND ${BINARYSWAP_SH} ${form} ${CMAKE_BINARY_DIR}/bin ${BINARYSWAP_OUT}/${form}-iso-${n} ${n} isosurface)
    add_test(NAME binaryswap_${form}_interpenetrating_depth_exact_n${n}
      COMMAND ${BINARYSWAP_SH} ${form} ${CMAKE_BINARY_DIR}/bin ${BINARYSWAP_OUT}/${form}-overlap-${n} ${n} overlap)
  endforeach()
endforeach()
# Every strategy of the SPU (spus/binaryswap/strategies) gives the same
# exact frames; and a lossless codec other than the default.
if(TESSERA_SANITIZE)
  set(BINARYSWAP_STRATEGY_CASES "insitu|3|bswap|strategy: bswap")
else()
  set(BINARYSWAP_STRATEGY_CASES
    "insitu|5|bswap|strategy: bswap" "insitu|8|bswap|strategy: bswap" "servers|7|bswap|strategy: bswap"
    "insitu|5|direct|strategy: direct" "servers|4|direct|strategy: direct"
    "insitu|7|radixk3|strategy: radixk-3" "insitu|4|gather_erle|strategy: gather, codec: erle")
endif()
foreach(case ${BINARYSWAP_STRATEGY_CASES})
  string(REPLACE "|" ";" case "${case}")
  list(GET case 0 form)
  list(GET case 1 n)
  list(GET case 2 name)
  list(GET case 3 options)
  add_test(NAME binaryswap_${form}_${name}_depth_exact_n${n}
    COMMAND ${BINARYSWAP_SH} ${form} ${CMAKE_BINARY_DIR}/bin ${BINARYSWAP_OUT}/${form}-${name}-${n} ${n} overlap - "${options}")
endforeach()
# A peer that draws nothing sends the image header alone and the frame is
# still exact; when no peer draws anything the display shows the
# background the applications cleared to, nothing else.
add_test(NAME binaryswap_blank_peer_sends_header_only_exact
  COMMAND ${BINARYSWAP_SH} insitu ${CMAKE_BINARY_DIR}/bin ${BINARYSWAP_OUT}/blank 2 overlap blank)
add_test(NAME binaryswap_display_draws_nothing
  COMMAND ${BINARYSWAP_SH} servers ${CMAKE_BINARY_DIR}/bin ${BINARYSWAP_OUT}/nothing 3 overlap nothing)

# `tessera check` and the compositing groups (core/graph/groups.c): one
# line with file:line:column naming the node at fault, exit status 2.
set(BINARYSWAP_GRAPHS ${BINARYSWAP_DIR}/graphs)
foreach(case
    "missing_peer|missing_peer.yaml:8:3: node 'p0': peers names peer 'p3', but no node has that name \\(a missing peer\\)"
    "unlisted_peer|unlisted_peer.yaml:8:3: node 'p0': peers misses peer 'p2', which also sends to display 'display'"
    "two_displays|two_displays.yaml:8:3: node 'p0': peers names 'p2', which sends to display 'display2': one group has one display node"
    "window_sizes|window_sizes.yaml:9:3: node 'p1': its binaryswap draws 32x48, but the group's window is 64x48"
    "listed_twice|listed_twice.yaml:8:3: node 'p0': peers lists peer 'p1' twice"
    "mixed|mixed.yaml:7:3: node 'p0': it and 'app1' are peers of display 'display', but one is a server and the other an application")
  string(REPLACE "|" ";" case "${case}")
  list(GET case 0 name)
  list(GET case 1 message)
  add_test(NAME binaryswap_check_rejects_${name}
    COMMAND ${BINARYSWAP_EXPECT} 2 "" "^${BINARYSWAP_GRAPHS}/${message}"
            $<TARGET_FILE:tessera_cli> check ${BINARYSWAP_GRAPHS}/${name}.yaml)
endforeach()
add_test(NAME binaryswap_check_accepts_a_group_listed_in_rank_order
  COMMAND ${BINARYSWAP_EXPECT} 0 "^ok: 7 nodes" "" $<TARGET_FILE:tessera_cli> check ${BINARYSWAP_GRAPHS}/listed_ok.yaml)
foreach(g sortlast sortlast_servers sortlast_alpha)
  add_test(NAME binaryswap_example_graph_${g}_checks
    COMMAND ${BINARYSWAP_EXPECT} 0 "^ok: " "" $<TARGET_FILE:tessera_cli> check ${CMAKE_SOURCE_DIR}/examples/graphs/${g}.yaml)
endforeach()

# Faults: a peer killed (kill -9) or stopped (SIGSTOP: it never sends
# again) mid-run; rank 0 names it, everyone ends non-zero, nothing is left.
add_test(NAME binaryswap_peer_killed_mid_run_ends_group_naming_it
  COMMAND ${BINARYSWAP_DIR}/faults.sh kill ${CMAKE_BINARY_DIR}/bin ${BINARYSWAP_OUT}/fault-kill)
add_test(NAME binaryswap_peer_that_never_sends_times_out_naming_it
  COMMAND ${BINARYSWAP_DIR}/faults.sh stop ${CMAKE_BINARY_DIR}/bin ${BINARYSWAP_OUT}/fault-stop)
add_test(NAME binaryswap_peer_that_never_connects_names_it
  COMMAND ${BINARYSWAP_DIR}/faults.sh absent ${CMAKE_BINARY_DIR}/bin ${BINARYSWAP_OUT}/fault-absent)
add_test(NAME binaryswap_peer_window_size_differs_names_it
  COMMAND ${BINARYSWAP_DIR}/faults.sh sizes ${CMAKE_BINARY_DIR}/bin ${BINARYSWAP_OUT}/fault-sizes)

# The region of interest from the geometry's boxes (issue 11, item 2;
# spus/binaryswap/roi.c, tests/binaryswap/roi.sh). behind_viewer: one
# triangle per peer, straddling the eye plane, behind the viewer, cut by
# the near or far plane; built twice like the examples. Both exact.
add_executable(behind_viewer-native ${BINARYSWAP_DIR}/behind_viewer_driver.c ${CMAKE_SOURCE_DIR}/examples/common/exapp.c)
target_compile_definitions(behind_viewer-native PRIVATE EXAPP_NATIVE)
target_include_directories(behind_viewer-native PRIVATE ${CMAKE_SOURCE_DIR}/examples)
target_link_libraries(behind_viewer-native PRIVATE PkgConfig::OSMESA tessera m)
add_executable(behind_viewer ${BINARYSWAP_DIR}/behind_viewer_driver.c ${CMAKE_SOURCE_DIR}/examples/common/exapp.c)
target_include_directories(behind_viewer PRIVATE ${CMAKE_SOURCE_DIR}/examples)
target_link_libraries(behind_viewer PRIVATE tessera_gl tessera m)
add_test(NAME binaryswap_bounds_behind_viewer
  COMMAND ${BINARYSWAP_DIR}/roi.sh insitu ${CMAKE_BINARY_DIR}/bin ${BINARYSWAP_OUT}/roi-behind 8 behind_viewer behind)
add_test(NAME binaryswap_roi_bounds_info_is_honoured
  COMMAND ${BINARYSWAP_DIR}/roi.sh insitu ${CMAKE_BINARY_DIR}/bin ${BINARYSWAP_OUT}/roi-bounds 2 behind_viewer bounds --bounds)
add_test(NAME binaryswap_roi_reads_only_the_box
  COMMAND ${BINARYSWAP_DIR}/roi.sh servers ${CMAKE_BINARY_DIR}/bin ${BINARYSWAP_OUT}/roi-box 3 isosurface box)

get_property(BINARYSWAP_TESTS_AFTER DIRECTORY PROPERTY TESTS)
if(BINARYSWAP_TESTS_BEFORE)
  list(REMOVE_ITEM BINARYSWAP_TESTS_AFTER ${BINARYSWAP_TESTS_BEFORE})
endif()
set(BINARYSWAP_ENV "LP_NUM_THREADS=0")
if(TESSERA_SANITIZE)
  list(APPEND BINARYSWAP_ENV "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp:print_suppressions=0:use_tls=0")
endif()
set_tests_properties(${BINARYSWAP_TESTS_AFTER} PROPERTIES
  TIMEOUT 120 LABELS binaryswap FAIL_REGULAR_EXPRESSION "FAIL:" ENVIRONMENT "${BINARYSWAP_ENV}")

# Alpha mode (issue 11, items 4 and 8): N peers each draw a convex,
# depth-sorted share of a translucent scene (spheres --alpha); every frame
# equals the serial back-to-front blend of the same layers, computed by
# alpha_blend from each share rendered natively: 0 differing pixels. The
# strategies that blend each pixel in one place agree; those that regroup
# the blend are refused (tsr_composite_schedule_keeps_order). Own block: its
# tests take the common properties below.
get_property(ALPHA_TESTS_BEFORE DIRECTORY PROPERTY TESTS)
add_executable(alpha_blend ${BINARYSWAP_DIR}/alpha_blend_check.c)
target_link_libraries(alpha_blend PRIVATE tessera m)
set(ALPHA_SH ${BINARYSWAP_DIR}/alpha.sh)
set(ALPHA_ARGS ${CMAKE_BINARY_DIR}/bin $<TARGET_FILE:alpha_blend>)
if(TESSERA_SANITIZE)
  set(ALPHA_COUNTS 1 3)
else()
  set(ALPHA_COUNTS 1 2 3 4 5 7 8)
endif()
foreach(n ${ALPHA_COUNTS})
  add_test(NAME binaryswap_alpha_matches_serial_blend_n${n}
    COMMAND ${ALPHA_SH} insitu ${ALPHA_ARGS} ${BINARYSWAP_OUT}/alpha-${n} ${n})
endforeach()
# Alpha mode reads only the box of what each peer drew (roi.c), not the
# whole window: the frames stay the serial blend, and every peer's logged
# region of every frame is smaller than the 96x72 window.
add_test(NAME binaryswap_alpha_reads_only_the_box
  COMMAND sh -c "TESSERA_LOG=debug \"$0\" insitu \"$1\" \"$2\" \"$3\" 3 || exit 1; \
    n=$(grep -c 'alpha region' \"$3/run.err\"); full=$(grep -c 'alpha region \\[0, 0, 96, 72\\]' \"$3/run.err\"); \
    echo \"alpha regions: $n, whole-window: $full\"; [ $n -eq 6 ] && [ $full -eq 0 ]"
    ${ALPHA_SH} ${ALPHA_ARGS} ${BINARYSWAP_OUT}/alpha-box)
if(NOT TESSERA_SANITIZE)
  foreach(case
      "gather|4|strategy: gather" "direct|5|strategy: direct" "radixk3|3|strategy: radixk-3"
      "bswap|2|strategy: bswap" "servers_direct|3|strategy: direct")
    string(REPLACE "|" ";" case "${case}")
    list(GET case 0 name)
    list(GET case 1 n)
    list(GET case 2 options)
    set(form insitu)
    if(name MATCHES "^servers")
      set(form servers)
    endif()
    add_test(NAME binaryswap_alpha_${name}_matches_serial_blend_n${n}
      COMMAND ${ALPHA_SH} ${form} ${ALPHA_ARGS} ${BINARYSWAP_OUT}/alpha-${name}-${n} ${n} "${options}")
  endforeach()
  # float colour in depth mode selects pixels: the native render, exactly
  add_test(NAME binaryswap_insitu_float_colour_depth_exact_n3
    COMMAND ${BINARYSWAP_SH} insitu ${CMAKE_BINARY_DIR}/bin ${BINARYSWAP_OUT}/insitu-float-3 3 overlap - "colour: rgba32f")
  add_test(NAME binaryswap_alpha_float_colour_matches_serial_float_blend_n4
    COMMAND ${ALPHA_SH} insitu ${ALPHA_ARGS} ${BINARYSWAP_OUT}/alpha-float-4 4 "colour: rgba32f")
endif()
add_test(NAME binaryswap_alpha_background_added_once
  COMMAND ${ALPHA_SH} insitu ${ALPHA_ARGS} ${BINARYSWAP_OUT}/alpha-bg-3 3 "" background)
add_test(NAME binaryswap_alpha_view_order_from_graph
  COMMAND ${ALPHA_SH} insitu ${ALPHA_ARGS} ${BINARYSWAP_OUT}/alpha-reversed-3 3 "" reversed)
add_test(NAME binaryswap_alpha_view_order_from_boxes
  COMMAND ${ALPHA_SH} insitu ${ALPHA_ARGS} ${BINARYSWAP_OUT}/alpha-boxes-4 4 "" boxes)
add_test(NAME binaryswap_alpha_regrouping_strategy_refused
  COMMAND ${ALPHA_SH} insitu ${ALPHA_ARGS} ${BINARYSWAP_OUT}/alpha-refused-4 4 "strategy: bswap" refused)
add_test(NAME binaryswap_alpha_options_in_binaryswap_help
  COMMAND ${BINARYSWAP_EXPECT} 0 "view_order" "" $<TARGET_FILE:tessera_cli> spus binaryswap)
set_tests_properties(binaryswap_alpha_options_in_binaryswap_help PROPERTIES
  PASS_REGULAR_EXPRESSION "rgba32f")
add_test(NAME binaryswap_alpha_spheres_help_lists_alpha
  COMMAND ${BINARYSWAP_EXPECT} 0 "--alpha A" "" $<TARGET_FILE:spheres-native> --help)
set_tests_properties(binaryswap_alpha_spheres_help_lists_alpha PROPERTIES
  PASS_REGULAR_EXPRESSION "--background R,G,B")
add_test(NAME binaryswap_alpha_spheres_bad_alpha_is_a_clear_error
  COMMAND ${BINARYSWAP_EXPECT} 2 "" "^spheres: bad --alpha \\(expected 0 < A <= 1\\): 1.5"
          $<TARGET_FILE:spheres-native> --alpha 1.5 --frames 1 --size 32x32 --out "")
foreach(case
    "twice|mode=alpha view_order=0,0|view_order lists rank 0 twice \\(entries 1 and 2\\)"
    "short|mode=alpha view_order=1|view_order lists 1 ranks, the group has 2"
    "not_a_rank|mode=alpha view_order=0,x|view_order entry 2 is 'x', not a rank 0..1"
    "depth_mode|view_order=1,0|view_order is for mode=alpha"
    "colour|colour=rgb565|colour=rgb565: expected rgba8 or rgba32f"
    "float_yuv|colour=rgba32f codec=yuv420|codec=yuv420 is for RGBA8 colour, not colour=rgba32f"
    "box_size|mode=alpha box=1,2,3|box has 3 numbers, not 6 \\(xmin, ymin, zmin, xmax, ymax, zmax\\)"
    "box_inverted|mode=alpha box=0,0,1,1,1,0|box: its minimum z \\(1\\) is above its maximum \\(0\\)")
  string(REPLACE "|" ";" case "${case}")
  list(GET case 0 name)
  list(GET case 1 options)
  list(GET case 2 message)
  add_test(NAME binaryswap_alpha_bad_${name}_is_one_clear_line
    COMMAND ${BINARYSWAP_EXPECT} 1 "" "^spheres: binaryswap#1: ${message}"
            $<TARGET_FILE:spheres> --alpha 0.5 --frames 1 --size 32x32
            --chain "binaryswap display=unix:${BINARYSWAP_OUT}/none.sock ${options} exchange=unix:${BINARYSWAP_OUT}/a,unix:${BINARYSWAP_OUT}/b")
endforeach()
get_property(ALPHA_TESTS DIRECTORY PROPERTY TESTS)
if(ALPHA_TESTS_BEFORE)
  list(REMOVE_ITEM ALPHA_TESTS ${ALPHA_TESTS_BEFORE})
endif()
set_tests_properties(${ALPHA_TESTS} PROPERTIES
  TIMEOUT 120 LABELS binaryswap FAIL_REGULAR_EXPRESSION "FAIL:" ENVIRONMENT "${BINARYSWAP_ENV}")
