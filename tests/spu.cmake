# SPU framework tests (tests/spu/): typed options, the plugin loader, chains
# and inheritance, two instances in one process, `tessera spus`, and the
# template SPU built out of tree against an install of this build.
set(SPU_TEST_SRC ${CMAKE_CURRENT_SOURCE_DIR}/spu)
set(SPU_TEST_ENV_DIR ${CMAKE_CURRENT_BINARY_DIR}/spu_env)           # a second passthrough
set(SPU_TEST_BAD_DIR ${CMAKE_CURRENT_BINARY_DIR}/spu_bad)           # broken plugins
set(SPU_TEST_TEMPLATE_DIR ${CMAKE_CURRENT_BINARY_DIR}/spu_template) # template, built in tree

# Options: the parser is internal to libtessera, so it is compiled in.
add_executable(spu_options_test ${SPU_TEST_SRC}/options_test.c
  ${CMAKE_SOURCE_DIR}/core/spu/options.c ${CMAKE_SOURCE_DIR}/core/util/names.c ${CMAKE_SOURCE_DIR}/core/util/error.c
  ${CMAKE_SOURCE_DIR}/core/util/log.c)
target_include_directories(spu_options_test PRIVATE ${CMAKE_SOURCE_DIR}/include
  ${CMAKE_SOURCE_DIR}/core/spu)
target_link_libraries(spu_options_test PRIVATE Threads::Threads m)
foreach(t bool int_range int_rejects_junk_and_overflow float_range float_rejects_nan_and_inf
          string enum int_list float_list string_list defaults did_you_mean given_twice
          bad_default_is_class_error subclass_overrides_super accessor_wrong_type_returns_zero)
  add_test(NAME spu_options_parse_${t} COMMAND spu_options_test spu_options_parse_${t})
endforeach()

# Real plugin files for the loader tests.
function(tessera_spu_test_plugin target source variant dir file)
  add_library(${target} MODULE ${source})
  if(variant)
    target_compile_definitions(${target} PRIVATE ${variant})
  endif()
  target_link_libraries(${target} PRIVATE tessera)
  set_target_properties(${target} PROPERTIES PREFIX "" OUTPUT_NAME ${file}
    LIBRARY_OUTPUT_DIRECTORY ${dir} C_VISIBILITY_PRESET hidden)
endfunction()
tessera_spu_test_plugin(spu_test_shadow ${SPU_TEST_SRC}/test_plugins.c TEST_PLUGIN_SHADOW
  ${SPU_TEST_ENV_DIR} passthrough_spu)
tessera_spu_test_plugin(spu_test_noentry ${SPU_TEST_SRC}/test_plugins.c TEST_PLUGIN_NO_ENTRY
  ${SPU_TEST_BAD_DIR} noentry_spu)
tessera_spu_test_plugin(spu_test_oldabi ${SPU_TEST_SRC}/test_plugins.c TEST_PLUGIN_OLD_ABI
  ${SPU_TEST_BAD_DIR} oldabi_spu)
tessera_spu_test_plugin(spu_test_misnamed ${SPU_TEST_SRC}/test_plugins.c TEST_PLUGIN_MISNAMED
  ${SPU_TEST_BAD_DIR} misnamed_spu)
tessera_spu_test_plugin(spu_test_prevabi ${SPU_TEST_SRC}/test_plugins.c TEST_PLUGIN_PREVIOUS_ABI
  ${SPU_TEST_BAD_DIR} prevabi_spu)
tessera_spu_test_plugin(spu_test_template ${CMAKE_SOURCE_DIR}/spus/template/template.c ""
  ${SPU_TEST_TEMPLATE_DIR} template_spu)

add_executable(spu_loader_test ${SPU_TEST_SRC}/loader_test.c)
target_link_libraries(spu_loader_test PRIVATE tessera)
add_dependencies(spu_loader_test spu_passthrough spu_test_shadow spu_test_noentry
  spu_test_oldabi spu_test_misnamed spu_test_prevabi)
