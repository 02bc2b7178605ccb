# tests/render.cmake — images, imgdiff, the render SPU and the examples'
# accuracy: every example rendered through a chain must be bit-identical
# to the same program drawn by OSMesa directly.
get_property(RENDER_TESTS_BEFORE DIRECTORY PROPERTY TESTS)
set(RENDER_TEST_DIR ${CMAKE_CURRENT_SOURCE_DIR}/render)
set(RENDER_OUT ${CMAKE_BINARY_DIR}/test-out/render)
set(TESSERA_BIN $<TARGET_FILE:tessera_cli>)
file(MAKE_DIRECTORY ${RENDER_OUT})

# --- tsr_image ----------------------------------------------------------------
add_executable(image_test ${RENDER_TEST_DIR}/image_test.c)
target_link_libraries(image_test PRIVATE tessera PkgConfig::PNG m)
set(IMAGE_OUT ${RENDER_OUT}/image)
file(MAKE_DIRECTORY ${IMAGE_OUT})
add_test(NAME image_png_roundtrip_keeps_rgba_and_bottom_up_rows
         COMMAND image_test roundtrip ${IMAGE_OUT})
add_test(NAME image_reads_grey_palette_16bit_alpha_as_rgba8
         COMMAND image_test convert ${IMAGE_OUT})
add_test(NAME image_compare_counts_pixels_beyond_tolerance_and_psnr
         COMMAND image_test compare)
add_test(NAME image_flip_rows_mirrors_wide_rows COMMAND image_test flip)
add_test(NAME image_rgb_png_drops_alpha_keeps_colour
         COMMAND image_test rgb ${IMAGE_OUT})
# render's PNGs are what a window shows (RGB) unless output_alpha=1;
# the examples' --out-alpha likewise
add_test(NAME render_png_rgb_by_default_alpha_on_request
         COMMAND ${RENDER_TEST_DIR}/png_channels.sh ${CMAKE_BINARY_DIR}/bin $<TARGET_FILE:image_test>
                 ${RENDER_OUT}/png-channels)
add_test(NAME image_errors_name_the_file_and_libpng_problem
         COMMAND image_test errors ${IMAGE_OUT})
add_test(NAME image_frame_pattern_allows_only_one_int_conversion
         COMMAND image_test frame-path)

# --- tessera imgdiff ----------------------------------------------------------
set(IMGDIFF_OUT ${RENDER_OUT}/imgdiff)
file(MAKE_DIRECTORY ${IMGDIFF_OUT})
add_test(NAME imgdiff_fixtures COMMAND image_test fixtures ${IMGDIFF_OUT})
set_tests_properties(imgdiff_fixtures PROPERTIES FIXTURES_SETUP imgdiff_pngs)
set(EXPECT ${RENDER_TEST_DIR}/expect.sh)
macro(imgdiff_test name rc out_re err_re)
  add_test(NAME ${name} COMMAND ${EXPECT} ${rc} "${out_re}" "${err_re}"
           ${TESSERA_BIN} imgdiff ${ARGN})
  set_tests_properties(${name} PROPERTIES FIXTURES_REQUIRED imgdiff_pngs)
endmacro()
imgdiff_test(imgdiff_identical_images_exit_0 0
  "^differing_pixels: 0$" ""
  ${IMGDIFF_OUT}/base.png ${IMGDIFF_OUT}/base_copy.png)
imgdiff_test(imgdiff_identical_images_report_psnr_inf 0 "^psnr_db: inf$" ""
  ${IMGDIFF_OUT}/base.png ${IMGDIFF_OUT}/base_copy.png)
imgdiff_test(imgdiff_one_pixel_off_exit_1 1 "^differing_pixels: 1$" ""
  ${IMGDIFF_OUT}/base.png ${IMGDIFF_OUT}/one_pixel_off.png)
