"""How close to its schedule does a stream leave the computer? Play a library gesture
repeated to about a minute, through a real pseudo-terminal opened with pyserial, to a
separate process that timestamps every byte as it arrives; then send the same stream
the way the original script did, sleeping after each byte, and compare in one run.

    python benchmarks/timing.py [--gesture count] [--seconds 60]

Errors are arrival time minus planned time, both counted from the stream's first byte
(so the pty's constant latency is not counted against either sender); "as written"
is the same measured in the sender, when each write returned, which tells a late
sender from a late receiver. The relative
sender sleeps exactly the planned gap after each byte: the most generous version of
"a fixed sleep after each byte". POSIX only (pseudo-terminals).
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
from inmoov_dsl.player import Link, play
from inmoov_dsl.ports import open_port


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


def errors(stamps: list, times: np.ndarray, data: bytes) -> np.ndarray:
    arrived = np.array([t for t, _ in stamps])
    assert bytes(b for _, b in stamps) == data, "bytes lost or changed on the way"
    return (arrived - arrived[0]) - (times - times[0])


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
    print("| sender | p50 ms | p99 ms | max ms | as written: p99 / max ms "
          "| error over the last 5 s, ms | drift, ms per minute |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for name, send in [
        ("gestplay (one absolute clock)", lambda p: play(compiled, [Link(181, p, device)])),
        ("sleep after each byte", lambda p: relative_sleeps(p, stream.times, stream.data)),
    ]:
        stamped = Stamped(port)
        send(stamped)
        time.sleep(0.2)
        receiver.stdin.write("\n")
        receiver.stdin.flush()
        stamps = json.loads(receiver.stdout.readline())
        print(summary(name, errors(stamps, stream.times, stream.data),
                      errors(stamped.sent, stream.times, stream.data), stream.times),
              flush=True)
    port.close()
    receiver.stdin.close()
    receiver.wait()


if __name__ == "__main__":
    main()
