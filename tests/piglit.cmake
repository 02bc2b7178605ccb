# tests/piglit.cmake — piglit's own GL 1.0-2.1 tests (Debian's piglit,
# unmodified) through tessera (issue 27, item 3; docs/conformance.md).
# tests/piglit/choose.py chooses them by a rule (every test of quick_gl's
# GL 1.0-2.1 groups, every 32nd GLSL 1.10/1.20 shader_runner test: 537);
# tests/piglit/sweep.py runs each natively on its own Xvfb, and each that
# passes natively through `tessera exec` with [render], the 2x2 grid wall
# (tests/piglit/wall.yaml) and, every 4th by name, [pack -> tessera node
# render] (tests/piglit/pack.yaml). A test that fails natively is
# excluded, and said so; a failure under tessera fails the test unless
# tests/piglit/exceptions.tsv (proven Mesa's) or tests/piglit/open.tsv
# (known, not fixed yet: reported as OPEN every run) names it.
# Four parts, so ctest runs them in parallel; each part starts its own
# Xvfb (-displayfd: no fixed display, no lock) as a desktop has it (GLX
# enabled, many visuals), and runs every test natively and under tessera
# on it: the faker's configs are offered there as Mesa's are. Plain build
# only: a sanitized faker under 537 uninstrumented programs would take the
# CI's budget (at most 8 minutes for all four parts on two cores).
if(NOT TESSERA_SANITIZE)
  find_program(TESSERA_PYTHON3 python3 PATHS /usr/bin NO_DEFAULT_PATH)
  set(PIGLIT_PARTS 4)
  math(EXPR last "${PIGLIT_PARTS} - 1")
  foreach(part RANGE ${last})
    set(name piglit_gl_1_0_to_2_1_tests_passing_natively_pass_through_render_wall_and_pack_part_${part})
    add_test(NAME ${name}
             COMMAND sh -c "[ -d /usr/lib/x86_64-linux-gnu/piglit/bin ] || { echo 'SKIP: piglit is not installed (scripts/setup-debian installs it)'; exit 77; }; exec \"$0\" \"$@\""
                     ${TESSERA_PYTHON3} ${CMAKE_CURRENT_SOURCE_DIR}/piglit/sweep.py
                     $<TARGET_FILE:tessera_cli> ${CMAKE_BINARY_DIR}/test-out/piglit/part${part}
                     --shard ${part}/${PIGLIT_PARTS})
    set_tests_properties(${name} PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 900 LABELS piglit)
  endforeach()
endif()