imgdiff_test(imgdiff_one_pixel_off_reports_max_channel_error_3 1 "^max_channel_error: 3$" ""
  ${IMGDIFF_OUT}/base.png ${IMGDIFF_OUT}/one_pixel_off.png)
imgdiff_test(imgdiff_within_tolerance_exit_0 0 "^differing_pixels: 0$" ""
  ${IMGDIFF_OUT}/base.png ${IMGDIFF_OUT}/one_pixel_off.png --tolerance 3)
imgdiff_test(imgdiff_just_beyond_tolerance_exit_1 1 "^differing_pixels: 1$" ""
  ${IMGDIFF_OUT}/base.png ${IMGDIFF_OUT}/one_pixel_off.png --tolerance 2)
imgdiff_test(imgdiff_size_mismatch_exit_2_names_files 2 ""
  "size mismatch: .*base.png is 48x32, .*small.png is 48x31"
  ${IMGDIFF_OUT}/base.png ${IMGDIFF_OUT}/small.png)
imgdiff_test(imgdiff_missing_file_exit_2_names_file 2 "" "no-such-file.png: No such file"
  ${IMGDIFF_OUT}/base.png ${IMGDIFF_OUT}/no-such-file.png)
imgdiff_test(imgdiff_not_png_exit_2_names_file 2 "" "not_png.png: not a PNG file"
  ${IMGDIFF_OUT}/not_png.png ${IMGDIFF_OUT}/base.png)
imgdiff_test(imgdiff_bad_tolerance_exit_2 2 "" "bad --tolerance '256'"
  ${IMGDIFF_OUT}/base.png ${IMGDIFF_OUT}/base.png --tolerance 256)
imgdiff_test(imgdiff_one_file_is_usage_error 2 "" "expected two PNG files"
  ${IMGDIFF_OUT}/base.png)
imgdiff_test(imgdiff_help_exit_0 0 "usage: tessera imgdiff A.png B.png \\[--tolerance N\\]" ""
  --help)

# --- the render SPU -----------------------------------------------------------
add_test(NAME render_spu_has_no_gl_imports
         COMMAND ${RENDER_TEST_DIR}/no_gl_imports.sh $<TARGET_FILE:spu_render>)

set(SPHERES_BIN $<TARGET_FILE:spheres>)
macro(render_rejects name err_re chain)
  add_test(NAME ${name} COMMAND ${EXPECT} 1 "" "${err_re}"
           ${SPHERES_BIN} --frames 1 --chain "${chain}")
endmacro()
render_rejects(render_rejects_missing_output_directory
  "render.*no/such/dir.*No such file or directory"
  "render output=${RENDER_OUT}/no/such/dir/f-%d.png")
render_rejects(render_rejects_output_directory_that_is_a_file
  "render.*is not a directory"
  "render output=${RENDER_TEST_DIR}/expect.sh/f-%d.png")
render_rejects(render_rejects_output_pattern_with_string_conversion
  "render.*bad file pattern 'f-%s.png'"
  "render output=f-%s.png")
render_rejects(render_rejects_negative_width "render.*width.*-4" "render width=-4 height=10")
render_rejects(render_rejects_width_without_height "render.*width=64 and height=0"
  "render width=64")
render_rejects(render_rejects_unknown_option "render.*colour" "render colour=red")
render_rejects(render_rejects_bad_tiles_naming_the_tile
  "render.*option tiles=0:0:8:8,0:0:-5:3: tile 2 '0:0:-5:3': width must be 1..16384"
  "render tiles=0:0:8:8,0:0:-5:3")
render_rejects(render_rejects_tiles_not_in_x_y_w_h_form
  "render.*tile 1 '1:2:3': expected X:Y:W:H" "render tiles=1:2:3")

add_test(NAME render_fixed_size_option_overrides_window_size
  COMMAND ${RENDER_TEST_DIR}/render_options.sh fixed-size ${SPHERES_BIN}
          $<TARGET_FILE:image_test> ${RENDER_OUT}/fixed-size)