foreach(t finds_build_tree_plugin env_path_first missing_spu_names_search_path
          rejects_file_without_entry_point rejects_abi_mismatch rejects_name_mismatch
          rejects_bad_names registered_class_wins register_rejects_bad_class
          list_sorted_deduplicated find_is_thread_safe
          register_rejects_bad_network_declaration rejects_previous_abi)
  add_test(NAME spu_loader_${t} COMMAND spu_loader_test spu_loader_${t}
    ${TESSERA_SPU_BUILD_DIR} ${SPU_TEST_ENV_DIR} ${SPU_TEST_BAD_DIR})
endforeach()

add_executable(spu_chain_test ${SPU_TEST_SRC}/chain_test.c)
target_link_libraries(spu_chain_test PRIVATE tessera)
add_dependencies(spu_chain_test spu_passthrough)
foreach(t inheritance super_options_accepted subclass_calls_super_api rejects_unknown_option rejects_wrong_type
          rejects_unknown_spu rejects_super_cycle_and_depth empty_is_error
          parse_errors_name_token parse_quoted_values create_failure_cleans_up
          unset_slots_reach_child links_text_reads_back native_windows_per_chain)
  add_test(NAME spu_chain_${t} COMMAND spu_chain_test spu_chain_${t})
  set_tests_properties(spu_chain_${t} PROPERTIES ENVIRONMENT "TESSERA_SPU_PATH=")
endforeach()
add_test(NAME spu_passthrough_verbose_option COMMAND spu_chain_test spu_passthrough_verbose_option)
set_tests_properties(spu_passthrough_verbose_option PROPERTIES ENVIRONMENT "TESSERA_LOG=")

add_executable(spu_two_instances_test ${SPU_TEST_SRC}/two_instances_test.c)
target_link_libraries(spu_two_instances_test PRIVATE tessera)
add_dependencies(spu_two_instances_test spu_passthrough spu_test_template)
foreach(t two_instances_one_process two_instances_one_chain)
  add_test(NAME spu_${t} COMMAND spu_two_instances_test spu_${t} ${SPU_TEST_TEMPLATE_DIR}
    ${CMAKE_CURRENT_BINARY_DIR})
endforeach()

# `tessera spus`
if(TARGET tessera_cli)
  # PASS_REGULAR_EXPRESSION ignores exit codes, so the shell appends it.
  add_test(NAME spu_cli_lists_spus_with_options
    COMMAND sh -c "\"$0\" spus; echo \"exit=$?\"" $<TARGET_FILE:tessera_cli>)
  set_tests_properties(spu_cli_lists_spus_with_options PROPERTIES ENVIRONMENT "TESSERA_SPU_PATH="
    PASS_REGULAR_EXPRESSION "\npassthrough\n  passes every call to the next SPU unchanged\n  options:\n    verbose \\(bool, default false\\)\n        log when[^\n]*\n(.*\n)*exit=0\n$")
  add_test(NAME spu_cli_shows_one_spu
    COMMAND sh -c "\"$0\" spus passthrough; echo \"exit=$?\"" $<TARGET_FILE:tessera_cli>)
  set_tests_properties(spu_cli_shows_one_spu PROPERTIES ENVIRONMENT "TESSERA_SPU_PATH="
    PASS_REGULAR_EXPRESSION "^passthrough\n  passes every call[^\n]*\n  options:\n    verbose (.*\n)*exit=0\n$")
  add_test(NAME spu_cli_help
    COMMAND sh -c "\"$0\" spus --help; echo \"exit=$?\"" $<TARGET_FILE:tessera_cli>)
  set_tests_properties(spu_cli_help PROPERTIES
    PASS_REGULAR_EXPRESSION "^usage: tessera spus (.*\n)*exit=0\n$")
  add_test(NAME spu_cli_unknown_spu_exits_2
    COMMAND sh -c "\"$0\" spus zzqqxx 2>&1; echo \"exit=$?\"" $<TARGET_FILE:tessera_cli>)
  set_tests_properties(spu_cli_unknown_spu_exits_2 PROPERTIES PASS_REGULAR_EXPRESSION
    "^tessera spus: unknown SPU 'zzqqxx': no zzqqxx_spu.so in [^\n]*\nexit=2\n$")
