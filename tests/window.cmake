# tests/window.cmake — render's window output (window_output, spus/render/
# xwindow.c) under a private Xvfb: the pixels of the window (XGetImage)
# against the PNG of the same frame, 0 differing pixels, for a wall node's
# own window and for glxgears' own window drawn back under the faker.
set(WINDOW_TEST_DIR ${CMAKE_CURRENT_SOURCE_DIR}/window)
set(WINDOW_OUT ${CMAKE_BINARY_DIR}/test-out/window)
file(MAKE_DIRECTORY ${WINDOW_OUT})
add_executable(window_xgrab ${WINDOW_TEST_DIR}/xgrab.c)
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
