"""How close to its schedule does a stream reach the board? Play a library gesture
repeated to about a minute, through a real pseudo-terminal opened with pyserial, to a
separate process that timestamps every byte as it arrives, on an idle machine and with
one core, then both, kept busy by other processes; beside it, the same stream written one byte at a
time on the same clock, and (idle only) sent the way the original script did, sleeping
after each byte.

    python benchmarks/timing.py [--gesture count] [--seconds 60]

Errors are arrival time minus planned time, less their median (the pty's constant
latency, and the clocks' different origins, are not counted against any sender; a late
first byte would shift every other one if they were counted from it). A pty has no baud
rate, so the wire is modelled at the receiver: a byte reaches the board when it has
arrived and the byte before it has been on the wire for a byte-time (what a UART does
with a write of several bytes). "As written" is measured in the sender, when each write
returned (the wire modelled likewise), which tells a late sender from a late receiver.
The relative sender sleeps exactly the planned gap after each byte: the most generous
version of "a fixed sleep after each byte". POSIX only (pseudo-terminals).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import select
import subprocess
import sys
import time

import numpy as np

from inmoov_dsl import compile_source, load_library
from inmoov_dsl.wire.player import Link, play, schedule, wait_until
from inmoov_dsl.wire.ports import open_port


def receive() -> None:
    """The timestamping end: prints its pty path, then for each line on stdin prints
    the (time, byte) pairs received since the last one, as JSON."""
    import tty

    master, slave = os.openpty()
    tty.setraw(slave)
    print(os.ttyname(slave), flush=True)
    stamps: list[tuple[float, int]] = []
    poller = select.poll()
    poller.register(master, select.POLLIN)
    poller.register(sys.stdin.fileno(), select.POLLIN)
    while True:
        for fd, _ in poller.poll():
            now = time.monotonic()
            if fd == master:
                stamps += [(now, b) for b in os.read(master, 4096)]
            elif sys.stdin.readline():
                print(json.dumps(stamps), flush=True)
                stamps = []
            else:
                return


def relative_sleeps(port, times: np.ndarray, data: bytes) -> None:
    """How the original script sent: write a byte, sleep, write the next."""
    gaps = np.diff(times, append=times[-1])
    for byte, gap in zip(data, gaps.tolist(), strict=True):
        port.write(bytes([byte]))
        time.sleep(gap)


class Stamped:
    """A port that also notes when each write returned (the sender's own view)."""

    def __init__(self, port):
        self.port, self.sent = port, []

    def write(self, data: bytes) -> int:
        n = self.port.write(data)
        self.sent += [(time.monotonic(), b) for b in data]
        return n

    def read(self, size: int = 1) -> bytes:
        return self.port.read(size)


def on_the_wire(stamps: list, tau: float) -> list:
    """When each byte reaches the board: not before it arrived, and a byte-time after
    the byte before it (a UART's pace; the pty delivers a write at once)."""
    out, free = [], -math.inf
    for t, b in stamps:
        free = max(t, free + tau)
        out.append((free, b))
    return out


def per_byte(compiled, link) -> None:
    """gestplay's clock, one write per byte (as it played before writes were runs)."""
    events = schedule(compiled, [link])
    start = time.perf_counter()
    for t, _, byte in events:
        wait_until(start + t, [link], time.perf_counter, time.sleep)
        link.port.write(bytes([byte]))


def errors(stamps: list, times: np.ndarray, data: bytes) -> np.ndarray:
    arrived = np.array([t for t, _ in stamps])
    assert bytes(b for _, b in stamps) == data, "bytes lost or changed on the way"
    late = arrived - times
    return late - np.median(late)


def summary(name: str, e: np.ndarray, sent: np.ndarray, times: np.ndarray) -> str:
    ms = np.abs(e) * 1000
    slope = np.polyfit(times, e, 1)[0] * 60 * 1000  # ms per minute
    tail = e[times > times[-1] - 5].mean() * 1000
    own = np.abs(sent) * 1000
    return (f"| {name} | {np.percentile(ms, 50):.3f} | {np.percentile(ms, 99):.3f} | "
            f"{ms.max():.3f} | {np.percentile(own, 99):.3f} / {own.max():.3f} | "
            f"{tail:+.2f} | {slope:+.2f} |")


def main() -> None:
    if sys.argv[1:2] == ["--receive"]:
        receive()
        return
    ap = argparse.ArgumentParser()
    ap.add_argument("--gesture", default="count")
    ap.add_argument("--seconds", type=float, default=60.0)
    ap.add_argument("--busy", type=int, nargs="+", choices=(0, 1, 2), default=[0, 1, 2],
                    help="cores kept busy by other processes, for each run (default 0 1 2)")
    args = ap.parse_args()
    path = load_library()[args.gesture]
    one = compile_source(f'use "{path.name}"\nbench: {args.gesture}\n').duration
    times_over = max(1, math.ceil(args.seconds / one))
    compiled = compile_source(f'use "{path.name}"\nbench:\n    repeat {times_over}: '
                              f"{args.gesture}\n")
    stream = compiled.stream()
    receiver = subprocess.Popen([sys.executable, __file__, "--receive"], text=True,
                                stdin=subprocess.PIPE, stdout=subprocess.PIPE)
    device = receiver.stdout.readline().strip()
    port = open_port(device, stream.baud)
    print(f"{args.gesture} x{times_over}: {compiled.duration:.1f} s, {len(stream.data):,} "
          f"bytes, through {device} ({sys.platform}, Python {sys.version.split()[0]})\n")
    print("| machine | sender | p50 ms | p99 ms | max ms | as written: p99 / max ms "
          "| error over the last 5 s, ms | drift, ms per minute |")
    print("|---|---|---:|---:|---:|---:|---:|---:|")
    senders = [
        ("gestplay (runs of bytes in one write)",
         lambda p: play(compiled, [Link(181, p, device)])),
        ("gestplay's clock, one write per byte", lambda p: per_byte(compiled,
                                                                    Link(181, p, device))),
        ("sleep after each byte", lambda p: relative_sleeps(p, stream.times, stream.data)),
    ]
    loads = (("idle", 0), ("one core busy", 1), ("both cores busy", 2))
    for machine, busy in (loads[k] for k in args.busy):
        hogs = [subprocess.Popen([sys.executable, "-c", "while True: pass"])
                for _ in range(busy)]
        try:
            for name, send in senders[:2] if hogs else senders:
                stamped = Stamped(port)
                send(stamped)
                time.sleep(0.2)
                receiver.stdin.write("\n")
                receiver.stdin.flush()
                stamps = on_the_wire(json.loads(receiver.stdout.readline()),
                                     stream.byte_time)
                row = summary(name, errors(stamps, stream.times, stream.data),
                              errors(on_the_wire(stamped.sent, stream.byte_time),
                                     stream.times, stream.data), stream.times)
                print(f"| {machine} {row}", flush=True)
        finally:
            for hog in hogs:
                hog.kill()
                hog.wait()
    port.close()
    receiver.stdin.close()
    receiver.wait()


if __name__ == "__main__":
    main()
