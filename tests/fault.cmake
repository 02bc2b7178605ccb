# tests/fault.cmake — the fault matrix (issue 10, item 13): one test per
# cell, fault_GRAPH_TARGET_FAULT. Faults: sigkill, sigstop, sigterm and
# close (the target's connections shut down from outside); targets: the
# application, every kind of server the graph has (render server, replicate
# target, render tile server, readback tile server, display) and the
# mothership (the `tessera run` process); graphs: small-window copies of
# examples/graphs/ tcp, replicate, wall, wall_display, sortlast and
# sortlast_servers (tests/fault/*.yaml, same topology; the sort-last ones
# are named after their SPU, binaryswap and binaryswap_servers, and fault
# a peer, the display and the application), and faker_tcp and
# faker_wall: tcp and wall with an unmodified glxgears as the app. tests/fault/fault_cell_test.c
# runs one cell and says what it checks. Cells share no port (every server
# listens on port 0, the sort-last graphs use unix sockets in the cell's
# own TMPDIR) and no file (one output folder each), so they run in
# parallel.
#
# Plain build only: the matrix counts in issue 10's CI minutes, and the
# sanitizer build runs the same code paths in tests/run.cmake's failure
# tests, plus four glxgears cells for the faker's side of a fault.
# -DTESSERA_FAULT_MATRIX=ON adds it all to a sanitizer build.
# Included by tests/CMakeLists.txt.
get_property(FAULT_TESTS_BEFORE DIRECTORY PROPERTY TESTS)
set(FAULT_DIR ${CMAKE_CURRENT_SOURCE_DIR}/fault)
set(FAULT_OUT ${CMAKE_BINARY_DIR}/test-out/fault)
file(MAKE_DIRECTORY ${FAULT_OUT})

# Found by the matrix, in every build: the matrix's wall_display graph
# (64x48 tiles) hung before its first window, because a tile server that
# never swaps left its frame barrier in an unflushed wire buffer.
if(TARGET spu_readback)
  add_test(NAME readback_small_tiles_frame_barrier_reaches_display_exact
    COMMAND ${FAULT_DIR}/small_tiles.sh ${CMAKE_BINARY_DIR}/bin ${FAULT_DIR}/wall_display.yaml
            ${FAULT_OUT}/small-tiles 20)
endif()

add_executable(fault_cell ${FAULT_DIR}/fault_cell_test.c)
target_link_libraries(fault_cell PRIVATE tessera)

# The run's time-out: a SIGSTOPped node or application is found after this
# much silence (a stopped mothership after 3 x this, by its nodes).
set(FAULT_TIMEOUT_MS 1500)
set(FAULTS sigkill sigstop sigterm close)
set(FAULT_TCP_READY out/tcp-000002.png)

# An unmodified program as the app (issue 12, item 6): glxgears under the
# faker over TCP and on the 2x2 wall (tests/fault/faker_*.yaml), each cell
# under its own Xvfb (tests/fault/xvfb_cell.sh), with the same checks as
# the graphs below. The application is then the faker in glxgears'
# process: its stream client, the X connections it keeps, its end on a
# signal. faker_fault_cells(GRAPH KIND TARGET "FAULTS" READY...).
function(faker_fault_cells graph kind target faults)
  if(NOT TARGET tessera_faker_gl)
    return()
  endif()
  foreach(fault ${faults})
    set(name fault_${graph}_${kind}_${fault})
    add_test(NAME ${name}
      COMMAND bash ${FAULT_DIR}/xvfb_cell.sh ${FAULT_OUT}/${name} $<TARGET_FILE:fault_cell>
              $<TARGET_FILE:tessera_cli> ${FAULT_DIR}/${graph}.yaml ${FAULT_OUT}/${name}
              ${target} ${fault} ${FAULT_TIMEOUT_MS} ${ARGN})
    set_tests_properties(${name} PROPERTIES SKIP_RETURN_CODE 77)
  endforeach()
endfunction()

if(NOT TESSERA_SANITIZE OR TESSERA_FAULT_MATRIX)

# fault_cells(GRAPH KIND TARGET READY...): the four faults on TARGET
# (mothership, application or a node's name) of tests/fault/GRAPH.yaml,
# named fault_GRAPH_KIND_FAULT; READY: files that show frames flow.
function(fault_cells graph kind target)
  set(faults ${FAULTS})
  if(FAULT_CELLS_WITHOUT)
    list(REMOVE_ITEM faults ${FAULT_CELLS_WITHOUT})
  endif()
  foreach(fault ${faults})
    set(name fault_${graph}_${kind}_${fault})
    add_test(NAME ${name}
      COMMAND fault_cell $<TARGET_FILE:tessera_cli> ${FAULT_DIR}/${graph}.yaml ${FAULT_OUT}/${name}
              ${target} ${fault} ${FAULT_TIMEOUT_MS} ${ARGN})
  endforeach()
