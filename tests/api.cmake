# tests/api.cmake — the installed developer API (issue 9, item 3): an
# install of this build into a prefix (fixture api_install), then
#  * api_headers_self_contained: every installed header compiles alone,
#    includes only installed headers, by path;
#  * api_exports_match_headers: libtessera, libtessera_client,
#    libtessera_graph, libtessera_gl and libtessera_net export exactly what
#    the installed headers declare (nm -D against the headers' declarations);
#  * api_pkgconfig_libraries: tessera.pc lists libtessera_client,
#    tessera-graph.pc the graph model, and only the graph model links libyaml.
# The out-of-tree template SPU is spu_template_out_of_tree (tests/spu.cmake).
set(API_TEST_SCRIPT ${CMAKE_CURRENT_SOURCE_DIR}/api/check_api.sh)
set(API_PREFIX ${CMAKE_CURRENT_BINARY_DIR}/api/prefix)
file(MAKE_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR}/api)
set(API_EXTRA_CFLAGS "")
if(TESSERA_SANITIZE)
  set(API_EXTRA_CFLAGS "-fsanitize=address,undefined -fno-omit-frame-pointer")
endif()

add_test(NAME api_install
  COMMAND sh ${API_TEST_SCRIPT} install ${CMAKE_COMMAND} ${CMAKE_BINARY_DIR} ${API_PREFIX})
set_tests_properties(api_install PROPERTIES FIXTURES_SETUP api_prefix TIMEOUT 120)

add_test(NAME api_headers_self_contained
  COMMAND sh ${API_TEST_SCRIPT} headers ${API_PREFIX} ${CMAKE_C_COMPILER})

# The declarations are read with GCC's -aux-info (any GCC: only the
# headers are compiled).
if(CMAKE_C_COMPILER_ID STREQUAL "GNU")
  set(API_GCC ${CMAKE_C_COMPILER})
else()
  find_program(API_GCC NAMES gcc)
endif()
if(API_GCC)
  add_test(NAME api_exports_match_headers
    COMMAND sh ${API_TEST_SCRIPT} exports ${API_PREFIX} ${API_GCC})
endif()

add_test(NAME api_pkgconfig_libraries
  COMMAND sh ${API_TEST_SCRIPT} pkgconfig ${API_PREFIX} ${CMAKE_C_COMPILER} "${API_EXTRA_CFLAGS}")

foreach(t api_headers_self_contained api_exports_match_headers api_pkgconfig_libraries)
  if(TEST ${t})
    set_tests_properties(${t} PROPERTIES FIXTURES_REQUIRED api_prefix TIMEOUT 120)
  endif()
endforeach()
