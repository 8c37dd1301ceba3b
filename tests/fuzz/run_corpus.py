#!/usr/bin/env python3
"""Runs `BIN validate FILE` on every scene of a corpus (make_corpus.py's classes.tsv) and checks
that each is refused cleanly: a non-zero exit status that is not a timeout (124) or a signal
(>= 128), within 60 s and 2 GB of address space (ulimit -v), with a message on stderr that names
the file, and the line (and the key) where the index expects one.

Prints one line per class, then every failure with its description and the program's first
lines of output, then "N passed, N failed". Exit status 1 if any failed.

Usage: run_corpus.py BIN CORPUS_DIR [--jobs N] [--timeout S] [--vmem KB] [--tsv OUT]
"""

import argparse
import concurrent.futures
import os
import re
import subprocess
import sys
import time


def run_one(binary, path, timeout, vmem):
    # A subshell with the limits, then timeout(1): 124 on a timeout, 128 + n when the program ends
    # by signal n (timeout -k: a KILL 5 s after the TERM if it does not go).
    cmd = ["bash", "-c", 'ulimit -v "$1" && exec timeout -k 5 "$2" "$3" validate "$4"', "run_corpus",
           str(vmem), str(timeout), binary, path]
    t0 = time.monotonic()
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, stdin=subprocess.DEVNULL)
    return p.returncode, p.stdout, p.stderr, time.monotonic() - t0


def verdict(path, expect, rc, err):
    """(passed, outcome): outcome is 'refused', 'accepted', 'timeout', 'signal N' or 'exit N'."""
    if rc == 0:
        return False, "accepted (exit 0)"
    if rc == 124:
        return False, "timeout"
    if rc < 0 or rc >= 128:
        sig = -rc if rc < 0 else rc - 128
        return False, "signal %d" % sig
    text = err.decode("utf-8", "replace")
    if path not in text:
        return False, "exit %d, message does not name the file" % rc
    if expect == "line" and not re.search(re.escape(path) + r":\d+:", text):
        return False, "exit %d, message gives no line (PATH:N:)" % rc
    if expect.startswith("key:"):
        key = expect[4:]
        if not re.search(re.escape(path) + r":\d+: key '" + re.escape(key), text):
            return False, "exit %d, no message 'PATH:N: key '%s...'" % (rc, key)
    return True, "refused (exit %d)" % rc


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("binary")
    ap.add_argument("corpus")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--timeout", type=int, default=60)
    ap.add_argument("--vmem", type=int, default=2000000, help="ulimit -v, KB")
    ap.add_argument("--tsv", help="write file, class, outcome, seconds, description here")
    args = ap.parse_args()

    entries = []
    with open(os.path.join(args.corpus, "classes.tsv"), encoding="utf-8") as f:
        next(f)
        for line in f:
            name, cls, desc, expect = line.rstrip("\n").split("\t")
            entries.append((os.path.abspath(os.path.join(args.corpus, name)), cls, desc, expect))

    results = [None] * len(entries)
    t0 = time.monotonic()

    def run(k):
        rc, out, err, secs = run_one(args.binary, entries[k][0], args.timeout, args.vmem)
        ok, outcome = verdict(entries[k][0], entries[k][3], rc, err)
        results[k] = (ok, outcome, rc, out, err, secs)

    # Files over 8 MB one at a time (each may take up to the memory limit), the rest in parallel.
    big = [k for k, e in enumerate(entries) if os.path.getsize(e[0]) > 8 << 20]
    small = [k for k in range(len(entries)) if k not in set(big)]
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        list(pool.map(run, small))
    for k in big:
        run(k)
    wall = time.monotonic() - t0

    classes = []
    for e in entries:
        if e[1] not in classes:
            classes.append(e[1])
    for cls in classes:
        ks = [k for k, e in enumerate(entries) if e[1] == cls]
        refused = sum(1 for k in ks if 0 < results[k][2] < 128 and results[k][2] != 124)
        failed = sum(1 for k in ks if not results[k][0])
        print("%s: %d scenes, %d refused, %d failed" % (cls, len(ks), refused, failed))

    failures = [k for k in range(len(entries)) if not results[k][0]]
    if failures:
        print("\nfailures:")
    for k in failures:
        path, cls, desc, expect = entries[k]
        ok, outcome, rc, out, err, secs = results[k]
        print("FAIL %s [%s] %s (%.1f s)\n  %s" % (os.path.basename(path), cls, outcome, secs, desc))
        lines = (err + out).decode("utf-8", "replace").splitlines()[:4]
        for line in lines:
            print("  | " + (line if len(line) <= 300 else line[:300] + "..."))
    slowest = max(range(len(entries)), key=lambda k: results[k][5]) if entries else None
    if slowest is not None:
        print("\n%d scenes in %.1f s (%d at a time); slowest %s, %.1f s" % (
            len(entries), wall, args.jobs, os.path.basename(entries[slowest][0]), results[slowest][5]))
    if args.tsv:
        with open(args.tsv, "w", encoding="utf-8") as f:
            for k, (path, cls, desc, expect) in enumerate(entries):
                f.write("%s\t%s\t%s\t%.2f\t%s\n" % (os.path.basename(path), cls, results[k][1], results[k][5], desc))
    print("%d passed, %d failed" % (len(entries) - len(failures), len(failures)))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