add_test(NAME render_window_option_ignores_other_windows_swaps
  COMMAND ${RENDER_TEST_DIR}/render_options.sh other-window ${SPHERES_BIN}
          ${RENDER_OUT}/other-window)

add_test(NAME examples_take_chain_from_TESSERA_CHAIN_unless_chain_option
  COMMAND ${RENDER_TEST_DIR}/render_options.sh env-chain ${SPHERES_BIN}
          ${RENDER_OUT}/env-chain)
add_test(NAME examples_default_chain_renders_into_out_dir
  COMMAND ${RENDER_TEST_DIR}/render_options.sh default-chain ${SPHERES_BIN}
          ${RENDER_OUT}/default-chain)

add_test(NAME examples_reject_unknown_option_exit_2
  COMMAND ${EXPECT} 2 "" "spheres: unknown option .*--bogus" ${SPHERES_BIN} --bogus)
add_test(NAME examples_native_reject_bad_size_exit_2
  COMMAND ${EXPECT} 2 "" "isosurface: bad --size .*10by10"
          $<TARGET_FILE:isosurface-native> --size 10by10)
add_test(NAME examples_isosurface_rejects_bad_orbit_exit_2
  COMMAND ${EXPECT} 2 "" "isosurface: bad --orbit \\(expected a number in -360..360\\): 400"
          $<TARGET_FILE:isosurface-native> --orbit 400)
add_test(NAME examples_reject_bad_out_pattern_exit_2
  COMMAND ${EXPECT} 2 "" "bad file pattern 'x-%s.png'"
          $<TARGET_FILE:texquads-native> --out x-%s.png)

add_executable(render_driver ${RENDER_TEST_DIR}/render_driver.c)
target_link_libraries(render_driver PRIVATE tessera_gl tessera Threads::Threads)
add_test(NAME render_two_instances_on_two_threads_render_independently
  COMMAND ${RENDER_TEST_DIR}/two_chains.sh $<TARGET_FILE:render_driver> ${TESSERA_BIN}
          ${RENDER_OUT}/two_chains 3)
add_test(NAME render_without_window_commands_draws_512_square
  COMMAND sh -c "rm -f \"$2\" && \"$0\" no-window \"$1\" && \"$3\" expect-size \"$2\" 512 512"
          $<TARGET_FILE:render_driver> ${RENDER_OUT}/no-window-%d.png
          ${RENDER_OUT}/no-window-0.png $<TARGET_FILE:image_test>)

# render's fast DrawPixels (spus/render/drawpixels.c): every case equal to
# glDrawPixels byte for byte, taken exactly where the state allows it.
add_executable(drawpixels_driver ${RENDER_TEST_DIR}/drawpixels_driver.c)
target_link_libraries(drawpixels_driver PRIVATE tessera_gl tessera)
foreach(mode solo shared)
  add_test(NAME render_fast_drawpixels_equals_gldrawpixels_${mode}
    COMMAND ${RENDER_TEST_DIR}/drawpixels.sh $<TARGET_FILE:drawpixels_driver> ${TESSERA_BIN}
            ${RENDER_OUT}/drawpixels-${mode} ${mode})
endforeach()

# render's depth clears that also clear a never-used stencil (render.c,
# render_Clear): colour, depth and stencil read-backs equal OSMesa's own,
# before and after the stencil test writes, alone and in shared mode.
add_executable(render_stencil_clear ${RENDER_TEST_DIR}/stencil_clear_driver.c)
target_link_libraries(render_stencil_clear PRIVATE tessera_gl tessera)
add_executable(render_stencil_clear_native ${RENDER_TEST_DIR}/stencil_clear_driver.c)
target_compile_definitions(render_stencil_clear_native PRIVATE STENCIL_NATIVE)
target_link_libraries(render_stencil_clear_native PRIVATE PkgConfig::OSMESA)
foreach(mode solo shared)
  add_test(NAME render_depth_clears_keep_the_stencil_exactly_as_osmesa_${mode}
    COMMAND sh -c "mkdir -p \"$2\" && \"$0\" native \"$2/native.raw\" && \"$1\" ${mode} \"$2/render.raw\" && cmp \"$2/native.raw\" \"$2/render.raw\""
            $<TARGET_FILE:render_stencil_clear_native> $<TARGET_FILE:render_stencil_clear> ${RENDER_OUT}/stencil-${mode})
