# tests/faker.cmake — the faker (faker/): its exports cover what Debian's GL
# programs import, GetProcAddress agrees with dlsym, glxgears runs through
# it under Xvfb (directly and through `tessera exec`), and `tessera exec`
# passes status, signals and output through (about 5 s in all); and, in
# plain builds, every xscreensaver-gl hack draws through it (about 1.5 min).
if(NOT TARGET tessera_faker_gl)
  return()
endif()
set(FAKER_TEST_DIR ${CMAKE_CURRENT_SOURCE_DIR}/faker)
set(FAKER_OUT ${CMAKE_BINARY_DIR}/test-out/faker)
file(MAKE_DIRECTORY ${FAKER_OUT})

# Sanitized builds: glxgears is not instrumented but loads the instrumented
# faker, so the sanitizer runtimes are preloaded into it (ASan must come
# first in the process); the test programs below are instrumented anyway.
set(FAKER_PRELOAD "")
if(TESSERA_SANITIZE)
  foreach(rt libasan.so libubsan.so)
    execute_process(COMMAND ${CMAKE_C_COMPILER} -print-file-name=${rt}
                    OUTPUT_VARIABLE rt_path OUTPUT_STRIP_TRAILING_WHITESPACE)
    if(NOT EXISTS "${rt_path}")
      message(FATAL_ERROR "faker tests: the sanitizer runtime ${rt} was not found (${rt_path})")
    endif()
    string(APPEND FAKER_PRELOAD "${rt_path} ")
  endforeach()
  string(STRIP "${FAKER_PRELOAD}" FAKER_PRELOAD)
endif()

add_executable(faker_procs ${FAKER_TEST_DIR}/procs_test.c)
target_link_libraries(faker_procs PRIVATE ${CMAKE_DL_LIBS})
add_executable(faker_frames ${FAKER_TEST_DIR}/frames_check.c)
target_link_libraries(faker_frames PRIVATE tessera)

add_test(NAME faker_exports_every_gl_glx_egl_import_of_glxgears_glxinfo_glu_and_xscreensaver_gl
         COMMAND bash ${FAKER_TEST_DIR}/imports.sh ${TESSERA_FAKER_DIR})
add_test(NAME faker_getprocaddress_equals_dlsym_for_every_exported_name
         COMMAND sh -c "nm -D --defined-only '${TESSERA_FAKER_DIR}/libGL.so.1' '${TESSERA_FAKER_DIR}/libEGL.so.1' | awk '{print $NF}' | sed 's/@.*//' | grep -E '^(gl|glX|egl)[A-Z]' | sort -u > '${FAKER_OUT}/names.txt' && '$<TARGET_FILE:faker_procs>' '${TESSERA_FAKER_DIR}' '${FAKER_OUT}/names.txt'")
add_test(NAME faker_glxgears_under_xvfb_writes_moving_frames_and_ends_on_sigterm
         COMMAND bash ${FAKER_TEST_DIR}/glxgears.sh direct ${TESSERA_FAKER_DIR} $<TARGET_FILE:tessera_cli>
                 $<TARGET_FILE:faker_frames> ${FAKER_OUT}/glxgears)
add_test(NAME faker_tessera_exec_runs_glxgears_with_the_default_render_chain
         COMMAND bash ${FAKER_TEST_DIR}/glxgears.sh exec ${TESSERA_FAKER_DIR} $<TARGET_FILE:tessera_cli>
                 $<TARGET_FILE:faker_frames> ${FAKER_OUT}/exec)
add_test(NAME faker_tessera_exec_passes_status_signals_and_output_through
         COMMAND bash ${FAKER_TEST_DIR}/exec_status.sh $<TARGET_FILE:tessera_cli> ${FAKER_OUT}/status)
set_tests_properties(
  faker_exports_every_gl_glx_egl_import_of_glxgears_glxinfo_glu_and_xscreensaver_gl
  faker_glxgears_under_xvfb_writes_moving_frames_and_ends_on_sigterm
  faker_tessera_exec_runs_glxgears_with_the_default_render_chain
  PROPERTIES SKIP_RETURN_CODE 77)
set_tests_properties(
  faker_glxgears_under_xvfb_writes_moving_frames_and_ends_on_sigterm
  faker_tessera_exec_runs_glxgears_with_the_default_render_chain
  PROPERTIES ENVIRONMENT "FAKER_PRELOAD=${FAKER_PRELOAD}" TIMEOUT 60)

