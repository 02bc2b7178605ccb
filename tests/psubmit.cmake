# tests/psubmit.cmake — parallel submission into one shared-mode server
# node (server/node.h): the unpacker's yield/resume, psubmit with 1..4 rank
# processes bit-identical to psubmit-native, semaphore ordering, deadlock
# and a client leaving a barrier. Real processes, real sockets, real
# OSMesa; every test bounded. Included by tests/CMakeLists.txt.
get_property(PSUBMIT_TESTS_BEFORE DIRECTORY PROPERTY TESTS)
set(PSUBMIT_DIR ${CMAKE_CURRENT_SOURCE_DIR}/psubmit)
set(PSUBMIT_OUT ${CMAKE_BINARY_DIR}/test-out/psubmit)
set(PSUBMIT_BIN ${CMAKE_BINARY_DIR}/bin)
file(MAKE_DIRECTORY ${PSUBMIT_OUT})

add_executable(psubmit_unpack_yield ${PSUBMIT_DIR}/unpack_yield_test.c)
target_include_directories(psubmit_unpack_yield PRIVATE ${CMAKE_SOURCE_DIR}/core ${TESSERA_GEN_DIR}/src)
target_link_libraries(psubmit_unpack_yield PRIVATE tessera)
add_test(NAME psubmit_unpacker_resumes_after_yield COMMAND psubmit_unpack_yield)

add_executable(psubmit_driver ${PSUBMIT_DIR}/psubmit_driver.c)
target_link_libraries(psubmit_driver PRIVATE tessera_gl tessera)

foreach(ranks 1 2 3 4)
  add_test(NAME psubmit_${ranks}_ranks_bit_identical
    COMMAND ${PSUBMIT_DIR}/psubmit.sh accuracy ${PSUBMIT_BIN} ${PSUBMIT_OUT}/ranks${ranks} ${ranks} 3)
endforeach()
add_test(NAME psubmit_semaphore_orders_drawing
  COMMAND ${PSUBMIT_DIR}/psubmit.sh semaphore ${PSUBMIT_BIN} ${PSUBMIT_OUT}/semaphore $<TARGET_FILE:psubmit_driver>)
add_test(NAME psubmit_deadlock_names_barrier_and_semaphore
  COMMAND ${PSUBMIT_DIR}/psubmit.sh deadlock ${PSUBMIT_BIN} ${PSUBMIT_OUT}/deadlock $<TARGET_FILE:psubmit_driver>)
add_test(NAME psubmit_barrier_client_disconnects_clear_error
  COMMAND ${PSUBMIT_DIR}/psubmit.sh barrier-left ${PSUBMIT_BIN} ${PSUBMIT_OUT}/barrier-left
          $<TARGET_FILE:psubmit_driver>)
add_test(NAME psubmit_barrier_waiter_cut_named_when_another_drops
  COMMAND ${PSUBMIT_DIR}/psubmit.sh barrier-cut ${PSUBMIT_BIN} ${PSUBMIT_OUT}/barrier-cut
          $<TARGET_FILE:psubmit_driver>)
add_test(NAME psubmit_only_first_swapping_client_ends_frames
  COMMAND ${PSUBMIT_DIR}/psubmit.sh one-swapper ${PSUBMIT_BIN} ${PSUBMIT_OUT}/one-swapper
          $<TARGET_FILE:psubmit_driver>)
add_test(NAME psubmit_graph_four_apps_one_server_bit_identical
  COMMAND ${PSUBMIT_DIR}/psubmit.sh graph ${PSUBMIT_BIN} ${PSUBMIT_OUT}/graph
          ${CMAKE_SOURCE_DIR}/examples/graphs/psubmit.yaml)
add_test(NAME psubmit_node_refuses_client_marker_in_shared_mode
  COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/render/expect.sh 2 "" "needs independent mode"
          $<TARGET_FILE:tessera_cli> node --listen tcp://127.0.0.1:0 --chain "render output=c{client}-%04d.png")

get_property(PSUBMIT_TESTS_AFTER DIRECTORY PROPERTY TESTS)
if(PSUBMIT_TESTS_BEFORE)
  list(REMOVE_ITEM PSUBMIT_TESTS_AFTER ${PSUBMIT_TESTS_BEFORE})
endif()
set(PSUBMIT_ENV "")
if(TESSERA_SANITIZE)
  set(PSUBMIT_ENV "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp:print_suppressions=0:use_tls=0")
endif()
set_tests_properties(${PSUBMIT_TESTS_AFTER} PROPERTIES TIMEOUT 180 LABELS psubmit ENVIRONMENT "${PSUBMIT_ENV}")
