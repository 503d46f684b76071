#!/usr/bin/env python3
"""The benchmarks' one way of timing a command: whole-process wall time, the
median of RUNS runs after WARMUP unmeasured ones, and the peak resident memory
of the measured runs.

The peak is the command's own, from one more run through GNU time
(`/usr/bin/time -f %M`) where it is installed: a process forked from this
script starts with the script's resident set (about 14 MB) as its
high-water mark, which ru_maxrss keeps across the exec, so an empty
stream's 8 MB read as 14.7 and every per-item figure above such a baseline
came out low. That run is not timed: GNU time's own fork adds about 1 ms
(/bin/true: 1.7 ms against 0.6). Without GNU time the timed runs'
ru_maxrss is taken, floor and all, and a line on stderr says so.

    python3 bench/timing.py [--runs N] [--warmup W] [--stdin FILE] -- CMD ARG...

prints `MEDIAN_SECONDS PEAK_KB` on one line. The command's output is discarded;
a command that fails stops the benchmark with its exit status and stderr.
From Python: `from timing import measure` (bench/ on sys.path).
"""
import os
import statistics
import subprocess
import sys
import tempfile
import time

RUNS = 5
WARMUP = 1


GNU_TIME = "/usr/bin/time"
_warned = []


def run_once(cmd, stdin=None, gnu_time=False):
    """Wall seconds and peak resident KB of one run of `cmd`; with
    `gnu_time`, the peak is GNU time's and the wall time includes its fork."""
    inp = open(stdin, "rb") if stdin else subprocess.DEVNULL
    peak_file = None
    launch = cmd
    if gnu_time:
        fd, peak_file = tempfile.mkstemp(prefix="timing-")
        os.close(fd)
        launch = [GNU_TIME, "-f", "%M", "-o", peak_file, *cmd]
    try:
        start = time.perf_counter()
        proc = subprocess.Popen(launch, stdin=inp, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        err = proc.stderr.read()
        _, status, usage = os.wait4(proc.pid, 0)
        wall = time.perf_counter() - start
        peak = usage.ru_maxrss
        if peak_file:
            # GNU time's last line is the peak (a failure adds one before it).
            # An empty file (GNU time itself killed) keeps the child's own.
            with open(peak_file) as f:
                words = f.read().split()
            peak = int(words[-1]) if words else peak
    finally:
        if peak_file:
            os.unlink(peak_file)
        if stdin:
            inp.close()
    code = os.waitstatus_to_exitcode(status)
    if code != 0:
        sys.stderr.write(err.decode(errors="replace"))
        raise SystemExit(f"timing.py: {' '.join(cmd)}: exit status {code}")
    return wall, peak


def measure(cmd, runs=RUNS, warmup=WARMUP, stdin=None):
    """(median wall seconds of `runs` runs after `warmup` ones, peak KB:
    of one more run through GNU time, or of the timed runs without it)."""
    for _ in range(warmup):
        run_once(cmd, stdin)
    walls, peak = [], 0
    for _ in range(runs):
        wall, kb = run_once(cmd, stdin)
        walls.append(wall)
        peak = max(peak, kb)
    if os.access(GNU_TIME, os.X_OK):
        peak = run_once(cmd, stdin, gnu_time=True)[1]
    elif not _warned:
        _warned.append(True)
        sys.stderr.write("timing.py: no GNU time: peaks include this script's ~14 MB\n")
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
