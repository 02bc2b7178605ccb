#!/usr/bin/env python3
"""tests/piglit/choose.py - which piglit tests the conformance sweep runs.

What it is for: the one rule that chooses the tests (issue 27, item 3),
so nobody picks them by hand:
  * every test of piglit's quick_gl profile in a GL 1.0-2.1 group
    (spec@!opengl 1.0 ... spec@!opengl 2.1);
  * every k-th GLSL 1.10 and 1.20 execution test of quick_shader
    (shader_runner .shader_test files), counted in name order;
  * of all those, in name order, every 4th (index 0, 4, 8, ...) also runs
    through [pack -> tessera node render].
Each test's command line is the one piglit's runner gives it: the binary
from piglit's bin/, then -auto, and -fbo when the profile runs it
concurrently (framework/test/piglit_test.py, shader_test.py).

What it owns: nothing but the reading of the two profile lists.
It must never run a test or decide a result: tests/piglit/sweep.py does.

Usage: choose.py [--every K] [--piglit DIR]    prints one test per line:
       NAME<TAB>PACK(0|1)<TAB>ARGV joined by TABs
"""
import argparse
import ast
import gzip
import os
import re
import sys
import xml.etree.ElementTree as ET

PIGLIT_DIR = "/usr/lib/x86_64-linux-gnu/piglit"
# k: the sweep's time budget (at most 8 minutes of CI on two cores for the
# whole sweep, docs/conformance.md) fits every 32nd shader_runner test
# (96 of 3059; with the 441 GL tests, 537 in all).
DEFAULT_EVERY = 32

GL_GROUP = re.compile(r"^spec@!opengl (\d)\.(\d)@")
GLSL_EXECUTION = re.compile(r"^spec@glsl-1\.(10|20)@execution@")


def _profile(piglit, name):
    path = os.path.join(piglit, "tests", name + ".xml.gz")
    try:
        with gzip.open(path) as f:
            return ET.parse(f).getroot()
    except OSError as e:
        sys.exit("choose.py: cannot read piglit's profile %s: %s "
                 "(scripts/setup-debian installs piglit)" % (path, e))


def _options(test):
    return {o.get("name"): o.get("value") for o in test.findall("option")}


def _gl_test(piglit, test):
    opts = _options(test)
    argv = ast.literal_eval(opts["command"])
    argv[0] = os.path.join(piglit, "bin", argv[0])
    argv.append("-auto")
    if opts.get("run_concurrent") == "True":
        argv.append("-fbo")
    return argv


def _shader_test(piglit, test):
    argv = ast.literal_eval(_options(test)["command"])
    return [os.path.join(piglit, "bin", argv[0]),
            os.path.join(piglit, argv[1]), "-auto", "-fbo"]


def select(piglit=PIGLIT_DIR, every=DEFAULT_EVERY):
    """[(name, argv, through_pack)] in name order."""
    chosen = {}
    for t in _profile(piglit, "quick_gl"):
        name = t.get("name")
        m = GL_GROUP.match(name)
        in_gl = m and (int(m.group(1)), int(m.group(2))) <= (2, 1)
        if t.get("type") == "gl" and in_gl:
            chosen[name] = _gl_test(piglit, t)
    shader = sorted((t.get("name"), t) for t in _profile(piglit, "quick_shader")
                    if t.get("type") == "shader" and GLSL_EXECUTION.match(t.get("name"))
                    and ast.literal_eval(_options(t)["command"])[0] == "shader_runner")
    for name, t in shader[::every]:
        chosen[name] = _shader_test(piglit, t)
    names = sorted(chosen)
    return [(n, chosen[n], i % 4 == 0) for i, n in enumerate(names)]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--every", type=int, default=DEFAULT_EVERY,
                    help="k: every k-th GLSL 1.10/1.20 shader_runner test (default %(default)s)")
    ap.add_argument("--piglit", default=PIGLIT_DIR, help="piglit's directory (default %(default)s)")
    a = ap.parse_args()
    if a.every < 1:
        sys.exit("choose.py: --every must be at least 1, not %d" % a.every)
    for name, argv, pack in select(a.piglit, a.every):
        print("\t".join([name, "1" if pack else "0"] + argv))


if __name__ == "__main__":
    main()
