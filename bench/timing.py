#!/usr/bin/env python3
"""The benchmarks' one way of timing a command: whole-process wall time, the
median of RUNS runs after WARMUP unmeasured ones, and the peak resident memory
of the measured runs (the child's own ru_maxrss, so nothing of this script).

    python3 bench/timing.py [--runs N] [--warmup W] [--stdin FILE] -- CMD ARG...

prints `MEDIAN_SECONDS PEAK_KB` on one line. The command's output is discarded;
a command that fails stops the benchmark with its exit status and stderr.
From Python: `from timing import measure` (bench/ on sys.path).
"""
import os
import statistics
import subprocess
import sys
import time

RUNS = 5
WARMUP = 1


def run_once(cmd, stdin=None):
    """Wall seconds and peak resident KB of one run of `cmd`."""
    inp = open(stdin, "rb") if stdin else subprocess.DEVNULL
    try:
        start = time.perf_counter()
        proc = subprocess.Popen(cmd, stdin=inp, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        err = proc.stderr.read()
        _, status, usage = os.wait4(proc.pid, 0)
        wall = time.perf_counter() - start
    finally:
        if stdin:
            inp.close()
    code = os.waitstatus_to_exitcode(status)
    if code != 0:
        sys.stderr.write(err.decode(errors="replace"))
        raise SystemExit(f"timing.py: {' '.join(cmd)}: exit status {code}")
    return wall, usage.ru_maxrss


def measure(cmd, runs=RUNS, warmup=WARMUP, stdin=None):
    """(median wall seconds, peak KB) over `runs` runs after `warmup` ones."""
    for _ in range(warmup):
        run_once(cmd, stdin)
    walls, peak = [], 0
    for _ in range(runs):
        wall, kb = run_once(cmd, stdin)
        walls.append(wall)
        peak = max(peak, kb)
    return statistics.median(walls), peak


def main(argv):
    runs, warmup, stdin = RUNS, WARMUP, None
    while argv and argv[0] != "--":
        flag, value, argv = argv[0], argv[1], argv[2:]
        if flag == "--runs":
            runs = int(value)
        elif flag == "--warmup":
            warmup = int(value)
        elif flag == "--stdin":
            stdin = value
        else:
            raise SystemExit(f"timing.py: unknown option {flag}")
    if not argv[1:]:
        raise SystemExit(__doc__)
    median, peak = measure(argv[1:], runs, warmup, stdin)
    print(f"{median:.4f} {peak}")


if __name__ == "__main__":
    main(sys.argv[1:])
