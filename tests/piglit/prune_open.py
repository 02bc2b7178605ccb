#!/usr/bin/env python3
"""tests/piglit/prune_open.py - open.tsv after a whole sweep (issue 27).

What it is for: after sweep.py has run the whole list (in one OUT or in
the parts ctest runs: OUT/part*/results.tsv), drops each line of
tests/piglit/open.tsv whose test no longer fails under its graph (it
passed, or it did not run because it fails natively), and keeps every
other line as it is, with its cause. It only removes lines: a failure the
open list does not name is a regression, printed as FAIL, and the file is
left unchanged (exit 1).

What it owns: nothing but the open list it rewrites.
It must never add a line: a cause is written by hand after reading the
test's output.

Usage: prune_open.py RESULTS.tsv... [--open FILE] [--dry-run]
"""
import argparse
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
GRAPHS = ("render", "wall", "pack")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("results", nargs="+", help="sweep.py's results.tsv files, together the whole list")
    ap.add_argument("--open", default=os.path.join(HERE, "open.tsv"), help="the open list (default %(default)s)")
    ap.add_argument("--dry-run", action="store_true", help="print what would go, write nothing")
    a = ap.parse_args()

    failing = set()
    for path in a.results:
        with open(path) as f:
            header = f.readline().rstrip("\n").split("\t")
            if header[:2] != ["name", "native"]:
                sys.exit("prune_open.py: %s is not a sweep.py results.tsv" % path)
            for line in f:
                row = dict(zip(header, line.rstrip("\n").split("\t")))
                if row["native"] != "pass":
                    continue
                for g in GRAPHS:
                    if row.get(g, "-") not in ("-", "pass"):
                        failing.add((row["name"], g))

    kept, gone, listed = [], [], set()
    with open(a.open) as f:
        for line in f:
            parts = line.rstrip("\n").split("\t")
            if line.startswith("#") or len(parts) != 3:
                kept.append(line)
                continue
            listed.add((parts[1], parts[0]))
            if (parts[1], parts[0]) in failing:
                kept.append(line)
            else:
                gone.append(line)
    regressions = sorted(failing - listed)
    for name, g in regressions:
        print("FAIL: %s under %s is not in %s: a regression" % (name, g, a.open))
    for line in gone:
        print("gone: " + line.rstrip("\n"))
    print("%d lines go, %d failures stay open, %d regressions" % (len(gone), len(failing & listed), len(regressions)))
    if regressions:
        sys.exit(1)
    if not a.dry_run:
        with open(a.open, "w") as f:
            f.writelines(kept)


if __name__ == "__main__":
    main()