# EGL with no X server: linked against the faker's libraries themselves.
# Its stderr (the faker's warnings, the harness's reports) is kept in
# egl.err and shown whether it passed or not; exactly one glGetMinmaxParameteriv
# warning must be in it.
add_executable(faker_egl_surfaceless ${FAKER_TEST_DIR}/egl_surfaceless_test.c)
target_link_libraries(faker_egl_surfaceless PRIVATE tessera_faker_egl tessera_faker_gl)
add_test(NAME faker_egl_surfaceless_and_pbuffer_draw_with_no_x_server_and_refuse_gles
         COMMAND sh -c "env -u DISPLAY TESSERA_CHAIN=render '$<TARGET_FILE:faker_egl_surfaceless>' 2>'${FAKER_OUT}/egl.err'; s=$?; cat '${FAKER_OUT}/egl.err'; [ $s -eq 0 ] || exit 1; n=$(grep -c 'glGetMinmaxParameteriv is not supported by tessera' '${FAKER_OUT}/egl.err'); echo \"glGetMinmaxParameteriv warnings: $n\"; [ $n -eq 1 ]")

# A forked child's exit() leaves the parent's chain alone (faker/core.c
# chain_at_exit): the capture holds the parent's 6 glClear, not the 2 before
# the fork (xscreensaver's gflux forks such a child every run).
add_executable(faker_fork_exit ${FAKER_TEST_DIR}/fork_exit_driver.c)
target_link_libraries(faker_fork_exit PRIVATE tessera_faker_egl tessera_faker_gl)
add_test(NAME faker_forked_child_exit_leaves_the_parents_chain_and_capture_alone
         COMMAND sh -c "rm -f '${FAKER_OUT}/fork.tsrcap' && env -u DISPLAY TESSERA_CHAIN='capture file=${FAKER_OUT}/fork.tsrcap ! render output=' '$<TARGET_FILE:faker_fork_exit>' && '$<TARGET_FILE:tessera_cli>' replay --info '${FAKER_OUT}/fork.tsrcap' > '${FAKER_OUT}/fork.info' ; s=$?; cat '${FAKER_OUT}/fork.info'; [ $s -eq 0 ] && grep -Eq '^  glClear +6$' '${FAKER_OUT}/fork.info'")
# Before the fix the child also hung ending the parent's chain: bounded.
set_tests_properties(faker_forked_child_exit_leaves_the_parents_chain_and_capture_alone PROPERTIES TIMEOUT 30)

# GLX: configs, contexts, current state, sizes, a resize followed; then EGL
# on X11 into the same window.
add_executable(faker_glx_resize ${FAKER_TEST_DIR}/glx_resize_driver.c)
target_link_libraries(faker_glx_resize PRIVATE tessera_faker_egl tessera_faker_gl tessera PkgConfig::X11)
add_test(NAME faker_glx_contexts_sizes_and_a_resize_reach_the_stream_then_egl_on_x11
         COMMAND bash ${FAKER_TEST_DIR}/glx_resize.sh $<TARGET_FILE:faker_glx_resize> ${FAKER_OUT}/resize)
set_tests_properties(faker_glx_contexts_sizes_and_a_resize_reach_the_stream_then_egl_on_x11 PROPERTIES SKIP_RETURN_CODE 77)

# Sanitizer builds: OSMesa/LLVM keep process-lifetime allocations
# (tests/lsan.supp); the faker's and tessera's own are still checked.
if(TESSERA_SANITIZE)
  set_property(TEST
    faker_getprocaddress_equals_dlsym_for_every_exported_name
    faker_tessera_exec_passes_status_signals_and_output_through
    faker_egl_surfaceless_and_pbuffer_draw_with_no_x_server_and_refuse_gles
    faker_glx_contexts_sizes_and_a_resize_reach_the_stream_then_egl_on_x11
    APPEND PROPERTY ENVIRONMENT
    "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp:print_suppressions=0:use_tls=0")
endif()

