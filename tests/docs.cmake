# The documentation's own tests (tests/docs/).
#
# docs_PAGE_shell_blocks_run: every ```sh / ```bash / ```console block of
# README.md and docs/PAGE.md runs in a scratch folder that looks like the
# repository root, exits 0 and writes the files it names; a block that
# cannot run here is skipped by a documented tag and listed
# (tests/docs/run_blocks.sh says how). One test per page, so they run in
# parallel. Pages whose blocks open X windows get a private Xvfb; pages
# whose blocks listen on fixed ports share a lock.
#
# docs_tracked_files_point_nowhere_outside: no tracked file names a path
# of the developers' machines or a link that leaves the repository.
set(DOCS_TEST_DIR ${CMAKE_CURRENT_SOURCE_DIR}/docs)

function(tessera_docs_page_test page)
  cmake_parse_arguments(DOC "XVFB" "LOCK" "" ${ARGN})
  get_filename_component(stem ${page} NAME_WE)
  string(TOLOWER ${stem} stem)
  set(name docs_${stem}_shell_blocks_run)
  set(args)
  set(locks)
  if(DOC_XVFB)
    set(args --xvfb)
    list(APPEND locks xvfb)
  endif()
  if(DOC_LOCK)
    list(APPEND locks ${DOC_LOCK})
  endif()
  add_test(NAME ${name}
           COMMAND bash ${DOCS_TEST_DIR}/run_blocks.sh ${args}
                   ${CMAKE_SOURCE_DIR} ${CMAKE_BINARY_DIR} ${CMAKE_SOURCE_DIR}/${page})
  set_tests_properties(${name} PROPERTIES TIMEOUT 300 LABELS docs)
  if(locks)
    set_tests_properties(${name} PROPERTIES RESOURCE_LOCK "${locks}")
  endif()
endfunction()

tessera_docs_page_test(README.md XVFB LOCK port_7000)
tessera_docs_page_test(docs/graphs.md)
tessera_docs_page_test(docs/walls.md LOCK port_7100)
tessera_docs_page_test(docs/sortlast.md)
tessera_docs_page_test(docs/faker.md XVFB)
tessera_docs_page_test(docs/capture.md XVFB)
tessera_docs_page_test(docs/network.md)
tessera_docs_page_test(docs/security.md)
tessera_docs_page_test(docs/render.md XVFB)
tessera_docs_page_test(docs/limits.md)
tessera_docs_page_test(docs/architecture.md)

# A page of docs/ not listed above is tested too (no X, no lock), so a new
# page's examples cannot drift before someone lists it.
file(GLOB docs_pages RELATIVE ${CMAKE_SOURCE_DIR} ${CMAKE_SOURCE_DIR}/docs/*.md)
foreach(page ${docs_pages})
  get_filename_component(stem ${page} NAME_WE)
  string(TOLOWER ${stem} stem)
  if(NOT TEST docs_${stem}_shell_blocks_run)
    tessera_docs_page_test(${page})
  endif()
endforeach()

add_test(NAME docs_tracked_files_point_nowhere_outside
         COMMAND bash ${DOCS_TEST_DIR}/no_outside_pointers.sh ${CMAKE_SOURCE_DIR})
set_tests_properties(docs_tracked_files_point_nowhere_outside PROPERTIES TIMEOUT 120 LABELS docs)
