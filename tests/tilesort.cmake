# tests/tilesort.cmake — sort-first (spus/tilesort): real `tessera node`
# tile servers with the render SPU, real example programs, every frame
# gathered from the servers and compared with the native OSMesa reference
# (0 differing pixels), in every tiling the issue names: 2x1, 2x2, 3x3 (odd
# sizes), 4x4, irregular tiles, several tiles per server, load-balanced
# across frames (kd, union, and balance, kd's alias: regions that change
# every frame), broadcast. examples/tilescenes draws the hard cases (lit
# and textured triangles, display lists, vertex arrays, wide lines and
# large points just outside tile edges, polygons crossing the eye plane,
# NaN/Inf vertices, window-covering and buffer-spanning primitives,
# glDrawPixels/glBitmap/glRect across tile borders) and the two where sort-
# first degrades towards broadcast (every primitive covers the window; a
# state change between every primitive), and one long primitive of each
# mode; batch_bytes=4096 and 256 make primitives span buffers, so they are
# cut and reopened. Bounded in time.
get_property(TILESORT_TESTS_BEFORE DIRECTORY PROPERTY TESTS)
# The scene drivers, each built twice like the examples (the -native build,
# on OSMesa, is the reference): balance_scenes (a balancer's failure cases),
# program_scenes (what unmodified programs do that the examples do not:
# glMaterial inside glBegin, buffers bound in turn around each draw, ...),
# read_pixels (glReadPixels of rectangles meeting only some tiles, piglit's
# probes), select_feedback (selection and feedback passes, records
# printed), gl_errors (GL errors and invalid queries, answers printed) and
# texture_units (image units past the coordinate units, answers printed).
foreach(scenes balance_scenes program_scenes read_pixels select_feedback gl_errors texture_units)
  add_executable(${scenes}-native tilesort/${scenes}_driver.c ${CMAKE_SOURCE_DIR}/examples/common/exapp.c)
  target_compile_definitions(${scenes}-native PRIVATE EXAPP_NATIVE)
  target_include_directories(${scenes}-native PRIVATE ${CMAKE_SOURCE_DIR}/examples)
  target_link_libraries(${scenes}-native PRIVATE PkgConfig::OSMESA tessera m)
  add_executable(${scenes} tilesort/${scenes}_driver.c ${CMAKE_SOURCE_DIR}/examples/common/exapp.c)
  target_include_directories(${scenes} PRIVATE ${CMAKE_SOURCE_DIR}/examples)
  target_link_libraries(${scenes} PRIVATE tessera_gl tessera m)
endforeach()
# tests/tilesort/cost_learning_test.c: the balancer's cost model with
# deterministic times, in one process (the tiling sources themselves).
set(TILESORT_SRC ${CMAKE_SOURCE_DIR}/spus/tilesort)
add_executable(tilesort_cost_learning tilesort/cost_learning_test.c ${TILESORT_SRC}/bucket.c ${TILESORT_SRC}/cost.c
               ${TILESORT_SRC}/balance_kd.c ${TILESORT_SRC}/balance_union.c)
target_include_directories(tilesort_cost_learning PRIVATE ${TILESORT_SRC})
target_link_libraries(tilesort_cost_learning PRIVATE tessera m)
add_test(NAME tilesort_first_draw_and_announced_page_faults_do_not_move_the_split COMMAND tilesort_cost_learning)
set(TILESORT_SH ${CMAKE_CURRENT_SOURCE_DIR}/tilesort/tilesort.sh)
set(TILESORT_OUT ${CMAKE_BINARY_DIR}/test-out/tilesort)
set(TILESORT_BIN ${CMAKE_BINARY_DIR}/bin)

# 15 frames: every tilescenes scene once (frames 10-14: one long primitive
# of each mode, cut into pieces and reopened, spus/tilesort/split.c).
foreach(config 1x1 2x1 2x2 3x3 4x4 irregular multi kd union balance broadcast)
  add_test(NAME tilesort_exact_tilescenes_${config}
    COMMAND ${TILESORT_SH} exact ${TILESORT_BIN} ${TILESORT_OUT}/scenes-${config}
            tilescenes 15 ${config} batch_bytes=4096)
endforeach()
# 256-byte batches (the smallest): every long primitive is cut every few
# vertices, at odd and even counts.
# (the load-balanced repeats of these, of the examples and of the wall
# graphs only in the plain build: CI time; the sanitized build runs the
# balanced modes on tilescenes and balance_scenes)
set(TILESORT_BALANCED kd union)
if(TESSERA_SANITIZE)
  set(TILESORT_BALANCED)