# The real-program sweeps hold RESOURCE_LOCK cpu_heavy_sweep: each keeps
# both cores busy, and two at once would starve each other's deadlines.
# The real-program sweep: every GL hack of xscreensaver-gl (about 80) and
# glxgears through `tessera exec` with [render] 1x1, two at a time, each
# until it has 10 frames not of one colour, then SIGTERM (about 1.5 min on
# two busy cores). Plain builds only: uninstrumented programs loading an
# instrumented faker 80 times would take the CI's whole budget.
if(NOT TESSERA_SANITIZE)
  add_test(NAME faker_every_xscreensaver_gl_hack_and_glxgears_draw_frames_and_end_on_sigterm
           COMMAND bash ${FAKER_TEST_DIR}/xscreensaver.sh $<TARGET_FILE:tessera_cli> $<TARGET_FILE:faker_frames>
                   ${CMAKE_SOURCE_DIR}/spec/gl.yaml ${FAKER_OUT}/xscreensaver)
  set_tests_properties(faker_every_xscreensaver_gl_hack_and_glxgears_draw_frames_and_end_on_sigterm
                       PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 600
                       RESOURCE_LOCK cpu_heavy_sweep)
  # The same for glxgears and 25 hacks (the five GLSL ones among them) as
  # the app node of [pack -> server render] over TCP (tests/faker/
  # sweep_pack.yaml; about 15 s), and of [tilesort 2x2 with assemble]
  # (sweep_wall.yaml; about 65 s).
  add_test(NAME faker_glxgears_and_25_xscreensaver_gl_hacks_draw_through_pack_to_a_server_and_end_on_sigterm
           COMMAND bash ${FAKER_TEST_DIR}/xscreensaver.sh $<TARGET_FILE:tessera_cli> $<TARGET_FILE:faker_frames>
                   ${CMAKE_SOURCE_DIR}/spec/gl.yaml ${FAKER_OUT}/xscreensaver_pack pack)
  set_tests_properties(faker_glxgears_and_25_xscreensaver_gl_hacks_draw_through_pack_to_a_server_and_end_on_sigterm
                       PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 300
                       RESOURCE_LOCK cpu_heavy_sweep)
  add_test(NAME faker_glxgears_and_25_xscreensaver_gl_hacks_draw_through_the_2x2_tilesort_wall_and_end_on_sigterm
           COMMAND bash ${FAKER_TEST_DIR}/xscreensaver.sh $<TARGET_FILE:tessera_cli> $<TARGET_FILE:faker_frames>
                   ${CMAKE_SOURCE_DIR}/spec/gl.yaml ${FAKER_OUT}/xscreensaver_wall wall)
  set_tests_properties(faker_glxgears_and_25_xscreensaver_gl_hacks_draw_through_the_2x2_tilesort_wall_and_end_on_sigterm
                       PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 300
                       RESOURCE_LOCK cpu_heavy_sweep)
  # Capture exactness (tests/faker/sweep_exact.sh): glxgears and the same 25
  # hacks captured once each, replayed through [render] 1x1 and the 2x2
  # wall: 0 differing pixels every frame, each equal to the live run (about
  # 31 s).
  add_test(NAME faker_glxgears_and_25_xscreensaver_gl_hacks_replayed_through_the_2x2_wall_equal_render_1x1_every_pixel
           COMMAND bash ${FAKER_TEST_DIR}/sweep_exact.sh $<TARGET_FILE:tessera_cli> ${FAKER_OUT}/xscreensaver_exact)
  set_tests_properties(faker_glxgears_and_25_xscreensaver_gl_hacks_replayed_through_the_2x2_wall_equal_render_1x1_every_pixel
                       PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 300
                       RESOURCE_LOCK cpu_heavy_sweep)
endif()

# Share lists: a display list and a texture of one GLX context drawn by a
# context made with it as share list.
add_executable(faker_glx_share ${FAKER_TEST_DIR}/glx_share_driver.c)
target_link_libraries(faker_glx_share PRIVATE tessera_faker_gl tessera PkgConfig::X11)
add_test(NAME faker_glx_share_list_context_draws_the_first_contexts_display_list_and_texture
         COMMAND bash ${FAKER_TEST_DIR}/glx_resize.sh $<TARGET_FILE:faker_glx_share> ${FAKER_OUT}/share)
set_tests_properties(faker_glx_share_list_context_draws_the_first_contexts_display_list_and_texture
                     PROPERTIES SKIP_RETURN_CODE 77)
