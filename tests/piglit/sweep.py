#!/usr/bin/env python3
"""tests/piglit/sweep.py - piglit's own tests through tessera (issue 27).

What it is for: runs the tests tests/piglit/choose.py chooses, unmodified,
on a private Xvfb: first natively (Mesa's GLX, no faker), then each test
that passes natively through `tessera exec` with [render], through the
2x2 grid wall (tests/piglit/wall.yaml) and, for every 4th by name, through
[pack -> tessera node render] (tests/piglit/pack.yaml). A test that passes
natively must pass under every graph it runs through, unless the
exceptions file names it for that graph with a reason (a difference
proven Mesa's), or the open list names it (a failure of tessera known and
not fixed yet: reported as OPEN on every run, counted apart from the
passes; docs/conformance.md). A test that does not
pass natively (fail, skip, crash, timeout) is excluded, and said so with
its native result: never silently.

Each run is the command line piglit's runner gives the test
(PIGLIT_PLATFORM=mixed_glx_egl, as `piglit run` sets it), in its own
session, killed with its whole process group at the time limit. Its
output, standard error and a line with its CPU time go to
OUT/runs/NAME/GRAPH.*; OUT/results.tsv has one line per test, and the
counts, the CPU seconds of the runs and the wall time end the output.

What it owns: its Xvfb servers (killed by pid at the end) and OUT.
It must never judge a test by anything but piglit's own result line.

Usage: sweep.py TESSERA OUT [--shard I/N] [--jobs J] [--every K]
                [--xvfb-args ARGS] [--exceptions FILE] [--only NAME...]
"""
import argparse
import contextlib
import json
import os
import re
import shlex
import shutil
import signal
import subprocess
import sys
import threading
import time
from concurrent.futures import ThreadPoolExecutor

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import choose as piglit_select  # noqa: E402  (tests/piglit/choose.py)

GRAPHS = ("render", "wall", "pack")
RESULT_LINE = re.compile(r"^PIGLIT: (\{.*\})\s*$", re.M)


def start_xvfb(extra, workdir):
    """Starts Xvfb on a display it picks itself; returns (proc, ':N')."""
    rfd, wfd = os.pipe()
    args = ["Xvfb", "-displayfd", str(wfd), "-screen", "0", "1280x1024x24",
            "-nolisten", "tcp", "-noreset"] + shlex.split(extra)
    log = open(os.path.join(workdir, "xvfb%d.log" % wfd), "w")
    proc = subprocess.Popen(args, pass_fds=(wfd,), stdout=log, stderr=log)
    os.close(wfd)
    deadline = time.monotonic() + 20
    buf = b""
    with os.fdopen(rfd, "rb", buffering=0) as r:
        while not buf.endswith(b"\n") and time.monotonic() < deadline:
            chunk = r.read(16)
            if not chunk:
                break
            buf += chunk
    if not buf.strip():
        proc.kill()
        sys.exit("sweep.py: Xvfb %s reported no display (log: %s)" % (" ".join(args), log.name))
    return proc, ":" + buf.decode().strip()