endif()
foreach(config 3x3 ${TILESORT_BALANCED})
  add_test(NAME tilesort_exact_tilescenes_cut_every_few_vertices_${config}
    COMMAND ${TILESORT_SH} exact ${TILESORT_BIN} ${TILESORT_OUT}/scenes-256-${config}
            tilescenes 15 ${config} batch_bytes=256)
endforeach()
# ... and on 1x1 and 4x4, exact, with the long strips of frame 10 reaching
# few of the 16 servers (a primitive sent whole to all of them: about 16).
add_test(NAME tilesort_cut_primitive_is_not_broadcast_4x4
  COMMAND ${TILESORT_SH} split ${TILESORT_BIN} ${TILESORT_OUT}/split-4x4 tilescenes 11 10 4 batch_bytes=256)
# (2x2: tilescenes above, and spheres through the wall graphs below)
foreach(example spheres isosurface texquads)
  foreach(config 3x3 ${TILESORT_BALANCED})
    add_test(NAME tilesort_exact_${example}_${config}
      COMMAND ${TILESORT_SH} exact ${TILESORT_BIN} ${TILESORT_OUT}/${example}-${config} ${example} 3 ${config})
  endforeach()
endforeach()
# glMaterial inside glBegin reaches every server in order, and one set
# again after glEnd is not lost (moebius drew grey for red); a buffer bound
# only between two state changes reaches the servers (romanboy drew
# nothing); client arrays enabled with glEnable (piglit's
# gl-1.1-color-material-array drew nothing); user clip planes 6 and 7
# (the tracker kept 6 of Mesa's 8); glDrawPixels with swapped bytes
# across the tiles (a server died of SIGSEGV in Mesa), glGetError inside
# glBegin and a glDrawPixels GL refuses (piglit's draw-pixels,
# geterror-inside-begin); colour-index glDrawPixels across the tiles (a
# server read past Mesa's converted image: piglit's
# gl-1.0-drawpixels-color-index); a list per glBitmap, three deleted, all
# called with glCallLists (the servers kept and drew the deleted lists:
# piglit's gl-1.0-dlist-bitmap), all broken on the 2x2 wall before; and
# the same glMaterialfv before every glBegin of a lit mesh, which the
# servers now get as the program made them (geodesic's capture differed
# from the 1x1 render by a pixel without, on a 1x1 tilesort too: the
# tracker left the repeats out; this scene drew exactly before as well).
foreach(config 1x1 2x2 broadcast)
  add_test(NAME tilesort_exact_material_inside_begin_and_buffers_bound_in_turn_${config}
    COMMAND ${TILESORT_SH} exact ${TILESORT_BIN} ${TILESORT_OUT}/program-scenes-${config} program_scenes 8 ${config})
endforeach()
# glReadPixels of one pixel beside the first server's tile, in its rows,
# copied a row of negative width (piglit's gl-1.0-texgen died with SIGSEGV
# in its probes on a 2x2 wall): every read of read_pixels (single pixels,
# both sides of the tile edges, rectangles in one, two and four tiles, as
# bytes and as floats) equals OSMesa's and writes nothing past the buffer.
foreach(config 2x2 3x3 multi)
  add_test(NAME tilesort_read_pixels_beside_a_servers_tiles_exact_and_in_bounds_${config}
    COMMAND ${TILESORT_SH} exact ${TILESORT_BIN} ${TILESORT_OUT}/read-pixels-${config} read_pixels 2 ${config})
endforeach()
# glRenderMode(GL_SELECT/GL_FEEDBACK): every hit record and feedback value
# (exact bits), the return values (also -1 on overflow, and GL_SELECT
# refused without a buffer) and every frame equal OSMesa's through render,
# pack -> node -> render and a wall, where one server runs each pass whole
# (spus/tilesort/gets.c says why) and no other draws its primitives;
# batch_bytes=4096 cuts the long strip into buffers.
foreach(config 2x2 multi)
  add_test(NAME tilesort_select_feedback_records_exact_render_pack_wall_${config}
    COMMAND ${TILESORT_SH} records ${TILESORT_BIN} ${TILESORT_OUT}/select-feedback-${config} select_feedback 2 ${config}
            batch_bytes=4096)