if(TESSERA_SANITIZE)
  set_property(TEST faker_glx_share_list_context_draws_the_first_contexts_display_list_and_texture
               APPEND PROPERTY ENVIRONMENT
               "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp:print_suppressions=0:use_tls=0")
endif()

# Threads: 3 threads, each with its own context and pbuffer, draw 12
# different frames at the same time; every frame read back equals the same
# frame drawn by one thread alone (0 differing pixels); a share-list
# context is made current while its share list is current on another
# thread, and a context current on another thread is refused; a share list
# idle on its plain table on another thread makes the MakeCurrent fail
# after the bounded 3 s, and one glClear there lets it through.
add_executable(faker_egl_threads ${FAKER_TEST_DIR}/egl_threads_test.c)
target_link_libraries(faker_egl_threads PRIVATE tessera_faker_egl tessera_faker_gl Threads::Threads)
add_test(NAME faker_threads_with_their_own_contexts_draw_at_once_exactly_as_one_thread_alone
         COMMAND sh -c "env -u DISPLAY TESSERA_CHAIN=render '$<TARGET_FILE:faker_egl_threads>' 3 12")
if(TESSERA_SANITIZE)
  set_property(TEST faker_threads_with_their_own_contexts_draw_at_once_exactly_as_one_thread_alone
               APPEND PROPERTY ENVIRONMENT
               "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp:print_suppressions=0:use_tls=0")
endif()

# Share lists across threads drawing at once: a loader thread makes the
# textures and display lists, and loads frame f+1's while a drawing thread
# draws frame f with the other pair, through [render], [loopback ! render]
# and [pack -> server render]; every frame equals the same frames drawn by
# one thread, and the runs' frames are the same bytes as OSMesa's own;
# the same through GLX under Xvfb (an X window and a GLX pbuffer).
add_executable(faker_egl_share_threads ${FAKER_TEST_DIR}/egl_share_threads_driver.c)
target_link_libraries(faker_egl_share_threads PRIVATE tessera_faker_egl tessera_faker_gl Threads::Threads)
add_executable(faker_glx_share_threads ${FAKER_TEST_DIR}/egl_share_threads_driver.c)
target_compile_definitions(faker_glx_share_threads PRIVATE SHARE_GLX)
target_link_libraries(faker_glx_share_threads PRIVATE tessera_faker_gl PkgConfig::X11 Threads::Threads)
add_executable(faker_egl_share_threads_native ${FAKER_TEST_DIR}/egl_share_threads_driver.c)
target_compile_definitions(faker_egl_share_threads_native PRIVATE SHARE_NATIVE)
target_link_libraries(faker_egl_share_threads_native PRIVATE PkgConfig::OSMESA)
add_test(NAME faker_share_list_contexts_on_two_threads_load_and_draw_at_once_exactly_as_one_thread
         COMMAND bash ${FAKER_TEST_DIR}/share_threads.sh egl $<TARGET_FILE:faker_egl_share_threads>
                 $<TARGET_FILE:faker_egl_share_threads_native> $<TARGET_FILE:tessera_cli>
                 ${FAKER_OUT}/share_threads)
add_test(NAME faker_glx_share_list_contexts_on_two_threads_window_and_pbuffer_exactly_as_one_thread
         COMMAND bash ${FAKER_TEST_DIR}/share_threads.sh glx $<TARGET_FILE:faker_glx_share_threads>
                 $<TARGET_FILE:faker_egl_share_threads_native> $<TARGET_FILE:tessera_cli>
                 ${FAKER_OUT}/glx_share_threads)
set_tests_properties(faker_share_list_contexts_on_two_threads_load_and_draw_at_once_exactly_as_one_thread
                     faker_glx_share_list_contexts_on_two_threads_window_and_pbuffer_exactly_as_one_thread
                     PROPERTIES TIMEOUT 120 SKIP_RETURN_CODE 77)
if(TESSERA_SANITIZE)
  set_property(TEST faker_share_list_contexts_on_two_threads_load_and_draw_at_once_exactly_as_one_thread
               faker_glx_share_list_contexts_on_two_threads_window_and_pbuffer_exactly_as_one_thread
               APPEND PROPERTY ENVIRONMENT
               "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp:print_suppressions=0:use_tls=0")
endif()

