# tests/format.cmake — the tracked C sources and headers match the
# repository's .clang-format: scripts/format --check lists the files that
# drift and fails (scripts/format rewrites them). Needs clang-format 14
# (scripts/setup-debian installs it). Included by tests/CMakeLists.txt.
add_test(NAME format_tree_matches_clang_format COMMAND ${CMAKE_SOURCE_DIR}/scripts/format --check)
set_tests_properties(format_tree_matches_clang_format PROPERTIES TIMEOUT 300 LABELS format)
