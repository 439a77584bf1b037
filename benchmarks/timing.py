"""How close to its schedule does a stream reach the board? gestplay plays a library
gesture repeated to about a minute through a real pseudo-terminal, opened with
pyserial, to gestsim, whose UART takes bytes from the pty as a real one does (5 ms
ahead of the wire) and logs when each byte starts on the wire; on an idle machine, then
with one core and with both cores kept busy by other processes; three runs each.

    python benchmarks/timing.py [--gesture count] [--seconds 60] [--runs 3]

The player sends the stream as one continuous run (CANCEL between commands, 10 ms
ahead of the wire: wire/pace.py). The error of a byte of the stream (the filler is not
counted) is when it reached the board minus its planned time, both from the run's
first byte; less the median, as before, though it is 0 here. gestsim stands in for the
board's hardware: it runs at real-time priority (SCHED_FIFO) where the system allows,
so that the load delays the sender, not the wire. POSIX only (pseudo-terminals).
"""

from __future__ import annotations

import argparse
import contextlib
import math
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from inmoov_dsl import compile_source, load_library
from inmoov_dsl.protocol import Signal
from inmoov_dsl.wire.player import Link, play
from inmoov_dsl.wire.ports import open_port
from inmoov_dsl.wire.ready import wait_ready


def arrivals(log: Path, skip: int, data: bytes, tau: float) -> np.ndarray:
    """When each byte of ``data`` reached the board, from the log's lines after
    ``skip``: the run's first byte is the stream's CANCEL, every other byte of the
    stream is a pair's (no 255), and the 255s between them are filler."""
    rows = [line.split() for line in log.read_text().splitlines()[skip:]]
    got = [(float(t) + tau, int(b)) for t, b in rows]
    first = next(k for k, (_, b) in enumerate(got) if b == Signal.CANCEL)
    real = [got[first]] + [g for g in got[first + 1:] if g[1] != Signal.CANCEL]
    assert bytes(b for _, b in real[:len(data)]) == data, "bytes lost or changed"
    return np.array([t for t, _ in real[:len(data)]])


def summary(e: np.ndarray, times: np.ndarray) -> tuple[float, float, float, float]:
    """p50, p99, max of |error| (ms), drift (ms per minute)."""
    ms = np.abs(e) * 1000
    slope = np.polyfit(times, e, 1)[0] * 60 * 1000
    return np.percentile(ms, 50), np.percentile(ms, 99), ms.max(), slope


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--gesture", default="count")
    ap.add_argument("--seconds", type=float, default=60.0)
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--busy", type=int, nargs="+", choices=(0, 1, 2), default=[0, 1, 2],
                    help="cores kept busy by other processes, for each run (default 0 1 2)")
    args = ap.parse_args()
    path = load_library()[args.gesture]
    one = compile_source(f'use "{path.name}"\nbench: {args.gesture}\n').duration
    times_over = max(1, math.ceil(args.seconds / one))
    compiled = compile_source(f'use "{path.name}"\nbench:\n    repeat {times_over}: '
                              f"{args.gesture}\n")
    stream = compiled.stream()
    tau = stream.byte_time
    with tempfile.TemporaryDirectory() as tmp:
        log = Path(tmp) / "received.log"
        env = dict(os.environ, INMOOV_DSL_STATE=tmp)
        board = subprocess.Popen([sys.executable, "-m", "inmoov_dsl.cli.gestsim", "--quiet",
                                  "--boot", "0", "--log", str(log)], env=env, text=True,
                                 stdout=subprocess.PIPE, stderr=subprocess.DEVNULL)
        device = board.stdout.readline().strip()
        realtime = "yes"
        try:
            os.sched_setscheduler(board.pid, os.SCHED_FIFO, os.sched_param(10))
        except (AttributeError, PermissionError, OSError):
            realtime = "no (not allowed here)"
        port = open_port(device, stream.baud)
        assert wait_ready(port), "gestsim did not answer"
        print(f"{args.gesture} x{times_over}: {compiled.duration:.1f} s, {len(stream.data):,} "
              f"bytes of stream, through {device} to gestsim (real-time priority: "
              f"{realtime}; {sys.platform}, Python {sys.version.split()[0]})\n")
        print("| machine | run | p50 ms | p99 ms | max ms | drift, ms per minute "
              "| worst lateness gestplay reports, ms |")
        print("|---|---:|---:|---:|---:|---:|---:|")
        loads = (("idle", 0), ("one core busy", 1), ("both cores busy", 2))
        try:
            for machine, busy in (loads[k] for k in args.busy):
                hogs = [subprocess.Popen([sys.executable, "-c", "while True: pass"])
                        for _ in range(busy)]
                try:
                    for run in range(1, args.runs + 1):
                        time.sleep(0.3)
                        skip = len(log.read_text().splitlines())
                        late = play(compiled, [Link(181, port, device)])
                        time.sleep(0.3)
                        arrived = arrivals(log, skip, stream.data, tau)
                        late_ms = (arrived - arrived[0]) - (stream.times - stream.times[0])
                        e = late_ms - np.median(late_ms)
                        p50, p99, worst, drift = summary(e, stream.times)
                        print(f"| {machine} | {run} | {p50:.3f} | {p99:.3f} | {worst:.3f} | "
                              f"{drift:+.2f} | {late * 1000:.3f} |", flush=True)
                finally:
                    for hog in hogs:
                        hog.kill()
                        hog.wait()
        finally:
            port.close()
            board.kill()
            with contextlib.suppress(subprocess.TimeoutExpired):
                board.wait(5)


if __name__ == "__main__":
    main()