endforeach()
# GL errors and invalid queries (tests/tilesort/gl_errors_driver.c): every
# glGetError answer, and what gets of unknown pnames write, equal OSMesa's
# through render, pack -> node -> render and a 2x2 wall, whose glGetError
# takes the errors made in the client (state calls the tracker refuses,
# glBegin/glEnd/glNewList GL refuses) and every server's (docs/walls.md);
# before, the wall answered GL_NO_ERROR for them and pack for setters of
# an unknown pname.
add_test(NAME tilesort_gl_errors_answer_as_osmesa_render_pack_wall_2x2
  COMMAND ${TILESORT_SH} records ${TILESORT_BIN} ${TILESORT_OUT}/gl-errors-2x2 gl_errors 2 2x2)
# Texture image units past the 8 coordinate units, up to the servers'
# GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS (tests/tilesort/texture_units_driver.c):
# a shader samples textures bound on units 0 to 191, two of them rebound
# every frame, and every frame equals OSMesa's; every unit is selected and
# asked back, and the errors GL raises past the coordinate units (and the
# calls it takes there) and glPushAttrib(GL_TEXTURE_BIT) there answer as
# OSMesa's. Before, the wall's tracker kept 8 units: glActiveTexture past
# them was ignored and the textures bound there never reached a server.
add_test(NAME tilesort_texture_image_units_past_the_coordinate_units_as_osmesa_2x2
  COMMAND ${TILESORT_SH} records ${TILESORT_BIN} ${TILESORT_OUT}/texture-units-2x2 texture_units 3 2x2)
# Large array draws are sorted primitive by primitive: on a 4x4 wall the
# isosurface's overlap stays near 1 (broadcast: 16); measured 1.038 with
# filled triangles boxed by half a pixel, 1.067 when they were boxed by
# the lines' and points' 2.5 pixels (the bound keeps the half pixel).
add_test(NAME tilesort_sorted_arrays_overlap_near_one
  COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/tilesort/overlap.sh ${TILESORT_BIN} ${TILESORT_OUT}/overlap 1.05)
# The wall graph through the mothership: tiles from the graph, tile PNGs and
# the assembled window exact, sort-first statistics in --stats.
if(TARGET tiles_driver)
  add_test(NAME tilesort_wall_graph_tiles_and_assembled_window_exact
    COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/tilesort/wall_graph.sh ${TILESORT_BIN}
            ${CMAKE_SOURCE_DIR}/examples/graphs/wall.yaml ${TILESORT_OUT}/wall $<TARGET_FILE:tiles_driver>)
  # The same wall with a display node (spus/readback): the tile servers
  # stream their tile images to it and it writes the assembled window.
  add_test(NAME tilesort_wall_display_node_assembles_exact_window
    COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/tilesort/wall_graph.sh ${TILESORT_BIN}
            ${CMAKE_SOURCE_DIR}/examples/graphs/wall_display.yaml ${TILESORT_OUT}/wall_display
            $<TARGET_FILE:tiles_driver>)
  # Both again load-balanced (6 frames; regions change every frame): the
  # assembled window exact with assemble= and through the display node.
  foreach(bucket ${TILESORT_BALANCED})
    add_test(NAME tilesort_wall_graph_${bucket}_assembled_window_exact
      COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/tilesort/wall_graph.sh ${TILESORT_BIN}
              ${CMAKE_SOURCE_DIR}/examples/graphs/wall.yaml ${TILESORT_OUT}/wall-${bucket}
              $<TARGET_FILE:tiles_driver> ${bucket} 6)
    add_test(NAME tilesort_wall_display_node_${bucket}_assembles_exact_window
      COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/tilesort/wall_graph.sh ${TILESORT_BIN}
              ${CMAKE_SOURCE_DIR}/examples/graphs/wall_display.yaml ${TILESORT_OUT}/wall_display-${bucket}
              $<TARGET_FILE:tiles_driver> ${bucket} 6)
  endforeach()
