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

    python3 bench/timing.py [--runs N] [--warmup W] [--stdin FILE] [--phase NAME]... -- CMD ARG...

prints `MEDIAN_SECONDS PEAK_KB` on one line, followed by the median of each
`--phase` NAME of the command's `--timings` line (scene-render's `read`,
`render`, `write`). The command's output is discarded; a command that fails
stops the benchmark with its exit status and stderr.

    python3 bench/timing.py [--runs N] [--warmup W] -- CMD1 ARG... -- CMD2 ARG... [-- ...]

times several commands taking turns in each round (`measure_in_turns`) and
prints `MEDIAN_SECONDS PEAK_KB` for each, one line each in order, the peak
from one more run of each.

From Python (bench/ on sys.path): `measure` (one command, wall time and
peak), `measure_in_turns` (several commands taking turns in each round,
wall time and `--timings` phases) and `medians` (one command, wall time and
a figure it reports itself); `run_logged` times one run and keeps its
output. Every benchmark's times of a process are medians of RUNS after
WARMUP taken by these, so that every RESULTS table means the same thing.
"""
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time
from typing import NamedTuple

RUNS = 5
WARMUP = 1


GNU_TIME = "/usr/bin/time"
_warned = []


class Run(NamedTuple):
    """One timed run: wall seconds, peak resident KB, the command's standard
    error and (when kept) standard output, as text."""

    wall: float
    peak: int
    stderr: str
    stdout: str


def run_once(cmd, stdin=None, gnu_time=False):
    """Wall seconds and peak resident KB of one run of `cmd`; with
    `gnu_time`, the peak is GNU time's and the wall time includes its fork."""
    r = run_logged(cmd, stdin, gnu_time)
    return r.wall, r.peak


def run_logged(cmd, stdin=None, gnu_time=False, keep_stdout=False):
    """One run of `cmd` as a `Run`; its standard output is discarded
    unless `keep_stdout` (then it goes through a temporary file, read once
    the command is done, so the timing loop reads one pipe only)."""
    inp = open(stdin, "rb") if stdin else subprocess.DEVNULL
    out = tempfile.TemporaryFile() if keep_stdout else subprocess.DEVNULL
    peak_file = None
    launch = cmd
    if gnu_time:
        fd, peak_file = tempfile.mkstemp(prefix="timing-")
        os.close(fd)
        launch = [GNU_TIME, "-f", "%M", "-o", peak_file, *cmd]
    try:
        start = time.perf_counter()
        proc = subprocess.Popen(launch, stdin=inp, stdout=out, stderr=subprocess.PIPE)
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
        text = ""
        if keep_stdout:
            out.seek(0)
            text = out.read().decode(errors="replace")
    finally:
        if peak_file:
            os.unlink(peak_file)
        if stdin:
            inp.close()
        if keep_stdout:
            out.close()
    code = os.waitstatus_to_exitcode(status)
    if code != 0:
        sys.stderr.write(err.decode(errors="replace"))
        raise SystemExit(f"timing.py: {' '.join(cmd)}: exit status {code}")
    return Run(wall, peak, err.decode(errors="replace"), text)


def measure(cmd, runs=RUNS, warmup=WARMUP, stdin=None):
    """(median wall seconds of `runs` runs after `warmup` ones, by `medians`;
    peak KB: of one more run through GNU time, or of the timed runs without
    it)."""
    peaks = []
    median, _, _ = medians(cmd, lambda r: peaks.append(r.peak), runs, warmup, stdin)
    if os.access(GNU_TIME, os.X_OK):
        return median, run_once(cmd, stdin, gnu_time=True)[1]
    if not _warned:
        _warned.append(True)
        sys.stderr.write("timing.py: no GNU time: peaks include this script's ~14 MB\n")
    return median, max(peaks)


