#!/usr/bin/env python3
"""tests/piglit/capture_sweep.py - piglit's tests captured and replayed (issue 27, item 7).

What it is for: piglit's -auto tests do not swap, so their capture is
judged by its answers. For each test tests/piglit/choose.py chooses that
passes natively on a private Xvfb, the program runs through
`tessera exec --chain "capture file=... ! render"`: it must pass there as
under [render], and its capture (the stream plus every reply the program
got: glGet*, glGetError, glReadPixels, ...) is then replayed with
`tessera replay --exact-answers` straight into render alone, with no
program and no X server. The replay compares each answer render gives
with the recorded one. A test holds when its capture run passes, the
replay ends cleanly with 0 differing answers, and the capture holds at
least one glReadPixels reply (the picture the program judged). A program
whose stream has no glReadPixels call at all (API tests: errors, limits,
queries; `tessera replay --info` counts the calls) has no picture to
hold: it is judged by its other answers, and counted and named apart
("reads no pixels"). A capture is bounded (max_bytes, MAX_CAPTURE): a
program that sends more (streaming-texture-leak uploads 5000 textures of
4 MiB) still runs through capture ! render and must pass, but has no
capture to replay; it is named and counted apart ("too large to
capture").

A test tests/piglit/open.tsv names under render is not run through
capture: capture stands in front of render, so render's cause would be
the cause; it is reported OPEN with that cause, counted apart, and runs
again as soon as its line goes (one of them, max-texture-size, would
write a 4 GiB capture before failing). A capture run that fails where
tests/piglit/capture-open.tsv names the test (failures of the capture or
the replay known and not fixed yet) is OPEN too; any other failure fails
the sweep. A capture an OPEN run still wrote is replayed, and must replay
with 0 differing answers.

Each run's output, standard error and CPU time go to
OUT/runs/NAME/{native,capture,replay}.*, the capture to
OUT/runs/NAME/capture/run.tsrcap (removed when the test holds, unless
--keep); OUT/results.tsv has one line per test, and the counts (tests
captured, replayed, answers compared, differing, glReadPixels replies)
and the CPU seconds end the output.

What it owns: its Xvfb server (killed by pid at the end) and OUT. It runs
the programs with tests/piglit/sweep.py's runner, so a run is the same
command line, session and time limit as there.
It must never judge a run by anything but piglit's own result line and
the replay's answers line.

Usage: capture_sweep.py TESSERA OUT [--shard I/N] [--jobs J] [--every K]
                        [--xvfb-args ARGS] [--keep] [--only NAME...]
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import threading
import time
from concurrent.futures import ThreadPoolExecutor

HERE = os.path.dirname(os.path.abspath(__file__))
sys.dont_write_bytecode = True  # the imports below write nothing into the source tree
sys.path.insert(0, HERE)
import choose as piglit_select  # noqa: E402  (tests/piglit/choose.py)
import sweep  # noqa: E402  (tests/piglit/sweep.py: start_xvfb, run_one, safe)

READ_PIXELS_CALLS = re.compile(r"^  glReadPixels +(\d+)$", re.M)
ANSWERS = re.compile(r"^tessera replay: .*: answers: (\d+) compared, (\d+) differ(?:; by request: (.*))?$", re.M)
GRAPHS = ("capture", "replay")
MAX_CAPTURE = 1 << 30  # bytes of one capture file: the CI's disk and time


def load_list(path, graphs):
    """{(name, graph): why} from GRAPH<TAB>NAME<TAB>WHY lines of `graphs`;
    other graphs' lines are skipped (open.tsv holds render's, wall's, ...)."""
    found = {}
    if not path or not os.path.exists(path):
        return found
    with open(path) as f:
        for n, line in enumerate(f, 1):
            line = line.rstrip("\n")
            if not line.strip() or line.startswith("#"):
                continue
            parts = line.split("\t")
            if len(parts) != 3 or not parts[2].strip():
                sys.exit("capture_sweep.py: %s:%d: expected GRAPH<TAB>NAME<TAB>WHY" % (path, n))
            if parts[0] in graphs:
                found[(parts[1], parts[0])] = parts[2]
    return found