# Two contexts of one share group with their own pixel store and client
# arrays, used in turn: the stream's mirrors follow its MakeCurrentTSR.
add_executable(faker_egl_share_client_state ${FAKER_TEST_DIR}/egl_share_client_state_driver.c)
target_link_libraries(faker_egl_share_client_state PRIVATE tessera_faker_egl tessera_faker_gl)
add_executable(faker_egl_share_client_state_native ${FAKER_TEST_DIR}/egl_share_client_state_driver.c)
target_compile_definitions(faker_egl_share_client_state_native PRIVATE SHARE_NATIVE)
target_link_libraries(faker_egl_share_client_state_native PRIVATE PkgConfig::OSMESA)
add_test(NAME faker_share_group_contexts_keep_their_own_pixel_store_and_client_arrays
         COMMAND bash ${FAKER_TEST_DIR}/share_client_state.sh $<TARGET_FILE:faker_egl_share_client_state>
                 $<TARGET_FILE:faker_egl_share_client_state_native> $<TARGET_FILE:tessera_cli>
                 ${FAKER_OUT}/share_client_state)
set_tests_properties(faker_share_group_contexts_keep_their_own_pixel_store_and_client_arrays PROPERTIES TIMEOUT 120)
if(TESSERA_SANITIZE)
  set_property(TEST faker_share_group_contexts_keep_their_own_pixel_store_and_client_arrays APPEND PROPERTY
               ENVIRONMENT "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp:print_suppressions=0:use_tls=0")
endif()

# GLX pbuffers and pixmaps: off-screen tessera drawables of their size.
add_executable(faker_glx_offscreen ${FAKER_TEST_DIR}/glx_offscreen_driver.c)
target_link_libraries(faker_glx_offscreen PRIVATE tessera_faker_gl PkgConfig::X11)
add_test(NAME faker_glx_pbuffers_and_pixmaps_are_offscreen_drawables_of_their_size
         COMMAND bash ${FAKER_TEST_DIR}/glx_offscreen.sh $<TARGET_FILE:faker_glx_offscreen> ${FAKER_OUT}/offscreen)
set_tests_properties(faker_glx_pbuffers_and_pixmaps_are_offscreen_drawables_of_their_size
                     PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 120)
if(TESSERA_SANITIZE)
  set_property(TEST faker_glx_pbuffers_and_pixmaps_are_offscreen_drawables_of_their_size
               APPEND PROPERTY ENVIRONMENT
               "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp:print_suppressions=0:use_tls=0")
endif()

# recorded_gl_test(NAME DRIVER TEST [DEFINITIONS...]): a driver that holds
# tessera's answers next to OSMesa's (tests/faker/recorded_gl.h), built
# twice, faker_NAME through the faker and faker_NAME_native on OSMesa, and
# the test gl21_commands.sh runs with them: [render], [capture ! render],
# [pack -> node render] and a 2x2 tilesort wall must write what OSMesa
# writes, and the capture replayed into render must answer as recorded.
function(recorded_gl_test name driver test)
  add_executable(faker_${name} ${FAKER_TEST_DIR}/${driver} ${FAKER_TEST_DIR}/recorded_gl.c)
  target_compile_definitions(faker_${name} PRIVATE ${ARGN})
  target_link_libraries(faker_${name} PRIVATE tessera_faker_egl tessera_faker_gl)
  add_executable(faker_${name}_native ${FAKER_TEST_DIR}/${driver} ${FAKER_TEST_DIR}/recorded_gl.c)
  target_compile_definitions(faker_${name}_native PRIVATE RECORDED_GL_NATIVE ${ARGN})
  target_link_libraries(faker_${name}_native PRIVATE PkgConfig::OSMESA)
  add_test(NAME ${test}
           COMMAND bash ${FAKER_TEST_DIR}/gl21_commands.sh $<TARGET_FILE:faker_${name}>
                   $<TARGET_FILE:faker_${name}_native> $<TARGET_FILE:tessera_cli> ${FAKER_OUT}/${name})
  set_tests_properties(${test} PROPERTIES TIMEOUT 120)
endfunction()

# The GL 1.0-2.1 commands added to complete the spec (issue 27), each where
# its effect shows.
recorded_gl_test(gl21_commands gl21_commands_driver.c
                 faker_gl21_commands_draw_and_answer_as_osmesa_through_render_pack_and_wall)
