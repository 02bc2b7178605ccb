# tests/graph.cmake — the graph file (tessera/graph.h): the model through
# its API, `tessera check` on the example graphs and on one bad file per
# error class (tests/graph/bad/, each naming the FILE:LINE:COL it expects),
# `tessera dot` through Graphviz, and the CLI's exit codes.
set(GRAPH_TEST_DIR ${CMAKE_CURRENT_SOURCE_DIR}/graph)
set(GRAPH_EXAMPLE_DIR ${CMAKE_SOURCE_DIR}/examples/graphs)
set(GRAPH_TESSERA $<TARGET_FILE:tessera_cli>)

add_executable(graph_model_test ${GRAPH_TEST_DIR}/graph_model_test.c)
target_link_libraries(graph_model_test PRIVATE tessera_graph tessera)
foreach(t reads_nodes_chain_options_edges defaults_apply_and_nodes_override
          edges_both_ways_and_start_order exec_string_is_split_like_a_shell
          list_option_values_use_chain_text chain_builds_from_the_model
          every_truncation_fails_cleanly network_spus_are_known roles_decide_the_graph_rules)
  add_test(NAME graph_model_${t} COMMAND graph_model_test ${t})
endforeach()

# Every example graph: its structure always, and the full check (SPUs and
# options against the plugins).
file(GLOB GRAPH_EXAMPLE_FILES CONFIGURE_DEPENDS ${GRAPH_EXAMPLE_DIR}/*.yaml)
set(GRAPH_FULLY_CHECKED_EXAMPLES local trace tcp unix replicate psubmit wall)
foreach(example ${GRAPH_FULLY_CHECKED_EXAMPLES})
  add_test(NAME graph_parses_example_${example}
           COMMAND ${GRAPH_TEST_DIR}/check_ok.sh ${GRAPH_TESSERA} ${GRAPH_EXAMPLE_DIR}/${example}.yaml)
endforeach()
foreach(file ${GRAPH_EXAMPLE_FILES})
  get_filename_component(example ${file} NAME_WE)
  add_test(NAME graph_example_structure_valid_${example}
           COMMAND ${GRAPH_TEST_DIR}/check_ok.sh ${GRAPH_TESSERA} ${file} --no-spu-check)
endforeach()

file(GLOB GRAPH_BAD_FILES CONFIGURE_DEPENDS ${GRAPH_TEST_DIR}/bad/*.yaml)
foreach(file ${GRAPH_BAD_FILES})
  get_filename_component(name ${file} NAME_WE)
  add_test(NAME graph_rejects_${name}
           COMMAND ${GRAPH_TEST_DIR}/expect_error.sh ${GRAPH_TESSERA} ${file})
endforeach()

find_program(GRAPH_DOT_PROGRAM dot)
if(GRAPH_DOT_PROGRAM)
  foreach(file ${GRAPH_EXAMPLE_FILES})
    get_filename_component(example ${file} NAME_WE)
    add_test(NAME graph_dot_output_is_valid_${example}
             COMMAND ${GRAPH_TEST_DIR}/dot_valid.sh ${GRAPH_TESSERA} ${GRAPH_DOT_PROGRAM} ${file}
                     --no-spu-check)
  endforeach()
else()
  message(STATUS "graphviz 'dot' not found: graph_dot_output_is_valid_* tests not added")
endif()

add_test(NAME graph_cli_exit_codes
         COMMAND ${GRAPH_TEST_DIR}/cli_exit_codes.sh ${GRAPH_TESSERA}
                 ${GRAPH_EXAMPLE_DIR}/local.yaml ${GRAPH_TEST_DIR}/bad/unknown_node_key.yaml)

# The CLI finds plugins in the build tree; make sure they are built.
add_dependencies(graph_model_test spu_passthrough spu_render spu_pack spu_replicate spu_tilesort
  spu_readback)