def medians(cmd, read, runs=RUNS, warmup=WARMUP, stdin=None, keep_stdout=False):
    """The same rule for a figure the command reports itself (a render
    time it prints, polyfill3's `--json` seconds): `warmup` unmeasured
    runs, then `runs` runs; (median wall seconds, median of `read(run)`
    over the runs where it is not None (None when it never is), the last
    `Run`). `runs` may be a function of the last warm-up's wall seconds,
    for a benchmark that runs a slow command fewer times."""
    warm = None
    for _ in range(warmup):
        warm = run_logged(cmd, stdin, keep_stdout=keep_stdout).wall
    if callable(runs):
        runs = runs(warm)
    walls, figures, last = [], [], None
    for _ in range(runs):
        last = run_logged(cmd, stdin, keep_stdout=keep_stdout)
        walls.append(last.wall)
        figure = read(last)
        if figure is not None:
            figures.append(figure)
    return (statistics.median(walls), statistics.median(figures) if figures else None, last)


def phases_of(stderr):
    """The phases of scene-render's `--timings` line (`scene-render:
    timings: read 0.1 s, render 0.2 s, write 0.0 s (N polygons)`) as
    {name: seconds}; {} when there is none."""
    m = re.search(r"timings: ([^(\n]*)", stderr)
    if not m:
        return {}
    return {name: float(s) for name, s in re.findall(r"([a-z]+) ([0-9.]+) s", m.group(1))}


def measure_in_turns(cmds, runs=RUNS, warmup=WARMUP, stdin=None):
    """For each command of `cmds`: (median wall seconds, {phase: median
    seconds}) of `runs` rounds after `warmup` ones, the phases being those of
    a scene-render `--timings` line on its standard error (a pipeline ending
    in one is `["sh", "-c", ...]`; {} for other commands). The
    commands take turns in each round, so that a slow spell of this shared
    machine falls on all of them (medians of one build's runs, then of the
    other's, moved by 10-20% between two runs of a script minutes apart,
    bench/RESULTS-stream.md)."""
    for _ in range(warmup):
        for cmd in cmds:
            run_logged(cmd, stdin)
    walls = [[] for _ in cmds]
    logs = [[] for _ in cmds]
    for _ in range(runs):
        for cmd, w, lg in zip(cmds, walls, logs):
            r = run_logged(cmd, stdin)
            w.append(r.wall)
            lg.append(phases_of(r.stderr))
    out = []
    for w, lg in zip(walls, logs):
        names = lg[0].keys() if lg else []
        out.append((statistics.median(w), {n: statistics.median(p[n] for p in lg) for n in names}))
    return out


def main(argv):
    runs, warmup, stdin, phases = RUNS, WARMUP, None, []
    while argv and argv[0] != "--":
        flag, value, argv = argv[0], argv[1], argv[2:]
        if flag == "--runs":
            runs = int(value)
        elif flag == "--warmup":
            warmup = int(value)
        elif flag == "--stdin":
            stdin = value
        elif flag == "--phase":
            phases.append(value)
        else:
            raise SystemExit(f"timing.py: unknown option {flag}")
    if not argv[1:]:
        raise SystemExit(__doc__)
    cmds = [[]]
    for word in argv[1:]:
        if word == "--":
            cmds.append([])
        else:
            cmds[-1].append(word)
    if len(cmds) > 1 and not phases:
        if not all(cmds):
            raise SystemExit(__doc__)
        gnu = os.access(GNU_TIME, os.X_OK)
        for cmd, (median, _) in zip(cmds, measure_in_turns(cmds, runs, warmup, stdin)):
            print(f"{median:.4f} {run_once(cmd, stdin, gnu_time=gnu)[1]}")
        return
    if phases:
        (median, found), = measure_in_turns([argv[1:]], runs, warmup, stdin)
        missing = [n for n in phases if n not in found]
        if missing:
            raise SystemExit(f"timing.py: no {', '.join(missing)} phase in {' '.join(argv[1:])}'s --timings line")
        peak = run_once(argv[1:], stdin, gnu_time=os.access(GNU_TIME, os.X_OK))[1]
        print(f"{median:.4f} {peak} " + " ".join(f"{found[n]:.4f}" for n in phases))
        return
    median, peak = measure(argv[1:], runs, warmup, stdin)
    print(f"{median:.4f} {peak}")


if __name__ == "__main__":
    main(sys.argv[1:])