# The extensions without commands the faker offers (spec/gl_extensions.txt),
# each where its effect shows; OSMesa has every listed one.
recorded_gl_test(extensions extensions_driver.c
                 faker_offered_extensions_draw_and_answer_as_osmesa_through_render_pack_and_wall
                 EXTENSIONS_TABLE="${CMAKE_SOURCE_DIR}/spec/gl_extensions.txt")
# The client-array commands beyond glDrawArrays/glDrawElements (issue 27
# item 5): secondary colour, fog coordinate and index arrays, the range and
# multi draws, in a display list, the pointer gets and the errors.
recorded_gl_test(client_arrays client_arrays_driver.c
                 faker_client_arrays_draw_and_answer_as_osmesa_through_render_pack_and_wall)
# GL_ARB_map_buffer_range, offered because its two commands are spec
# commands: each access bit on a range of a buffer, explicit flushes, the
# vertices, pack and unpack buffers written or read through a range, and
# GL's errors (core/wire/pack_map.c, core/state/state_map.c).
recorded_gl_test(map_buffer_range map_buffer_range_driver.c
                 faker_map_buffer_range_maps_and_answers_as_osmesa_through_render_pack_and_wall)
# GL_EXT_texture_integer, offered because its six commands are spec
# commands: the integer clear colour, integer border colours and the other
# texture parameters through them, integer images read back.
recorded_gl_test(texture_integer texture_integer_driver.c
                 faker_texture_integer_commands_answer_as_osmesa_through_render_pack_and_wall)
# Copies of the window's pixels across the tiles of the 2x2 wall
# (spus/tilesort/copy.c): glCopyPixels of colour, depth and stencil and
# glCopyTex(Sub)Image1D/2D/3D whose source lies on other tiles, read back,
# with the program's pixel store kept and the copies' errors once each.
recorded_gl_test(cross_tile_copy cross_tile_copy_driver.c
                 faker_cross_tile_copies_read_and_draw_as_osmesa_through_render_pack_and_wall)
# GL_EXT_framebuffer_object, offered because its seventeen commands are
# spec commands: a program's FBO with a texture and a depth renderbuffer
# drawn into (larger than the window), read back while bound, its texture
# drawn into the window and read back, the queries, status answers and
# errors; on the 2x2 wall too, which renders the FBO whole on every server
# (spus/tilesort/fbo.c).
recorded_gl_test(fbo fbo_driver.c faker_fbo_renders_into_textures_as_osmesa_through_render_pack_and_wall)
# GL_ARB_framebuffer_object's core names and glBlitFramebuffer (and
# glBlitFramebufferEXT, its alias), offered because their commands are spec
# commands: a core-named FBO of a texture and a depth-stencil renderbuffer,
# blits between it, a multisample renderbuffer and the window (read and
# draw framebuffers bound apart), a 3D texture's layer attached; on the
# 2x2 wall a blit from the window is gathered from the tiles
# (spus/tilesort/blit.c).
recorded_gl_test(blit blit_driver.c faker_core_fbo_and_blits_draw_as_osmesa_through_render_pack_and_wall)

# Front and back buffers of a double-buffered GLX window (issue 27 item
# 5): glDrawBuffer/glReadBuffer of every window buffer name, clears, a swap
# and the front read after it, through [render], [pack -> node render] and
# a 2x2 wall, answer as Mesa's own GLX on the same private Xvfb (libgl-dev).
pkg_check_modules(NATIVE_GL REQUIRED IMPORTED_TARGET gl)
add_executable(faker_glx_buffers ${FAKER_TEST_DIR}/glx_buffers_driver.c)
target_link_libraries(faker_glx_buffers PRIVATE tessera_faker_gl PkgConfig::X11)
add_executable(faker_glx_buffers_native ${FAKER_TEST_DIR}/glx_buffers_driver.c)
target_link_libraries(faker_glx_buffers_native PRIVATE PkgConfig::NATIVE_GL PkgConfig::X11)
add_test(NAME faker_glx_front_and_back_buffers_answer_as_mesa_through_render_pack_and_wall
         COMMAND bash ${FAKER_TEST_DIR}/glx_buffers.sh $<TARGET_FILE:faker_glx_buffers>
                 $<TARGET_FILE:faker_glx_buffers_native> $<TARGET_FILE:tessera_cli> ${FAKER_OUT}/glx_buffers)
