# tests/format.cmake — the tracked C sources and headers match the
# repository's .clang-format: scripts/format --check lists the files that
# drift and fails (scripts/format rewrites them). Needs clang-format 14
# (scripts/setup-debian installs it). Included by tests/CMakeLists.txt.
add_test(NAME format_tree_matches_clang_format COMMAND ${CMAKE_SOURCE_DIR}/scripts/format --check)
set_tests_properties(format_tree_matches_clang_format PROPERTIES TIMEOUT 300 LABELS format)

# A file per job: no tracked C source or header over
# 1,000 lines outside tests/, bench/, examples/ and generated code. The
# script prints every offender with its line count and how many files it
# counted.
add_test(NAME tree_source_files_at_most_1000_lines
         COMMAND bash ${CMAKE_SOURCE_DIR}/tests/format/file_sizes.sh ${CMAKE_SOURCE_DIR})
set_tests_properties(tree_source_files_at_most_1000_lines PROPERTIES TIMEOUT 60 LABELS format)

# No folder includes another folder's private header: a header used across
# folders is installed (include/tessera/) or moved. The script lists the
# few internal static libraries' interfaces it allows, with their reasons,
# and every offender.
add_test(NAME tree_private_headers_stay_in_their_folder
         COMMAND bash ${CMAKE_SOURCE_DIR}/tests/format/private_headers.sh ${CMAKE_SOURCE_DIR})
set_tests_properties(tree_private_headers_stay_in_their_folder PROPERTIES TIMEOUT 120 LABELS format)
