# tests/apitrace.cmake — apitrace traces replayed through tessera (issue 27,
# item 4; docs/conformance.md, "apitrace replays"). tests/apitrace/replay.py
# records, on its own default Xvfb (1280x1024x24, GLX enabled; -displayfd,
# so no fixed display and no lock), traces of glxgears and 14
# xscreensaver-gl hacks with Debian's `apitrace trace`, cut to 7 frames,
# and replays each with Debian's unmodified glretrace/eglretrace natively,
# under `tessera exec` with [render] and on a 2x2 grid wall: as many frames
# as natively, each equal in RGB to the native snapshot from frame 1 on
# (frame 0: Mesa draws it before it takes the replayer's resize; glxgears
# and gears recorded at 32x32 need none and are compared from frame 0;
# or >= 40 dB where the GL stacks round differently), the wall equal to
# render, 0 px (45 s to 2 min on two shared cores). The second test replays glxgears's trace on
# a wall of fixed pixel tiles: glretrace opens a 32x32 window and resizes
# it to the trace's 320x240 before it draws, and tilesort checks the tiles
# at the first frame drawn. Plain builds only: a sanitized faker under
# uninstrumented replayers would take the CI's budget.
if(NOT TARGET tessera_faker_gl OR TESSERA_SANITIZE)
  return()
endif()
add_executable(apitrace_frames_compare ${CMAKE_CURRENT_SOURCE_DIR}/apitrace/frames_compare.c)
target_link_libraries(apitrace_frames_compare PRIVATE tessera m)
find_program(TESSERA_PYTHON3 python3 PATHS /usr/bin NO_DEFAULT_PATH)
set(APITRACE_OUT ${CMAKE_BINARY_DIR}/test-out/apitrace)
add_test(NAME apitrace_replays_of_glxgears_and_14_xscreensaver_hacks_equal_native_through_render_and_the_2x2_wall
         COMMAND ${TESSERA_PYTHON3} ${CMAKE_CURRENT_SOURCE_DIR}/apitrace/replay.py
                 $<TARGET_FILE:tessera_cli> $<TARGET_FILE:apitrace_frames_compare> ${APITRACE_OUT}/grid)
add_test(NAME tilesort_pixel_tiles_take_a_window_resized_before_the_first_frame_glretrace_on_a_wall
         COMMAND ${TESSERA_PYTHON3} ${CMAKE_CURRENT_SOURCE_DIR}/apitrace/replay.py
                 $<TARGET_FILE:tessera_cli> $<TARGET_FILE:apitrace_frames_compare> ${APITRACE_OUT}/tiles
                 --tiles --only glxgears)
set_tests_properties(
  apitrace_replays_of_glxgears_and_14_xscreensaver_hacks_equal_native_through_render_and_the_2x2_wall
  tilesort_pixel_tiles_take_a_window_resized_before_the_first_frame_glretrace_on_a_wall
  PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 600)
set_tests_properties(
  apitrace_replays_of_glxgears_and_14_xscreensaver_hacks_equal_native_through_render_and_the_2x2_wall
  PROPERTIES RESOURCE_LOCK cpu_heavy_sweep)