def by_request(text):
    """{'glReadPixels': 4, ...} from the answers line's list."""
    counts = {}
    for item in (text or "").split(", "):
        m = re.match(r"^(gl\w+) (\d+)", item)
        if m:
            counts[m.group(1)] = int(m.group(2))
    return counts


def replay(tessera, capfile, run_dir, timeout):
    """Replays into render alone; returns a dict: status ('ok' or why
    not), compared, differ, readpixels, cpu."""
    stem = os.path.join(run_dir, "replay")
    os.makedirs(os.path.join(run_dir, "replay"), exist_ok=True)
    cmd = [tessera, "replay", capfile, "--exact-answers", "--chain",
           "render output=%s" % os.path.join(run_dir, "replay", "f-%04d.png")]
    t0 = time.monotonic()
    with open(stem + ".out", "w+") as out, open(stem + ".err", "w") as err:
        p = subprocess.Popen(cmd, stdout=out, stderr=err, stdin=subprocess.DEVNULL)
        while True:
            pid, status, ru = os.wait4(p.pid, os.WNOHANG)
            if pid:
                break
            if time.monotonic() - t0 > timeout:
                p.kill()
                pid, status, ru = os.wait4(p.pid, 0)
                status = None
                break
            time.sleep(0.02)
        p.returncode = 0  # reaped here, not by Popen
        out.seek(0)
        text = out.read()
    code = None if status is None else (-os.WTERMSIG(status) if os.WIFSIGNALED(status) else os.WEXITSTATUS(status))
    m = ANSWERS.search(text)
    res = {"compared": 0, "differ": 0, "readpixels": 0, "cpu": ru.ru_utime + ru.ru_stime}
    # the calls the program made (--info decodes the stream, draws nothing)
    info = subprocess.run([tessera, "replay", "--info", capfile], stdout=subprocess.PIPE,
                          stderr=subprocess.STDOUT, universal_newlines=True, timeout=timeout)
    calls = READ_PIXELS_CALLS.search(info.stdout)
    res["readpixels_calls"] = int(calls.group(1)) if calls else 0
    if m:
        res["compared"], res["differ"] = int(m.group(1)), int(m.group(2))
        res["readpixels"] = by_request(m.group(3)).get("glReadPixels", 0)
    if code is None:
        res["status"] = "timeout"
    elif code < 0:
        res["status"] = "crash (signal %d)" % -code
    elif not m:
        res["status"] = "no answers line (exit %d)" % code
    elif info.returncode != 0:
        res["status"] = "--info: %s" % info.stdout.strip().splitlines()[-1:]
    elif res["differ"]:
        res["status"] = "%d of %d answers differ" % (res["differ"], res["compared"])
    elif code != 0:
        res["status"] = "exit %d" % code
    else:
        res["status"] = "ok"
    with open(stem + ".time", "w") as f:
        f.write("%s %.3f cpu-s %.3f wall-s\n" % (res["status"], res["cpu"], time.monotonic() - t0))
    return res


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("tessera", help="the tessera program")
    ap.add_argument("out", help="output folder (emptied first)")
    ap.add_argument("--shard", default="0/1", help="I/N: part I of N equal parts of the list, in name order")
    ap.add_argument("--jobs", type=int, default=1, help="tests at a time (default 1)")
    ap.add_argument("--every", type=int, default=piglit_select.DEFAULT_EVERY,
                    help="k of choose.py (default %(default)s)")
    ap.add_argument("--xvfb-args", default="", help="more Xvfb arguments (the native and the tessera runs)")
    ap.add_argument("--open", default=os.path.join(HERE, "open.tsv"),
                    help="render's known failures (its render lines apply; default %(default)s)")
    ap.add_argument("--capture-open", default=os.path.join(HERE, "capture-open.tsv"),
                    help="known failures of capture or replay, same format (default %(default)s)")
    # 300, not sweep.py's 120: a capture writes every byte the program sends
    # (streaming-texture-leak uploads about 1.3 GB of textures) and took
    # over 120 s at a load of 26 on two cores
    ap.add_argument("--timeout", type=float, default=300, help="seconds per run (default %(default)s)")
    ap.add_argument("--keep", action="store_true", help="keep every capture file (default: only failures')")
    ap.add_argument("--only", nargs="*", help="only these test names")
    a = ap.parse_args()
    try:
        shard_i, shard_n = (int(x) for x in a.shard.split("/"))
        assert 0 <= shard_i < shard_n
    except (ValueError, AssertionError):
        sys.exit("capture_sweep.py: --shard must be I/N with 0 <= I < N, not '%s'" % a.shard)
    if not shutil.which("Xvfb"):
        print("SKIP: Xvfb is not installed (scripts/setup-debian installs xvfb)")
        sys.exit(77)
    a.tessera = os.path.abspath(a.tessera)
    if not os.access(a.tessera, os.X_OK):
        sys.exit("capture_sweep.py: %s is not an executable tessera" % a.tessera)
    known = load_list(a.open, ("render",))
    known.update(load_list(a.capture_open, GRAPHS))

    tests, total = sweep.select_part(a.every, shard_i, shard_n, a.only)
    out = sweep.fresh_out(a.out)
    t_start = time.monotonic()
    with sweep.xvfb_servers() as xvfbs:
        x, display = sweep.start_xvfb(a.xvfb_args, out)
        xvfbs.append(x)
        code = run_all(a, tests, total, shard_i, shard_n, known, out, display, t_start)
    sys.exit(code)