endfunction()

fault_cells(tcp app application ${FAULT_TCP_READY})
fault_cells(tcp server server ${FAULT_TCP_READY})
fault_cells(tcp mothership mothership ${FAULT_TCP_READY})

if(TARGET spu_replicate)
  set(FAULT_REPLICATE_READY out/replicate-s0-000002.png out/replicate-s1-000002.png out/replicate-s2-000002.png)
  fault_cells(replicate app application ${FAULT_REPLICATE_READY})
  fault_cells(replicate target s1 ${FAULT_REPLICATE_READY})
  fault_cells(replicate mothership mothership ${FAULT_REPLICATE_READY})
endif()

if(TARGET spu_tilesort)
  # The assembled window: every tile server has drawn its part.
  fault_cells(wall app application out/wall-000002.png)
  fault_cells(wall tileserver wall10 out/wall-000002.png)
  fault_cells(wall mothership mothership out/wall-000002.png)
  if(TARGET spu_readback)
    # The display's window: every readback tile server streams to it.
    fault_cells(wall_display app application out/wall-000002.png)
    fault_cells(wall_display readback wall00 out/wall-000002.png)
    fault_cells(wall_display display display out/wall-000002.png)
    fault_cells(wall_display mothership mothership out/wall-000002.png)
  endif()
endif()

if(TARGET spu_binaryswap)
  # Sort-last (issue 11, item 10), both forms. In situ the application is
  # a peer (binaryswap runs in its process); with servers the peer is a
  # render server whose chain is binaryswap. The display's window: every
  # peer has composited into it.
  # fault_binaryswap_app_sigstop (a stopped in-situ peer): the display drops
  # its silent stream after the time-out and its node reports that at once
  # (a STATS with failure=), while the other peers would wait binaryswap's
  # timeout_ms (10 s) for the stopped one: the verdict names the stopped
  # peer, not their exits.
  fault_cells(binaryswap app application out/binaryswap-000002.png)
  fault_cells(binaryswap display display out/binaryswap-000002.png)
  fault_cells(binaryswap_servers app application out/binaryswap-000002.png)
  fault_cells(binaryswap_servers peer peer1 out/binaryswap-000002.png)
  fault_cells(binaryswap_servers display display out/binaryswap-000002.png)
endif()

# The faker's graphs, every cell (about 30 s at -j2).
faker_fault_cells(faker_tcp app application "${FAULTS}" ${FAULT_TCP_READY})
faker_fault_cells(faker_tcp server server "${FAULTS}" ${FAULT_TCP_READY})
faker_fault_cells(faker_tcp mothership mothership "${FAULTS}" ${FAULT_TCP_READY})
if(TARGET spu_tilesort)
  faker_fault_cells(faker_wall app application "${FAULTS}" out/wall-000002.png)
  faker_fault_cells(faker_wall tileserver wall10 "${FAULTS}" out/wall-000002.png)
  faker_fault_cells(faker_wall mothership mothership "${FAULTS}" out/wall-000002.png)
endif()

else()
  # Sanitizer builds: the faker's own side of a fault, instrumented (the
  # rest of the matrix runs the same node and mothership code as above):
  # its stream client cut under it (server killed, tile server's sockets
  # shut down), its sockets shut down in the program, and its end on
  # SIGTERM; about 15 s at -j2.
  faker_fault_cells(faker_tcp server server sigkill ${FAULT_TCP_READY})
  faker_fault_cells(faker_tcp app application close ${FAULT_TCP_READY})
  if(TARGET spu_tilesort)
    faker_fault_cells(faker_wall tileserver wall10 close out/wall-000002.png)
    faker_fault_cells(faker_wall app application sigterm out/wall-000002.png)
  endif()
endif() # the matrix

get_property(FAULT_TESTS_AFTER DIRECTORY PROPERTY TESTS)
if(FAULT_TESTS_BEFORE)
  list(REMOVE_ITEM FAULT_TESTS_AFTER ${FAULT_TESTS_BEFORE})
endif()
# One llvmpipe thread per renderer: two cells at once on two cores.
set(FAULT_ENV "LP_NUM_THREADS=0")
if(TESSERA_SANITIZE)
  # glxgears is not instrumented but loads the instrumented faker
  # (tests/faker.cmake's FAKER_PRELOAD; xvfb_cell.sh preloads it).
  list(APPEND FAULT_ENV "FAKER_PRELOAD=${FAKER_PRELOAD}")
  list(APPEND FAULT_ENV "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp:print_suppressions=0:use_tls=0")
endif()
set_tests_properties(${FAULT_TESTS_AFTER} PROPERTIES TIMEOUT 90 LABELS fault ENVIRONMENT "${FAULT_ENV}")