endforeach()

# OSMesa alone, no tessera: the llvmpipe behaviour behind engine's known
# wall inexactness (quad_diagonal_test.c; tests/faker/sweep_exact.sh). Fails
# when llvmpipe stops cutting a quad by what else its draw holds.
add_executable(render_llvmpipe_quad_diagonal ${RENDER_TEST_DIR}/quad_diagonal_test.c)
target_link_libraries(render_llvmpipe_quad_diagonal PRIVATE PkgConfig::OSMESA)
add_test(NAME render_llvmpipe_cuts_a_quad_by_what_else_its_draw_holds
         COMMAND $<TARGET_FILE:render_llvmpipe_quad_diagonal>)

# --- tiles: servers that own rectangles of the window ---------------------------
# Every tile PNG must equal the same pixels of the full-window render (0
# differing pixels), the scene's glGet of the scissor must give the
# application's values (tiles_driver.c says what the scene holds).
add_executable(tiles_driver ${RENDER_TEST_DIR}/tiles_driver.c)
target_link_libraries(tiles_driver PRIVATE tessera_gl tessera)
set(TILES_OUT ${RENDER_OUT}/tiles)
macro(tiles_test name dir)
  add_test(NAME ${name} COMMAND sh -c "rm -rf \"$1\" && mkdir -p \"$1\" && exec \"$0\" compare \"$@\""
           $<TARGET_FILE:tiles_driver> ${TILES_OUT}/${dir} ${ARGN})
  set_tests_properties(${name} PROPERTIES TIMEOUT 120)
endmacro()
# 2x2 on four servers (odd size: the tile borders are not centred).
tiles_test(render_tiles_2x2_four_servers_bit_exact_vs_full_window 2x2 301x227 2
  0:0:150:113 150:0:151:113 0:113:150:114 150:113:151:114)
# The same tiles given as the `tiles` option (what the mothership does).
tiles_test(render_tiles_option_2x2_bit_exact_vs_full_window option 301x227 2 --option
  0:0:150:113 150:0:151:113 0:113:150:114 150:113:151:114)
# Two tiles on one server (diagonal: the bounding rectangle is the whole
# window, the PNGs are -t0 and -t1), and the other two on another.
tiles_test(render_tiles_two_per_server_bit_exact_vs_full_window two-per-server 256x192 2
  0:0:128:96,128:96:128:96 128:0:128:96,0:96:128:96)
# The tiles change between frames (load balancing re-splits): one tile,
# then two, then another split, then the whole window (count 0); and a
# server that starts without tiles and gets them after its first frame.
tiles_test(render_tiles_change_between_frames_bit_exact change 240x180 4
  0:0:100:180/0:0:100:90,100:0:140:180/0:0:61:180/-
  100:0:140:180/0:90:100:90/61:0:179:180/-
  -/0:0:120:180/-/120:0:120:180)
# Through the wire format (loopback SPU): TilesTSR packed and unpacked, the
# scissor queries answered across it.
tiles_test(render_tiles_tilestsr_through_wire_bit_exact loopback 200x150 2 --loopback
  0:0:100:75 100:0:100:75 0:75:100:75,100:75:100:75/0:0:200:75)
# Two contexts (two clients of a server) each with their own scissor state.
tiles_test(render_tiles_two_contexts_each_scissored_bit_exact contexts 200x150 2 --contexts
  0:0:100:75 100:0:100:75 0:75:100:75 100:75:100:75)
