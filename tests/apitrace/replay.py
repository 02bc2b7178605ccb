#!/usr/bin/env python3
"""tests/apitrace/replay.py - apitrace traces replayed through tessera (issue 27, item 4).

What it is for: on a private Xvfb as a desktop has it (1280x1024x24, GLX
enabled), it records a trace of glxgears and of xscreensaver-gl hacks with
Debian's `apitrace trace` (GLX for glxgears, EGL for the hacks), cut to
their first FRAMES frames (`apitrace trim`), and replays each with
Debian's unmodified glretrace (eglretrace for the EGL traces), taking a
snapshot of every frame (`-s`):

  native  Mesa's GLX/EGL on the Xvfb, no faker;
  render  `tessera exec` with [render] 1x1 (its PNGs and the snapshots);
  wall    `tessera exec --graph` of a tilesort wall of four render servers
          (tests/apitrace/wall.yaml: grid [2, 2] dividing whatever window
          the replayer opens; with --tiles, tiles.yaml: fixed pixel tiles
          of the traces' 320x240, which the replayer's 32x32 window only
          reaches when it is resized before the first frame), its tiles
          assembled into whole frames, and the snapshots.

and judges (apitrace_frames_compare): every replay has as many frames as
the native one; each render snapshot equals the native snapshot in RGB,
or is within MIN_PSNR dB of it where the two GL stacks round differently
(Mesa's GLX against render's OSMesa: such frames are counted and named);
render's PNGs equal render's snapshots; the wall's assembled frames and
snapshots equal render's, 0 pixels differing.

Frame 0 is compared with the native replay only for traces recorded in
the replayer's own 32x32 window (glxgears@32x32, gears@32x32): for the
others Mesa draws it natively before it takes the replayer's resize
(one() says how; docs/conformance.md).

Recording is done at test time (no trace is committed): the traces differ
from run to run (the programs animate by the clock and by random seeds),
but every replay of one run replays the same file. A trace that does not
reach FRAMES frames within the time limit fails the test.

What it owns: its Xvfb (killed by pid), the processes it starts (each in
its own session, killed with its group), and OUT.

Usage: replay.py TESSERA COMPARE OUT [--frames N] [--jobs J] [--tiles]
                 [--min-psnr DB] [--only NAME...]
"""
import argparse
import os
import shutil
import signal
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor

HERE = os.path.dirname(os.path.abspath(__file__))
HACKS = "/usr/libexec/xscreensaver"
# glxgears and 14 hacks, all at 320x240: hacks that draw from their
# first frames (no fade-in from black, which would leave nothing to
# compare) with small traces, of different kinds (lighting, display
# lists, textures, fog, blending, lines, many small draws), two of them
# drawing with GLSL 1.20 programs and buffer objects (GLSL_HACKS).
# NAME@32x32: the same program recorded in a 32x32 window, the size the
# replayer opens, so that it needs no resize and its frame 0 is compared
# with the native one too (see FIRST_COMPARED).
PROGRAMS = ["glxgears", "atunnel", "blinkbox", "circuit", "cubestorm", "gears", "geodesic", "glknots",
            "glsnake", "hypertorus", "moebius", "morph3d", "polytopes", "projectiveplane", "superquadrics",
            "glxgears@32x32", "gears@32x32"]
SIZE = (320, 240)
REPLAYER_WINDOW = (32, 32)


def name_and_size(entry):
    """'NAME' or 'NAME@WxH' -> (NAME, (W, H))."""
    if "@" not in entry:
        return entry, SIZE
    name, size = entry.split("@")
    w, h = size.split("x")
    return name, (int(w), int(h))


def log(out, text):
    print(text, flush=True)
    with open(os.path.join(out, "report.txt"), "a") as f:
        f.write(text + "\n")


def start_xvfb(workdir):
    """Starts Xvfb on a display it picks itself; returns (proc, ':N')."""
    rfd, wfd = os.pipe()
    args = ["Xvfb", "-displayfd", str(wfd), "-screen", "0", "1280x1024x24", "-nolisten", "tcp", "-noreset"]
    logf = open(os.path.join(workdir, "xvfb.log"), "w")
    proc = subprocess.Popen(args, pass_fds=(wfd,), stdout=logf, stderr=logf)
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
        sys.exit("replay.py: Xvfb reported no display (log: %s)" % logf.name)
    return proc, ":" + buf.decode().strip()


def stop_group(proc, grace=5):
    """SIGTERM to the process group of `proc` (its own session), SIGKILL
    after `grace` seconds; returns its status."""
    try:
        os.killpg(proc.pid, signal.SIGTERM)
    except ProcessLookupError:
        pass
    try:
        return proc.wait(grace)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        return proc.wait()


def run(cmd, d, name, limit=120):
    """Runs cmd in its own session, output to d/name.{out,err}; returns its
    status (None when killed at the time limit)."""
    with open(os.path.join(d, name + ".out"), "w") as o, open(os.path.join(d, name + ".err"), "w") as e:
        p = subprocess.Popen(cmd, stdout=o, stderr=e, start_new_session=True)
        try:
            return p.wait(limit)
        except subprocess.TimeoutExpired:
            stop_group(p)
            return None