def run_all(a, tests, total, shard_i, shard_n, known, out, display, t_start):
    env = sweep.piglit_env(DISPLAY=display)
    lock = threading.Lock()
    cpu_total = [0.0]
    rows = []

    def one(test):
        name, argv, _ = test
        d = os.path.join(out, "runs", sweep.safe(name))
        os.makedirs(d)
        res = {"native": None, "capture": None, "replay": None}
        res["native"], cpu = sweep.run_one(argv, env, d, a.timeout, os.path.join(d, "native"))
        if res["native"] == "pass" and (name, "render") not in known:
            run_dir = os.path.join(d, "capture")
            capfile = os.path.join(run_dir, "run.tsrcap")
            chain = "capture file=%s max_bytes=%d ! render output=%s" % (capfile, MAX_CAPTURE,
                                                                         os.path.join(run_dir, "f-%04d.png"))
            cmd = [a.tessera, "exec", "--chain", chain, "--"] + argv
            res["capture"], c = sweep.run_one(cmd, env, run_dir, a.timeout, os.path.join(d, "capture"))
            cpu += c
            if os.path.exists(capfile):
                res["replay"] = replay(a.tessera, capfile, d, a.timeout)
                cpu += res["replay"]["cpu"]
                rp = res["replay"]
                holds = res["capture"] == "pass" and rp["status"] == "ok" \
                    and (rp["readpixels"] > 0 or rp["readpixels_calls"] == 0)
                if holds and not a.keep:
                    os.remove(capfile)
            for f in os.listdir(run_dir):  # a killed run's temporary (spus/capture/README.md)
                if f.startswith(".run.tsrcap.tmp-"):
                    os.remove(os.path.join(run_dir, f))
        with lock:
            cpu_total[0] += cpu
            rows.append((name, res))
            rp = res["replay"]
            print("%-70s native=%s capture=%s replay=%s" % (
                name, res["native"], res["capture"] or "-",
                "-" if rp is None else "%s (%d answers, %d glReadPixels)"
                % (rp["status"], rp["compared"], rp["readpixels"])), flush=True)

    with ThreadPoolExecutor(max_workers=max(1, a.jobs)) as pool:
        for f in [pool.submit(one, t) for t in tests]:
            f.result()
    return report(a, rows, total, shard_i, shard_n, known, out, cpu_total[0], t_start)


def too_large(out, name):
    """The capture SPU abandoned the file at max_bytes (its one log line)."""
    try:
        with open(os.path.join(out, "runs", sweep.safe(name), "capture.err"), errors="replace") as f:
            return "would pass max_bytes=" in f.read()
    except OSError:
        return False