endif()
# Where the balancers' arithmetic fails (issue 13, item 5): the whole cost
# in one pixel, one window-sized primitive, an empty frame, and a server
# that stalls (it reports late); exact, every server keeps a region of a
# pixel or more, the regions cover the window, no NaN or Inf. 256x192.
foreach(bucket kd union)
  add_test(NAME tilesort_${bucket}_one_pixel_window_quad_empty_frame_stay_exact_every_server_keeps_a_region
    COMMAND ${TILESORT_SH} stable ${TILESORT_BIN} ${TILESORT_OUT}/stable-${bucket} ${bucket} 0)
  add_test(NAME tilesort_${bucket}_server_that_stalls_keeps_a_region_exact
    COMMAND ${TILESORT_SH} stable ${TILESORT_BIN} ${TILESORT_OUT}/stall-${bucket} ${bucket} 1)
  # Convergence with deterministic costs (1 ns per byte a server receives,
  # tessera node --cost bytes; item 3): a static scene is within 1.2 of perfect
  # balance from frame 3 on (counted from 0) and the split stops moving.
  add_test(NAME tilesort_${bucket}_static_scene_converges_within_3_frames_and_settles
    COMMAND ${TILESORT_SH} converge ${TILESORT_BIN} ${TILESORT_OUT}/converge-${bucket} ${bucket} 10 3 1.2 1
            batch_bytes=1024)
endforeach()
# A server reporting twice the time gets about half the others' load: its
# slowness shows in the first balanced frame's reports (frame 1; the
# evenly split frame 0 is not learnt from), so within 1.2 from frame 6
# on (measured: 1.202 / 1.165 at frame 5, kd / union, 1.165 / 1.164 at
# frame 6: the priors are llvmpipe's mix of bytes, box pixels and region
# pixels, which these tests' costs of 1 ns per byte are far from); 12
# frames, for the split to settle.
foreach(bucket ${TILESORT_BALANCED})
  add_test(NAME tilesort_${bucket}_server_twice_as_slow_gets_half_the_load
    COMMAND ${TILESORT_SH} converge ${TILESORT_BIN} ${TILESORT_OUT}/slow-${bucket} ${bucket} 12 6 1.2 2
            batch_bytes=1024)
endforeach()
# A moving scene (item 3): the isosurface's camera orbiting 10 degrees a
# frame (isosurface --orbit), deterministic costs: every frame exact, and
# the split follows the motion, the imbalance at most 1.4 every frame from
# frame 2 on (each split is made from the frame before's cost, so it lags
# the camera by a frame; the evenly split frame 0 is at 1.9). 512x384.
foreach(bucket ${TILESORT_BALANCED})
  add_test(NAME tilesort_${bucket}_tracks_an_orbiting_camera_exact_and_bounded
    COMMAND ${TILESORT_SH} track ${TILESORT_BIN} ${TILESORT_OUT}/orbit-${bucket} ${bucket} 6 10 1.4 batch_bytes=1024)
endforeach()
add_test(NAME tilesort_bad_tile_is_a_clear_error
  COMMAND ${TILESORT_SH} bad ${TILESORT_BIN} ${TILESORT_OUT}/bad-tile 0:0:0:512 grid SERVER)
add_test(NAME tilesort_grid_of_non_grid_tiles_is_a_clear_error
  COMMAND ${TILESORT_SH} bad ${TILESORT_BIN} ${TILESORT_OUT}/bad-grid
          0:0:0:300:768,0:300:0:724:400,0:300:400:724:368 grid "columns and rows")

get_property(TILESORT_TESTS_AFTER DIRECTORY PROPERTY TESTS)
if(TILESORT_TESTS_BEFORE)
  list(REMOVE_ITEM TILESORT_TESTS_AFTER ${TILESORT_TESTS_BEFORE})
endif()
# llvmpipe single-threaded: up to 16 servers share two cores. Sanitizer
# builds suppress OSMesa/LLVM's process-lifetime allocations.
set(TILESORT_ENV "LP_NUM_THREADS=0")
if(TESSERA_SANITIZE)
  list(APPEND TILESORT_ENV "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp:print_suppressions=0:use_tls=0")
endif()
set_tests_properties(${TILESORT_TESTS_AFTER} PROPERTIES
  TIMEOUT 240 LABELS tilesort FAIL_REGULAR_EXPRESSION "FAIL:" ENVIRONMENT "${TILESORT_ENV}")
# two 15-frame runs (1x1 and sixteen servers), slower under the sanitizers
set_tests_properties(tilesort_cut_primitive_is_not_broadcast_4x4 PROPERTIES TIMEOUT 600)
# The wall graphs: four crops and five PNG comparisons per frame for 20
# frames, each a sanitized process: on a loaded two-core machine 200 s and
# more (the runs themselves 23-31 s).
if(TARGET tiles_driver)
  set_tests_properties(tilesort_wall_graph_tiles_and_assembled_window_exact
                       tilesort_wall_display_node_assembles_exact_window PROPERTIES TIMEOUT 480)
endif()