def select_part(every, shard_i, shard_n, only):
    """The tests of part shard_i of shard_n of the rule's list (contiguous
    parts: the every-4th pack runs spread evenly over them), those of
    `only` among them if given, and how many the rule selects in all."""
    tests = piglit_select.select(every=every)
    total = len(tests)
    tests = tests[shard_i * total // shard_n:(shard_i + 1) * total // shard_n]
    if only:
        tests = [t for t in tests if t[0] in only]
    return tests, total


def fresh_out(path):
    """Empties the output folder (with its runs/) and returns its absolute path."""
    subprocess.run(["rm", "-rf", path], check=True)
    os.makedirs(os.path.join(path, "runs"))
    return os.path.abspath(path)


def piglit_env(**extra):
    """The environment of piglit's runs: GLX and EGL, no chain of the
    caller's, leaks not judged (piglit's own are not tessera's)."""
    env = dict(os.environ, PIGLIT_PLATFORM="mixed_glx_egl", **extra)
    env.pop("TESSERA_CHAIN", None)
    env.setdefault("ASAN_OPTIONS", "")
    env["ASAN_OPTIONS"] += ":detect_leaks=0"
    return env


@contextlib.contextmanager
def xvfb_servers():
    """A list for the Xvfb servers a sweep starts; they end when the block
    does, and on SIGTERM or SIGINT (ctest's time-out, ^C). The test runs
    end with their own sessions (run_one)."""
    xvfbs = []

    def stop():
        for x in xvfbs:
            if x.poll() is None:
                x.terminate()
                x.wait()

    def on_signal(signum, frame):
        stop()
        sys.exit(128 + signum)

    signal.signal(signal.SIGTERM, on_signal)
    signal.signal(signal.SIGINT, on_signal)
    try:
        yield xvfbs
    finally:
        stop()


def piglit_result(out):
    """The result piglit's runner would take from the output, or None."""
    result = None
    for m in RESULT_LINE.finditer(out):
        try:
            d = json.loads(m.group(1))
        except ValueError:
            continue
        if "result" in d:
            result = d["result"]
    return result


def run_one(argv, env, cwd, timeout, stem):
    """Runs argv; returns (result, cpu_seconds). result is piglit's word,
    or 'crash (signal N)', 'crash (exit N, no result)', 'timeout'."""
    os.makedirs(cwd, exist_ok=True)
    with open(stem + ".out", "w+") as out, open(stem + ".err", "w") as err:
        t0 = time.monotonic()
        try:
            p = subprocess.Popen(argv, env=env, cwd=cwd, stdout=out, stderr=err,
                                 stdin=subprocess.DEVNULL, start_new_session=True)
        except OSError as e:  # a profile entry whose program Debian does not ship
            return "not run (%s: %s)" % (os.path.basename(argv[0]), e.strerror), 0.0
        timed_out = False
        while True:
            pid, status, ru = os.wait4(p.pid, os.WNOHANG)
            if pid:
                break
            if time.monotonic() - t0 > timeout:
                timed_out = True
                try:
                    os.killpg(p.pid, signal.SIGKILL)
                except ProcessLookupError:
                    pass
                pid, status, ru = os.wait4(p.pid, 0)
                break
            time.sleep(0.02)
        p.returncode = 0  # reaped here, not by Popen
        # what the session left behind (a graph's nodes) goes with it
        try:
            os.killpg(p.pid, signal.SIGKILL)
        except (ProcessLookupError, PermissionError):
            pass
        cpu = ru.ru_utime + ru.ru_stime
        out.seek(0)
        text = out.read()
    result = piglit_result(text)
    if timed_out:
        result = "timeout"
    elif os.WIFSIGNALED(status):
        result = "crash (signal %d)" % os.WTERMSIG(status)
    elif result is None:
        result = "crash (exit %d, no result)" % os.WEXITSTATUS(status)
    with open(stem + ".time", "w") as f:
        f.write("%s %.3f cpu-s %.3f wall-s\n" % (result, cpu, time.monotonic() - t0))
    return result, cpu


def load_exceptions(path):
    """{(name, graph): reason}. Lines: GRAPH<TAB>NAME<TAB>REASON; # comments."""
    exc = {}
    if not path or not os.path.exists(path):
        return exc
    with open(path) as f:
        for n, line in enumerate(f, 1):
            line = line.rstrip("\n")
            if not line.strip() or line.startswith("#"):
                continue
            parts = line.split("\t")
            if len(parts) != 3 or parts[0] not in GRAPHS or not parts[2].strip():
                sys.exit("sweep.py: %s:%d: expected GRAPH<TAB>NAME<TAB>REASON with GRAPH one of %s"
                         % (path, n, ", ".join(GRAPHS)))
            exc[(parts[1], parts[0])] = parts[2]
    return exc


def load_open(path):
    """{(name, graph): note}: failures known and not fixed yet (issue 27),
    reported on every run as OPEN, never as passes. Same format as the
    exceptions. A listed test that passes is reported so the line goes."""
    return load_exceptions(path)


def safe(name):
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", name)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("tessera", help="the tessera program")
    ap.add_argument("out", help="output folder (emptied first)")
    ap.add_argument("--shard", default="0/1", help="I/N: part I of N equal parts of the list, in name order")
    ap.add_argument("--jobs", type=int, default=1, help="tests at a time (default 1)")
    ap.add_argument("--every", type=int, default=piglit_select.DEFAULT_EVERY,
                    help="k of choose.py (default %(default)s)")
    ap.add_argument("--xvfb-args", default="", help="more Xvfb arguments for the tessera runs")
    ap.add_argument("--exceptions", default=os.path.join(HERE, "exceptions.tsv"),
                    help="differences proven Mesa's (GRAPH<TAB>NAME<TAB>REASON lines)")
    ap.add_argument("--open", default=os.path.join(HERE, "open.tsv"),
                    help="known failures not fixed yet, same format (default %(default)s)")
    ap.add_argument("--timeout", type=float, default=120, help="seconds per run")
    ap.add_argument("--graphs", default=",".join(GRAPHS), help="graphs to run (default all)")
    ap.add_argument("--only", nargs="*", help="only these test names")
    a = ap.parse_args()
    try:
        shard_i, shard_n = (int(x) for x in a.shard.split("/"))
        assert 0 <= shard_i < shard_n
    except (ValueError, AssertionError):
        sys.exit("sweep.py: --shard must be I/N with 0 <= I < N, not '%s'" % a.shard)
    graphs = a.graphs.split(",")
    for g in graphs:
        if g not in GRAPHS:
            sys.exit("sweep.py: --graphs: '%s' is not one of %s" % (g, ", ".join(GRAPHS)))
    if not shutil.which("Xvfb"):
        print("SKIP: Xvfb is not installed (scripts/setup-debian installs xvfb)")
        sys.exit(77)
    a.tessera = os.path.abspath(a.tessera)
    if not os.access(a.tessera, os.X_OK):
        sys.exit("sweep.py: %s is not an executable tessera" % a.tessera)
    exceptions = load_exceptions(a.exceptions)
    open_failures = load_open(a.open)

    tests, total_selected = select_part(a.every, shard_i, shard_n, a.only)
    out = fresh_out(a.out)
    t_start = time.monotonic()
    with xvfb_servers() as xvfbs:
        run_all(a, tests, total_selected, shard_i, shard_n, graphs, exceptions, open_failures, out, xvfbs, t_start)


def run_all(a, tests, total_selected, shard_i, shard_n, graphs, exceptions, open_failures, out, xvfbs, t_start):
    native_x, native_display = start_xvfb("", out)
    xvfbs.append(native_x)
    tessera_display = native_display
    if a.xvfb_args.strip():
        x, tessera_display = start_xvfb(a.xvfb_args, out)
        xvfbs.append(x)

    base_env = piglit_env()
    lock = threading.Lock()
    cpu_total = [0.0]
    rows = []

    def runs_for(name, pack):
        return [g for g in graphs if g != "pack" or pack]

    def one(test):
        name, argv, pack = test
        d = os.path.join(out, "runs", safe(name))
        os.makedirs(d)
        res = {"native": None}
        cpu = 0.0
        env = dict(base_env, DISPLAY=native_display)
        res["native"], c = run_one(argv, env, d, a.timeout, os.path.join(d, "native"))
        cpu += c
        if res["native"] == "pass":
            env = dict(base_env, DISPLAY=tessera_display)
            for g in runs_for(name, pack):
                run_dir = os.path.join(d, g)
                if g == "render":
                    cmd = [a.tessera, "exec", "--out", os.path.join(run_dir, "f-%04d.png"), "--"] + argv
                else:
                    cmd = [a.tessera, "exec", "--graph", os.path.join(HERE, g + ".yaml"),
                           "--out", run_dir, "--"] + argv
                res[g], c = run_one(cmd, env, run_dir, a.timeout, os.path.join(d, g))
                cpu += c
        with lock:
            cpu_total[0] += cpu
            rows.append((name, pack, res))
            line = "%-70s native=%s" % (name, res["native"])
            for g in GRAPHS:
                if g in res:
                    line += " %s=%s" % (g, res[g])
            print(line, flush=True)

    with ThreadPoolExecutor(max_workers=max(1, a.jobs)) as pool:
        for f in [pool.submit(one, t) for t in tests]:
            f.result()

    rows.sort()
    failures, excluded, excepted, stale, opened = [], [], [], [], []
    counts = {"native": 0}
    ran = {g: 0 for g in GRAPHS}
    for g in GRAPHS:
        counts[g] = 0
    with open(os.path.join(out, "results.tsv"), "w") as f:
        f.write("name\tnative\t" + "\t".join(GRAPHS) + "\n")
        for name, pack, res in rows:
            f.write("\t".join([name] + [res.get(k) or "-" for k in ("native",) + GRAPHS]) + "\n")
            if res["native"] != "pass":
                excluded.append("excluded: %s: fails natively on this X server (%s)" % (name, res["native"]))
                continue
            counts["native"] += 1
            for g in GRAPHS:
                if g not in res:
                    continue
                ran[g] += 1
                reason = exceptions.get((name, g))
                known = open_failures.get((name, g))
                if res[g] == "pass":
                    counts[g] += 1
                    if reason or known:
                        stale.append("note: %s passes under %s now: its line in %s can go"
                                     % (name, g, "exceptions.tsv" if reason else "open.tsv"))
                elif reason:
                    excepted.append("exception: %s under %s: %s (%s)" % (name, g, res[g], reason))
                elif known:
                    opened.append("OPEN: %s under %s: %s (%s)" % (name, g, res[g], known))
                else:
                    failures.append("FAIL: %s under %s: %s (passes natively; %s.out, .err)"
                                    % (name, g, res[g], os.path.join(out, "runs", safe(name), g)))
    for line in excluded + excepted + opened + stale + failures:
        print(line)
    print("selected %d of %d (shard %d/%d, every %d-th shader_runner test); "
          "passed natively %d; passed: %s"
          % (len(tests), total_selected, shard_i, shard_n, a.every, counts["native"],
             ", ".join("%s %d of %d" % (g, counts[g], ran[g]) for g in GRAPHS if g in graphs)))
    print("excluded (fail natively) %d, exceptions %d, open (known, not fixed) %d, new failures %d; "
          "%.1f CPU seconds in the runs, %.1f s wall"
          % (len(excluded), len(excepted), len(opened), len(failures), cpu_total[0],
             time.monotonic() - t_start))
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
