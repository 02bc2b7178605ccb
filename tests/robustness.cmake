# tests/robustness.cmake — what a kill, a lying peer or a crafted file must
# not do (issue 10, defects 8 to 11): leave partial PNGs, overwrite one
# output file every frame unasked, pass a malformed reply off as success,
# wait on an application that is gone, print a peer's control bytes, or
# decode a huge image imgdiff would refuse anyway. Real processes, sockets,
# OSMesa and PNGs; every wait is bounded.
get_property(ROBUST_TESTS_BEFORE DIRECTORY PROPERTY TESTS)
set(ROBUST_OUT ${CMAKE_BINARY_DIR}/test-out/robustness)
set(ROBUST_EXPECT ${CMAKE_CURRENT_SOURCE_DIR}/render/expect.sh)
file(MAKE_DIRECTORY ${ROBUST_OUT})

# --- defect 8: whole PNGs, and no silent overwriting ----------------------
add_executable(png_kill_test ${CMAKE_CURRENT_SOURCE_DIR}/render/png_kill_test.c)
target_link_libraries(png_kill_test PRIVATE tessera)
add_test(NAME render_node_killed_sigkill_sigterm_leaves_only_whole_pngs
  COMMAND png_kill_test ${CMAKE_BINARY_DIR}/bin ${ROBUST_OUT}/png-kill 12)
set_tests_properties(render_node_killed_sigkill_sigterm_leaves_only_whole_pngs PROPERTIES TIMEOUT 180)

add_test(NAME render_refuses_output_without_frame_number
  COMMAND ${ROBUST_EXPECT} 1 ""
          "render#1: option output=.*/one.png has no frame number: every frame would overwrite.*one-%04d.png.*output_overwrite=1"
          $<TARGET_FILE:spheres> --frames 2 --chain "render output=${ROBUST_OUT}/one.png")
add_test(NAME render_output_overwrite_keeps_the_last_frame
  COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/render/output_overwrite.sh ${CMAKE_BINARY_DIR}/bin ${ROBUST_OUT}/overwrite)
add_test(NAME readback_refuses_output_without_frame_number
  COMMAND ${ROBUST_EXPECT} 1 "" "readback#1.render: option output=tile.png has no frame number.*output_overwrite=1"
          $<TARGET_FILE:spheres> --frames 1 --chain "readback output=tile.png server=tcp://127.0.0.1:1")
add_test(NAME tilesort_refuses_assemble_without_frame_number
  COMMAND ${ROBUST_EXPECT} 1 "" "tilesort#1: option assemble=wall.png has no frame number.*assemble_overwrite=1"
          $<TARGET_FILE:spheres> --frames 1 --chain "tilesort servers=tcp://127.0.0.1:1 tiles=0:0:0:64:64 assemble=wall.png")
add_test(NAME tilesort_refuses_assemble_with_string_conversion
  COMMAND ${ROBUST_EXPECT} 1 "" "tilesort#1: option assemble: bad file pattern 'wall-%s.png'"
          $<TARGET_FILE:spheres> --frames 1 --chain "tilesort servers=tcp://127.0.0.1:1 tiles=0:0:0:64:64 assemble=wall-%s.png")

# --- defects 9 and 10: a lying server over a real socket ------------------
add_executable(lying_server ${CMAKE_CURRENT_SOURCE_DIR}/node/lying_server_peer.c)
target_include_directories(lying_server PRIVATE ${CMAKE_SOURCE_DIR}/netlib)
target_link_libraries(lying_server PRIVATE tessera tessera_net)
set(ROBUST_LIAR ${CMAKE_CURRENT_SOURCE_DIR}/node/lying_server.sh)
foreach(mode wrong-size truncated)
  foreach(policy exit drop)
    string(REPLACE "-" "_" mode_name ${mode})
    add_test(NAME client_malformed_reply_${mode_name}_fails_server_on_error_${policy}
      COMMAND ${ROBUST_LIAR} bad-reply ${CMAKE_BINARY_DIR}/bin ${ROBUST_OUT}/liar-${mode}-${policy}
              $<TARGET_FILE:lying_server> $<TARGET_FILE:node_driver> ${mode} ${policy})
  endforeach()
endforeach()
add_executable(text_sanitize_test ${CMAKE_CURRENT_SOURCE_DIR}/node/text_sanitize_test.c)
target_link_libraries(text_sanitize_test PRIVATE tessera)
add_test(NAME peer_text_sanitize_escapes_controls_and_invalid_utf8 COMMAND text_sanitize_test)
add_test(NAME client_server_error_text_escape_sequences_printed_escaped
  COMMAND ${ROBUST_LIAR} error-text ${CMAKE_BINARY_DIR}/bin ${ROBUST_OUT}/liar-error-text
          $<TARGET_FILE:lying_server> $<TARGET_FILE:node_driver>)

add_test(NAME run_app_exiting_without_connecting_ends_run_at_once_naming_it
  COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/run/app_exits.sh $<TARGET_FILE:tessera_cli> ${ROBUST_OUT}/app-exits)
set_tests_properties(run_app_exiting_without_connecting_ends_run_at_once_naming_it PROPERTIES TIMEOUT 60)

# --- defect 11: imgdiff reads headers first and bounds what a PNG claims --
add_executable(png_claims ${CMAKE_CURRENT_SOURCE_DIR}/render/png_claims_driver.c)
set(ROBUST_IMGDIFF_LIMIT_KB 262144) # 256 MiB: the old whole-image read of 16384x16384 needs 1 GiB
if(TESSERA_SANITIZE)
  set(ROBUST_IMGDIFF_LIMIT_KB 0)
endif()
add_test(NAME imgdiff_huge_claimed_size_refused_from_headers_before_decoding
  COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/render/imgdiff_huge.sh $<TARGET_FILE:tessera_cli> $<TARGET_FILE:png_claims>
          ${ROBUST_OUT}/imgdiff-huge ${ROBUST_IMGDIFF_LIMIT_KB})

get_property(ROBUST_TESTS_AFTER DIRECTORY PROPERTY TESTS)
list(REMOVE_ITEM ROBUST_TESTS_AFTER ${ROBUST_TESTS_BEFORE})
set(ROBUST_ENV "")
if(TESSERA_SANITIZE)
  set(ROBUST_ENV "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp:print_suppressions=0:use_tls=0")
endif()
set_property(TEST ${ROBUST_TESTS_AFTER} APPEND PROPERTY LABELS robustness)
set_property(TEST ${ROBUST_TESTS_AFTER} APPEND PROPERTY ENVIRONMENT "${ROBUST_ENV}")