# 3x3 of odd sizes, and a tile at the window's corner.
tiles_test(render_tiles_3x3_odd_sizes_bit_exact 3x3 250x190 1
  0:0:83:63 83:0:84:63 167:0:83:63 0:63:83:64 83:63:84:64 167:63:83:64
  0:127:83:63 83:127:84:63 167:127:83:63)

# The tile list text (tessera/tiles.h), both forms, and its errors.
add_test(NAME tiles_text_parses_both_forms_and_names_bad_tiles COMMAND tiles_driver parse)

# Pages outside a server's tiles never become resident (VmRSS).
add_test(NAME render_tile_server_leaves_pages_outside_its_tile_unused
  COMMAND ${RENDER_TEST_DIR}/tile_memory.sh $<TARGET_FILE:tiles_driver>)
set_tests_properties(render_tile_server_leaves_pages_outside_its_tile_unused PROPERTIES TIMEOUT 120)

# Through the mothership: a graph's `tiles:` reach the servers' render SPUs.
if(TARGET spu_replicate)
  add_test(NAME render_tiles_from_graph_nodes_bit_exact_vs_native
    COMMAND ${RENDER_TEST_DIR}/tiles_graph.sh ${CMAKE_BINARY_DIR}/bin
            ${RENDER_TEST_DIR}/tiles_graph.yaml ${TILES_OUT}/graph $<TARGET_FILE:tiles_driver>)
  set_tests_properties(render_tiles_from_graph_nodes_bit_exact_vs_native PROPERTIES TIMEOUT 150)
endif()

# --- accuracy: examples through chains vs OSMesa directly -----------------------
# Frames per run: enough to exercise animation, small enough to stay fast.
set(ACCURACY_FRAMES 4)
foreach(example ${TESSERA_EXAMPLES})
  foreach(kind render print loopback)
    add_test(NAME accuracy_${example}_${kind}_bit_exact_vs_osmesa
      COMMAND ${RENDER_TEST_DIR}/accuracy.sh ${CMAKE_BINARY_DIR}/bin ${example}
              ${RENDER_OUT}/accuracy/${example}-${kind} ${ACCURACY_FRAMES} ${kind})
  endforeach()
endforeach()
# An odd window size catches row-stride and flip mistakes.
add_test(NAME accuracy_texquads_odd_size_render_bit_exact_vs_osmesa
  COMMAND ${RENDER_TEST_DIR}/accuracy.sh ${CMAKE_BINARY_DIR}/bin texquads
          ${RENDER_OUT}/accuracy/texquads-odd 2 render 333x217)
# llvmpipe bins triangles into tiles rasterized by LP_NUM_THREADS threads;
# the result must not depend on how many (measured: 0, 1, 3, 4, 8 agree).
add_test(NAME accuracy_isosurface_same_with_0_and_4_llvmpipe_threads
  COMMAND ${RENDER_TEST_DIR}/accuracy.sh ${CMAKE_BINARY_DIR}/bin isosurface
          ${RENDER_OUT}/accuracy/isosurface-threads 2 render)
set_tests_properties(accuracy_isosurface_same_with_0_and_4_llvmpipe_threads PROPERTIES
  ENVIRONMENT "ACCURACY_NATIVE_THREADS=0;ACCURACY_CHAIN_THREADS=4")

# Sanitizer builds: OSMesa/LLVM keep process-lifetime allocations that
# LeakSanitizer reports; suppress those (tests/lsan.supp), check ours.
if(TESSERA_SANITIZE)
  get_property(RENDER_TESTS_AFTER DIRECTORY PROPERTY TESTS)
  if(RENDER_TESTS_BEFORE)
    list(REMOVE_ITEM RENDER_TESTS_AFTER ${RENDER_TESTS_BEFORE})
  endif()
  set_tests_properties(${RENDER_TESTS_AFTER} PROPERTIES ENVIRONMENT
    "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp:print_suppressions=0:use_tls=0")
endif()