def frames_of(trace):
    """FramesCount of a trace (a partial one while it is being written
    counts what has reached the file), or -1."""
    r = subprocess.run(["apitrace", "info", trace], capture_output=True, text=True)
    for line in r.stdout.splitlines():
        if '"FramesCount"' in line:
            return int(line.split(":")[1].strip().rstrip(","))
    return -1


# The GLSL hacks ask for an OpenGL 3.0 context first and, refused, take
# 1.3 with GLSL 1.20 shaders and buffer objects. Mesa would give them 3.0,
# and a trace of a 3.0 context does not replay on tessera's 2.1 (the
# replayer checks the version; OpenGL 3.x is a later issue), so they are
# recorded on Mesa told to offer 2.1, as a 2.1 driver would: the trace
# then asks for 1.3, natively and under tessera alike.
GLSL_HACKS = ("etruscanvenus", "hypertorus", "projectiveplane", "romanboy", "sphereeversion")
RECORD_ENV = {"MESA_GL_VERSION_OVERRIDE": "2.1"}


def program_cmd(entry):
    name, size = name_and_size(entry)
    if name == "glxgears":
        return ["glxgears", "-geometry", "%dx%d" % size], "gl"
    return [os.path.join(HACKS, name), "-geometry", "%dx%d" % size], "egl"


def record_once(cmd, api, raw, frames, seconds, env):
    """Runs the program under `apitrace trace` for at most `seconds`, or
    until the trace on disk holds `frames` frames; returns True if the
    program ended by itself first."""
    with open(os.path.join(os.path.dirname(raw), "record.err"), "a") as e:
        p = subprocess.Popen(["apitrace", "trace", "--api", api, "-o", raw] + cmd, stdout=e, stderr=e,
                             env=env, start_new_session=True)
        deadline = time.monotonic() + seconds
        # The tracer writes the file in chunks of about a megabyte, so the
        # frame count on disk is only seen growing for fast programs
        # (glxgears); a slow one runs for the attempt's time.
        while time.monotonic() < deadline and p.poll() is None:
            if os.path.exists(raw) and frames_of(raw) >= frames:
                break
            time.sleep(0.2)
        ended_by_itself = p.poll() is not None
        stop_group(p)
    return ended_by_itself


def record(name, d, frames, limit):
    """Records the program until its trace holds `frames` frames, in
    attempts of 3, 6, 12, ... seconds (at most `limit` in all), then cuts
    it to frames 0..frames-1: d/NAME.trace. Returns (api, why) - why is
    None when it worked."""
    cmd, api = program_cmd(name)
    env = dict(os.environ, **RECORD_ENV) if name_and_size(name)[0] in GLSL_HACKS else None
    raw = os.path.join(d, "raw.trace")
    seconds, spent, n, ended = 3, 0, -1, False
    while spent < limit:
        if os.path.exists(raw):
            os.remove(raw)
        ended = record_once(cmd, api, raw, frames, seconds, env)
        spent += seconds
        n = frames_of(raw) if os.path.exists(raw) else -1
        if n >= frames or ended:
            break
        seconds *= 2
    if n < frames:
        how = "it ended by itself" if ended else "in %d s" % spent
        return api, "the recording holds %d frames, not %d (%s; record.err)" % (n, frames, how)
    trace = os.path.join(d, name_and_size(name)[0] + ".trace")
    r = subprocess.run(["apitrace", "trim", "--frames=0-%d" % (frames - 1), "-o", trace, raw],
                       capture_output=True, text=True)
    got = frames_of(trace)
    if r.returncode != 0 or got != frames:
        return api, "apitrace trim gave %d frames, status %d: %s" % (got, r.returncode, r.stderr.strip())
    os.remove(raw)
    return api, None


def compare(compare_bin, a, b, min_psnr, d, what, first=0):
    """apitrace_frames_compare A B from frame `first`; returns (ok, its
    summary line)."""
    r = subprocess.run([compare_bin, "--from", str(first), a, b, min_psnr], capture_output=True, text=True)
    with open(os.path.join(d, "compare.txt"), "a") as f:
        f.write("== %s: %s against %s (%s)\n%s%s" % (what, b, a, min_psnr, r.stdout, r.stderr))
    lines = (r.stdout + r.stderr).strip().splitlines()
    return r.returncode == 0, (lines[-1] if lines else "no output")


