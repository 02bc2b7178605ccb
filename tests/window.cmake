# tests/window.cmake — render's window output (window_output, spus/render/
# xwindow.c) under a private Xvfb: the pixels of the window (XGetImage)
# against the PNG of the same frame, 0 differing pixels, for a wall node's
# own window and for glxgears' own window drawn back under the faker.
set(WINDOW_TEST_DIR ${CMAKE_CURRENT_SOURCE_DIR}/window)
set(WINDOW_OUT ${CMAKE_BINARY_DIR}/test-out/window)
file(MAKE_DIRECTORY ${WINDOW_OUT})
add_executable(window_xgrab ${WINDOW_TEST_DIR}/xgrab_check.c)
target_link_libraries(window_xgrab PRIVATE tessera PkgConfig::RENDER_X11)

add_test(NAME window_output_x11_wall_node_window_equals_its_png
         COMMAND bash ${WINDOW_TEST_DIR}/own_window.sh $<TARGET_FILE:tessera_cli> $<TARGET_FILE:spheres>
                 $<TARGET_FILE:window_xgrab> ${WINDOW_OUT}/own)
set_tests_properties(window_output_x11_wall_node_window_equals_its_png PROPERTIES TIMEOUT 60 SKIP_RETURN_CODE 77)
if(TARGET tessera_faker_gl)
  add_test(NAME window_output_app_glxgears_window_drawn_back_equals_its_png
           COMMAND bash ${WINDOW_TEST_DIR}/drawback.sh $<TARGET_FILE:tessera_cli> $<TARGET_FILE:window_xgrab>
                   ${WINDOW_OUT}/drawback)
  set_tests_properties(window_output_app_glxgears_window_drawn_back_equals_its_png PROPERTIES
                       TIMEOUT 60 SKIP_RETURN_CODE 77 ENVIRONMENT "FAKER_PRELOAD=${FAKER_PRELOAD}")
endif()

# `tessera exec --graph`: glxgears as the app node of examples/graphs/tcp.yaml
# and wall_display.yaml (tests/faker/exec_graph.sh).
if(TARGET tiles_driver AND TARGET tessera_faker_gl)
  foreach(graph tcp wall_display)
    add_test(NAME faker_exec_graph_${graph}_runs_glxgears_as_its_app_node
             COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/faker/exec_graph.sh ${CMAKE_BINARY_DIR}/bin
                     ${CMAKE_SOURCE_DIR}/examples/graphs/${graph}.yaml ${graph} ${FAKER_OUT}/exec_graph_${graph}
                     $<TARGET_FILE:tiles_driver> $<TARGET_FILE:faker_frames>)
    set_tests_properties(faker_exec_graph_${graph}_runs_glxgears_as_its_app_node PROPERTIES
                         SKIP_RETURN_CODE 77 TIMEOUT 120 ENVIRONMENT "FAKER_PRELOAD=${FAKER_PRELOAD}")
  endforeach()
endif()
if(TARGET tessera_faker_gl)
  add_test(NAME faker_exec_graph_pixel_tiles_larger_than_the_program_window_fail_naming_both_sizes
           COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/faker/exec_tiles_mismatch.sh ${CMAKE_BINARY_DIR}/bin
                   ${CMAKE_SOURCE_DIR}/examples/graphs/wall.yaml ${FAKER_OUT}/exec_tiles_mismatch)
  set_tests_properties(faker_exec_graph_pixel_tiles_larger_than_the_program_window_fail_naming_both_sizes
                       PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 90 ENVIRONMENT "FAKER_PRELOAD=${FAKER_PRELOAD}")
endif()
if(TARGET tessera_faker_gl)
  add_executable(window_exec_resize ${WINDOW_TEST_DIR}/exec_resize_driver.c)
  target_link_libraries(window_exec_resize PRIVATE tessera_faker_gl PkgConfig::RENDER_X11)
endif()
if(TARGET tessera_faker_gl)
  add_test(NAME window_exec_grid_wall_follows_a_resize_and_every_frame_is_exact
           COMMAND bash ${WINDOW_TEST_DIR}/exec_grid_resize.sh ${CMAKE_BINARY_DIR}/bin
                   $<TARGET_FILE:window_exec_resize> ${WINDOW_TEST_DIR}/grid_wall.yaml ${WINDOW_OUT}/grid_resize)
  set_tests_properties(window_exec_grid_wall_follows_a_resize_and_every_frame_is_exact PROPERTIES
                       TIMEOUT 120 SKIP_RETURN_CODE 77 ENVIRONMENT "FAKER_PRELOAD=${FAKER_PRELOAD}")
endif()
