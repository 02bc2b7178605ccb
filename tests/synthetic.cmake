# tests/synthetic.cmake — binaryswap's synthetic layers (the sort-last
# benchmarks' input, spus/binaryswap/synthetic.h) and its stats lines: a
# real `tessera run` of in-situ peers whose every frame must equal the
# composite of the generated layers computed in the test, with exact
# coverage; and a bad synthetic= value refused at init in one line, before
# any peer is waited for. No timing is checked.
add_executable(synthetic_check ${CMAKE_CURRENT_SOURCE_DIR}/binaryswap/synthetic_check.c)
target_link_libraries(synthetic_check PRIVATE tessera_composite_synthetic tessera m)
set(SYNTHETIC_OUT ${CMAKE_BINARY_DIR}/test-out/synthetic)
add_test(NAME binaryswap_synthetic_full_composite_exact_n3
  COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/binaryswap/synthetic.sh ${CMAKE_BINARY_DIR}/bin ${SYNTHETIC_OUT}/full3 3 full)
add_test(NAME binaryswap_synthetic_ellipse_composite_exact_n4
  COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/binaryswap/synthetic.sh ${CMAKE_BINARY_DIR}/bin ${SYNTHETIC_OUT}/ellipse4 4 ellipse)
# Large enough that the display draws some partial pieces in several bands
# (spus/binaryswap/bands.h: 14 DrawPixels for 8 pieces), with scissored
# clears beside them.
add_test(NAME binaryswap_synthetic_ellipse_banded_composite_exact_n4
  COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/binaryswap/synthetic.sh ${CMAKE_BINARY_DIR}/bin ${SYNTHETIC_OUT}/ellipse4-banded 4 ellipse 1024x768)
# Eight ellipses leave little background: strips folded from eight pieces
# go to the display filled with it, not gathered (final_filled).
add_test(NAME binaryswap_synthetic_ellipse_filled_composite_exact_n8
  COMMAND env FILLED=1 ${CMAKE_CURRENT_SOURCE_DIR}/binaryswap/synthetic.sh ${CMAKE_BINARY_DIR}/bin ${SYNTHETIC_OUT}/ellipse8 8 ellipse)
# No peer exists at this display address: a value that waited for peers
# would hang until link_timeout_ms instead of failing.
add_test(NAME binaryswap_synthetic_bogus_refused_at_init
  COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/render/expect.sh 1 ""
          "^spheres: binaryswap#1: synthetic=bogus: expected full, ellipse or off$"
          $<TARGET_FILE:spheres> --frames 1 --size 32x32
          --chain "binaryswap display=unix:${SYNTHETIC_OUT}/nobody synthetic=bogus rank=1 peers=unix:${SYNTHETIC_OUT}/p0,unix:${SYNTHETIC_OUT}/p1")
set_tests_properties(binaryswap_synthetic_full_composite_exact_n3 binaryswap_synthetic_ellipse_composite_exact_n4
  binaryswap_synthetic_ellipse_banded_composite_exact_n4 binaryswap_synthetic_ellipse_filled_composite_exact_n8
  binaryswap_synthetic_bogus_refused_at_init PROPERTIES
  TIMEOUT 60 LABELS binaryswap FAIL_REGULAR_EXPRESSION "FAIL:" ENVIRONMENT "LP_NUM_THREADS=0")
if(TESSERA_SANITIZE)
  set_tests_properties(binaryswap_synthetic_full_composite_exact_n3 binaryswap_synthetic_ellipse_composite_exact_n4
    binaryswap_synthetic_ellipse_banded_composite_exact_n4 binaryswap_synthetic_ellipse_filled_composite_exact_n8
    binaryswap_synthetic_bogus_refused_at_init PROPERTIES
    ENVIRONMENT "LP_NUM_THREADS=0;LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp:print_suppressions=0:use_tls=0")
endif()

# How a partial final piece is drawn on the display (spus/binaryswap/bands.h):
# boxes and clears cover the piece's range exactly once, every active pixel
# in a box.
add_executable(bands_check ${CMAKE_CURRENT_SOURCE_DIR}/binaryswap/bands_test.c
  ${CMAKE_SOURCE_DIR}/spus/binaryswap/bands.c)
target_include_directories(bands_check PRIVATE ${CMAKE_SOURCE_DIR}/spus/binaryswap)
target_link_libraries(bands_check PRIVATE tessera)
add_test(NAME binaryswap_partial_piece_bands_cover_once COMMAND bands_check)
set_tests_properties(binaryswap_partial_piece_bands_cover_once PROPERTIES TIMEOUT 60 LABELS binaryswap)