def report(a, rows, total, shard_i, shard_n, known, out, cpu, t_start):
    rows.sort()
    lines, failures, opened, stale = [], [], [], []
    too_large_lines = []
    n = {"too_large": 0, "native": 0, "render_open": 0, "captured": 0, "capture_pass": 0, "replayed": 0, "held": 0, "no_pixels": 0}
    no_pixels = []
    answers = differ = readpixels = 0
    with open(os.path.join(out, "results.tsv"), "w") as f:
        f.write("name\tnative\tcapture\treplay\tanswers\tdiffer\tglReadPixels replies\tglReadPixels calls\n")
        for name, res in rows:
            rp = res["replay"] or {}
            f.write("\t".join([name, res["native"], res["capture"] or "-", rp.get("status", "-"),
                               str(rp.get("compared", 0)), str(rp.get("differ", 0)),
                               str(rp.get("readpixels", 0)), str(rp.get("readpixels_calls", 0))]) + "\n")
            if res["native"] != "pass":
                lines.append("excluded: %s: fails natively on this X server (%s)" % (name, res["native"]))
                continue
            n["native"] += 1
            n["capture_pass"] += res["capture"] == "pass"
            if rp:
                n["captured"] += 1
                n["replayed"] += rp["status"] != "timeout" and not rp["status"].startswith("crash")
                answers += rp["compared"]
                differ += rp["differ"]
                readpixels += rp["readpixels"]
            why = None
            if res["capture"] is None:
                opened.append("OPEN: %s: not captured, fails under render (%s)" % (name, known[(name, "render")]))
                n["render_open"] += 1
                continue
            if res["capture"] != "pass":
                why = "capture run: %s" % res["capture"]
            elif not rp and too_large(out, name):
                n["too_large"] += 1
                too_large_lines.append("too large to capture: %s: passes through capture ! render, sends over "
                                       "%d bytes" % (name, MAX_CAPTURE))
                continue
            elif not rp:
                why = "no capture file"
            elif rp["status"] != "ok":
                why = "replay: %s" % rp["status"]
            elif rp["readpixels"] == 0 and rp["readpixels_calls"] > 0:
                why = "replay: %d glReadPixels calls, no reply among its %d answers" % (rp["readpixels_calls"],
                                                                                        rp["compared"])
            listed = known.get((name, "capture")) or known.get((name, "replay")) or known.get((name, "render"))
            if why is None:
                n["held"] += 1
                if rp["readpixels_calls"] == 0:
                    n["no_pixels"] += 1
                    no_pixels.append("reads no pixels: %s: judged by its %d other answers"
                                     % (name, rp["compared"]))
                if known.get((name, "capture")) or known.get((name, "replay")):
                    stale.append("note: %s holds through capture and replay now: its line in capture-open.tsv "
                                 "can go" % name)
            # An OPEN capture run's capture still replays exactly, unless a
            # replay line names the replay's own known difference.
            elif listed and (known.get((name, "replay")) or not (rp and rp["differ"])):
                opened.append("OPEN: %s: %s (%s)" % (name, why, listed))
            else:
                failures.append("FAIL: %s: %s (passes natively; %s)"
                                % (name, why, os.path.join(out, "runs", sweep.safe(name))))
    for line in lines + no_pixels + too_large_lines + opened + stale + failures:
        print(line)
    print("selected %d of %d (shard %d/%d, every %d-th shader_runner test); passed natively %d; "
          "open under render (not captured) %d; passed through capture ! render %d; captured %d, replayed %d, held %d (0 differing answers, and "
          "at least one glReadPixels reply: %d; reads no pixels: %d); too large to capture %d"
          % (len(rows), total, shard_i, shard_n, a.every, n["native"], n["render_open"], n["capture_pass"], n["captured"],
             n["replayed"], n["held"], n["held"] - n["no_pixels"], n["no_pixels"], n["too_large"]))
    print("answers compared %d, differing %d, glReadPixels replies %d; open (known, not fixed) %d, "
          "new failures %d; %.1f CPU seconds in the runs, %.1f s wall"
          % (answers, differ, readpixels, len(opened), len(failures), cpu, time.monotonic() - t_start))
    return 1 if failures else 0


if __name__ == "__main__":
    main()