endif()

# The template SPU, built out of tree against `cmake --install` of this
# build into a temporary prefix, run in a chain by an out-of-tree driver.
set(SPU_TEST_EXTRA_CFLAGS "")
if(TESSERA_SANITIZE)
  set(SPU_TEST_EXTRA_CFLAGS "-fsanitize=address,undefined -fno-omit-frame-pointer")
endif()
add_test(NAME spu_template_out_of_tree
  COMMAND sh ${SPU_TEST_SRC}/template_out_of_tree.sh ${CMAKE_COMMAND} ${CMAKE_BINARY_DIR}
          ${CMAKE_SOURCE_DIR} ${CMAKE_CURRENT_BINARY_DIR}/spu_out_of_tree ${CMAKE_C_COMPILER}
          "${SPU_TEST_EXTRA_CFLAGS}")
set_tests_properties(spu_template_out_of_tree PROPERTIES TIMEOUT 300)

# Logging levels and error values (core/util/log.c, core/util/error.c compiled in).
add_executable(spu_log_test ${SPU_TEST_SRC}/log_test.c ${CMAKE_SOURCE_DIR}/core/util/log.c
  ${CMAKE_SOURCE_DIR}/core/util/error.c)
target_include_directories(spu_log_test PRIVATE ${CMAKE_SOURCE_DIR}/include)
target_link_libraries(spu_log_test PRIVATE Threads::Threads)
add_test(NAME spu_log_default_level_is_warn COMMAND spu_log_test spu_log_level_filter warn)
set_tests_properties(spu_log_default_level_is_warn PROPERTIES ENVIRONMENT "TESSERA_LOG=")
foreach(level debug info error)
  add_test(NAME spu_log_level_${level}_from_env COMMAND spu_log_test spu_log_level_filter ${level})
  set_tests_properties(spu_log_level_${level}_from_env PROPERTIES ENVIRONMENT "TESSERA_LOG=${level}")
endforeach()
add_test(NAME spu_error_values COMMAND spu_log_test spu_error_values)

# Roles, not names (tsr_spu_class.network): the core, the mothership, the
# CLI, the stream client and the server know no SPU by name and guess no
# role from an option name (tests/spu/names_lint_test.c says exactly what it
# flags); and the lint itself finds what the core held before SPUs
# declared their roles (names_lint_sample.c: 9 findings, nothing from its
# legitimate half).
add_executable(spu_names_lint ${SPU_TEST_SRC}/names_lint_test.c)
add_test(NAME spu_core_knows_no_spu_by_name
  COMMAND spu_names_lint ${CMAKE_SOURCE_DIR}/core ${CMAKE_SOURCE_DIR}/mothership
          ${CMAKE_SOURCE_DIR}/cli ${CMAKE_SOURCE_DIR}/client ${CMAKE_SOURCE_DIR}/server)
add_test(NAME spu_names_lint_finds_names_and_guessed_roles
  COMMAND sh -c "\"$0\" \"$1\"; echo \"exit=$?\"" $<TARGET_FILE:spu_names_lint>
          ${SPU_TEST_SRC}/names_lint_sample.c)
set_tests_properties(spu_names_lint_finds_names_and_guessed_roles PROPERTIES
  PASS_REGULAR_EXPRESSION "^[^\n]*sample.c:7: string literal \"pack\" names a built-in SPU\n[^\n]*sample.c:7: string literal \"replicate\"[^\n]*\n[^\n]*sample.c:9: identifier 'check_readback'[^\n]*\n[^\n]*sample.c:9: string literal \"tilesort\"[^\n]*\n[^\n]*sample.c:13: string literal \"servers\" looks an SPU option up by name[^\n]*\n[^\n]*sample.c:14: string literal \"token\" looks[^\n]*\n[^\n]*sample.c:15: string literal \"tiles\" looks[^\n]*\n[^\n]*sample.c:16: string literal \"pack server=[^\n]*\n[^\n]*sample.c:16: string literal \"pack server=[^\n]*\nnames_lint: 1 files, 9 findings\nexit=1\n$")