set_tests_properties(faker_glx_front_and_back_buffers_answer_as_mesa_through_render_pack_and_wall PROPERTIES TIMEOUT 120)

# A window of a multisample config (tests/faker/glx_multisample_driver.c):
# rotated triangles drawn with GL_MULTISAMPLE through depth and stencil,
# the config's and GL's sample answers, the window read by glReadPixels,
# glCopyPixels, glCopyTex(Sub)Image2D and after a swap, through [render],
# [pack -> node render] and a 2x2 wall: every line and every colour pixel
# equal to Mesa's own GLX with the same 4 samples on the same Xvfb, and the
# frame PNG render writes equal to what Mesa's swap shows in the X window.
add_executable(faker_glx_multisample ${FAKER_TEST_DIR}/glx_multisample_driver.c)
target_link_libraries(faker_glx_multisample PRIVATE tessera_faker_gl PkgConfig::X11)
add_executable(faker_glx_multisample_native ${FAKER_TEST_DIR}/glx_multisample_driver.c)
target_link_libraries(faker_glx_multisample_native PRIVATE PkgConfig::NATIVE_GL PkgConfig::X11)
add_test(NAME faker_glx_multisample_window_draws_and_reads_as_mesa_through_render_pack_and_wall
         COMMAND bash ${FAKER_TEST_DIR}/glx_multisample.sh $<TARGET_FILE:faker_glx_multisample>
                 $<TARGET_FILE:faker_glx_multisample_native> $<TARGET_FILE:tessera_cli> ${FAKER_OUT}/glx_multisample)
set_tests_properties(faker_glx_multisample_window_draws_and_reads_as_mesa_through_render_pack_and_wall
                     PROPERTIES TIMEOUT 120)

# Configs as a driver offers them (tests/faker/glx_configs_driver.c): the
# attribute lists of glxgears, glxinfo, waffle (piglit), apitrace, GLFW,
# SDL2, freeglut, VTK, Qt and xscreensaver sent to Mesa's GLX and to the
# faker on one default Xvfb, then to the faker on Xvfbs without GLX (24
# and 32, and 24 alone): whenever Mesa has a config the faker has one of
# the same sizes, save the listed differences (about 3 s; private Xvfbs
# on -displayfd numbers).
add_executable(faker_glx_configs ${FAKER_TEST_DIR}/glx_configs_driver.c)
target_link_libraries(faker_glx_configs PRIVATE PkgConfig::X11 ${CMAKE_DL_LIBS})
add_test(NAME faker_glx_configs_hold_to_mesas_for_real_programs_attribute_lists_on_any_x_server
         COMMAND bash ${FAKER_TEST_DIR}/glx_configs.sh $<TARGET_FILE:faker_glx_configs> ${TESSERA_FAKER_DIR}
                 ${FAKER_OUT}/configs)
set_tests_properties(faker_glx_configs_hold_to_mesas_for_real_programs_attribute_lists_on_any_x_server
                     PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 60)

# Only the faker (tests/faker/only_faker.sh): under `tessera exec`,
# glxgears, glxinfo, a piglit test (waffle, on GLX and on EGL),
# apitrace's glretrace and eglretrace (replaying traces recorded natively
# first) and a VTK 9 program (vtk_cone.py, python3-vtk9; it draws natively,
# and under exec VTK refuses OpenGL below 3.2 with its own message, exit 1,
# no frame) map the faker's libraries and no system GL library, read from
# /proc/PID/maps (about 15 s; a private Xvfb on a -displayfd number).
add_library(faker_maps_at_exit MODULE ${FAKER_TEST_DIR}/maps_at_exit.c)
add_test(NAME faker_programs_under_exec_map_no_system_gl_library
         COMMAND bash ${FAKER_TEST_DIR}/only_faker.sh $<TARGET_FILE:tessera_cli> $<TARGET_FILE:faker_maps_at_exit>
                 ${FAKER_OUT}/only_faker)
set_tests_properties(faker_programs_under_exec_map_no_system_gl_library PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 300)
if(TESSERA_SANITIZE)
  set_property(TEST faker_programs_under_exec_map_no_system_gl_library APPEND PROPERTY ENVIRONMENT
               "FAKER_PRELOAD=${FAKER_PRELOAD}")
endif()
