# tests/synthetic.cmake — binaryswap's synthetic layers (the sort-last
# benchmarks' input, spus/binaryswap/synthetic.h) and its stats lines: a
# real `tessera run` of in-situ peers whose every frame must equal the
# composite of the generated layers computed in the test, with exact
# coverage; and a bad synthetic= value refused at init in one line, before
# any peer is waited for. No timing is checked.
add_executable(synthetic_check ${CMAKE_CURRENT_SOURCE_DIR}/sortlast/synthetic_check.c)
target_link_libraries(synthetic_check PRIVATE tessera_composite_synthetic tessera m)
set(SYNTHETIC_OUT ${CMAKE_BINARY_DIR}/test-out/synthetic)
add_test(NAME binaryswap_synthetic_full_composite_exact_n3
  COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/sortlast/synthetic.sh ${CMAKE_BINARY_DIR}/bin ${SYNTHETIC_OUT}/full3 3 full)
add_test(NAME binaryswap_synthetic_ellipse_composite_exact_n4
  COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/sortlast/synthetic.sh ${CMAKE_BINARY_DIR}/bin ${SYNTHETIC_OUT}/ellipse4 4 ellipse)
# No peer exists at this display address: a value that waited for peers
# would hang until link_timeout_ms instead of failing.
add_test(NAME binaryswap_synthetic_bogus_refused_at_init
  COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/render/expect.sh 1 ""
          "^spheres: binaryswap#1: synthetic=bogus: expected full, ellipse or off$"
          $<TARGET_FILE:spheres> --frames 1 --size 32x32
          --chain "binaryswap display=unix:${SYNTHETIC_OUT}/nobody synthetic=bogus rank=1 peers=unix:${SYNTHETIC_OUT}/p0,unix:${SYNTHETIC_OUT}/p1")
set_tests_properties(binaryswap_synthetic_full_composite_exact_n3 binaryswap_synthetic_ellipse_composite_exact_n4
  binaryswap_synthetic_bogus_refused_at_init PROPERTIES
  TIMEOUT 60 LABELS sortlast FAIL_REGULAR_EXPRESSION "FAIL:" ENVIRONMENT "LP_NUM_THREADS=0")
if(TESSERA_SANITIZE)
  set_tests_properties(binaryswap_synthetic_full_composite_exact_n3 binaryswap_synthetic_ellipse_composite_exact_n4
    binaryswap_synthetic_bogus_refused_at_init PROPERTIES
    ENVIRONMENT "LP_NUM_THREADS=0;LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp:print_suppressions=0:use_tls=0")
endif()