def one(args, name):
    """Records, replays and judges one program; returns (name, verdict,
    details, psnr_frames)."""
    d = os.path.join(args.out, name.replace("@", "-"))
    os.makedirs(d)
    api, why = record(name, d, args.frames, args.record_seconds)
    if why:
        return name, "FAIL", "recording: " + why, 0
    trace = os.path.join(d, name_and_size(name)[0] + ".trace")
    retrace = "glretrace" if api == "gl" else "eglretrace"
    tessera = args.tessera
    graph = os.path.join(HERE, "tiles.yaml" if args.tiles else "wall.yaml")
    runs = [
        ("native", [retrace, "-s", os.path.join(d, "native") + "/", trace]),
        ("render", [tessera, "exec", "--out", os.path.join(d, "render-png", "f-%04d.png"), "--",
                    retrace, "-s", os.path.join(d, "render") + "/", trace]),
        ("wall", [tessera, "exec", "--graph", graph, "--out", os.path.join(d, "wall-out"), "--",
                  retrace, "-s", os.path.join(d, "wall") + "/", trace]),
    ]
    for sub in ("native", "render", "wall", "render-png", "wall-out"):
        os.makedirs(os.path.join(d, sub))
    for label, cmd in runs:
        status = run(cmd, d, label)
        if status != 0:
            err = open(os.path.join(d, label + ".err")).read().strip().splitlines()
            return name, "FAIL", "%s replay: %s; %s" % (
                label, "killed at the time limit" if status is None else "status %d" % status,
                " | ".join(err[-3:])), 0
    wall_frames = os.path.join(d, "wall-out", "frames")
    os.makedirs(wall_frames, exist_ok=True)
    for f in os.listdir(os.path.join(d, "wall-out")):
        if f.startswith("f-") and f.endswith(".png"):
            os.rename(os.path.join(d, "wall-out", f), os.path.join(wall_frames, f))
    # Frame 0 is compared with the native replay only when the trace's
    # window is the replayer's own 32x32. Otherwise the replayer grows its
    # 32x32 window to the trace's size in frame 0, before it draws, and
    # Mesa's software GLX and EGL on X11 (drisw) draw that frame into the
    # 32x32 buffers and read it back from buffers of the new size: black
    # (EGL) or a 32x32 corner and uninitialised rows (GLX; two native
    # replays differ there). tessera follows the resize at once (the faker
    # reads the window's size at glViewport); its frame 0 is still counted
    # and compared between render and the wall.
    first = 0 if name_and_size(name)[1] == REPLAYER_WINDOW else 1
    checks = [
        ("render snapshots against native", "native", "render", args.min_psnr, first),
        ("render PNGs against render snapshots", "render", "render-png", "exact", 0),
        ("wall snapshots against render snapshots", "render", "wall", "exact", 0),
        ("wall assembled frames against render PNGs", "render-png", os.path.join("wall-out", "frames"), "exact", 0),
    ]
    failed, summary, psnr_frames = [], [], 0
    for what, a, b, bound, first in checks:
        ok, line = compare(args.compare, os.path.join(d, a), os.path.join(d, b), bound, d, what, first)
        summary.append("%s: %s" % (b, line))
        if not ok:
            failed.append("%s: %s" % (what, line))
        if a == "native" and ok:
            # "frames N/N equal E within P, worst W dB"
            psnr_frames = int(line.split("within")[1].split(",")[0])
    if failed:
        return name, "FAIL", "; ".join(failed) + " (compare.txt)", psnr_frames
    return name, "ok", "; ".join(summary), psnr_frames


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("tessera")
    ap.add_argument("compare")
    ap.add_argument("out")
    ap.add_argument("--frames", type=int, default=7)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--record-seconds", type=int, default=45)
    ap.add_argument("--min-psnr", default="40")
    ap.add_argument("--tiles", action="store_true", help="the wall has fixed pixel tiles (tiles.yaml)")
    ap.add_argument("--only", nargs="+", default=None)
    args = ap.parse_args()
    args.tessera = os.path.abspath(args.tessera)
    args.compare = os.path.abspath(args.compare)
    for tool in ("apitrace", "glretrace", "eglretrace", "Xvfb"):
        if not shutil.which(tool):
            print("SKIP: %s is not installed (scripts/setup-debian installs apitrace and xvfb)" % tool)
            return 77
    programs = args.only or PROGRAMS
    for p in programs:
        cmd, _ = program_cmd(p)
        if not shutil.which(cmd[0]):
            print("SKIP: %s is not installed (scripts/setup-debian installs mesa-utils and xscreensaver-gl)"
                  % cmd[0])
            return 77
    shutil.rmtree(args.out, ignore_errors=True)
    os.makedirs(args.out)
    xvfb, display = start_xvfb(args.out)
    os.environ["DISPLAY"] = display
    begin = time.monotonic()
    try:
        with ThreadPoolExecutor(args.jobs) as pool:
            results = list(pool.map(lambda p: one(args, p), programs))
    finally:
        xvfb.terminate()
        xvfb.wait()
    for name, verdict, details, _ in results:
        log(args.out, "%s %s: %s" % (verdict, name, details))
    failed = [r[0] for r in results if r[1] != "ok"]
    psnr = [(r[0], r[3]) for r in results if r[3]]
    log(args.out, "apitrace replays (%s wall): %d traces of %d frames in %d s, %d at a time: %d equal native, "
        "render and the wall, %d failed; frames within %s dB but not equal to native: %s" % (
            "pixel-tile" if args.tiles else "2x2 grid", len(results), args.frames, time.monotonic() - begin,
            args.jobs, len(results) - len(failed), len(failed), args.min_psnr,
            ", ".join("%s %d" % p for p in psnr) if psnr else "none"))
    if failed:
        log(args.out, "FAIL: " + " ".join(failed))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
