"""How soon after Ctrl-C does the CANCEL reach the board? gestplay plays `demo` to a
board on a pseudo-terminal (gestsim, and the servo_rhand image in simavr), a SIGINT
comes at a random moment of the gesture, and the board's log tells when the last byte
(the CANCEL) reached it. POSIX, needs the AVR toolchain and simavr for the second
board; ~2 min.

    python benchmarks/stop.py [--trials 10]

The player drops what the port holds before it sends CANCEL, but a pty's other end
keeps what it has read (as a USB adapter's chip does): at most the horizon.
"""

from __future__ import annotations

import argparse
import random
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
TAU = 1 / 960


def board(kind: str, log: Path, build: Path) -> subprocess.Popen:
    if kind == "gestsim":
        argv = [sys.executable, "-m", "inmoov_dsl.cli.gestsim", "--quiet", "--boot", "0.2",
                "--log", str(log)]
    else:
        argv = [str(build / "harness" / "simboard"), str(build / "servo_rhand.elf"), "--pty",
                "--log", str(log)]
    return subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)


def trial(kind: str, build: Path, rng: random.Random, tmp: Path) -> float:
    """Seconds from SIGINT to the CANCEL reaching the board."""
    log = tmp / f"{kind}.log"
    proc = board(kind, log, build)
    path = proc.stdout.readline().strip()
    try:
        player = subprocess.Popen([sys.executable, "-m", "inmoov_dsl.cli.gestplay", "demo",
                                   "--port", path], stderr=subprocess.DEVNULL)
        while b" 1\n" not in log.read_bytes():
            time.sleep(0.02)
        time.sleep(rng.uniform(0.5, 8.0))
        signalled = time.monotonic()
        player.send_signal(signal.SIGINT)
        player.wait(timeout=10)
        time.sleep(0.1)
        last = float(log.read_text().splitlines()[-1].split()[0])
        return last + TAU - signalled
    finally:
        proc.kill()
        proc.wait()


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--trials", type=int, default=10)
    args = ap.parse_args()
    rng = random.Random(27)
    with tempfile.TemporaryDirectory() as tmp:
        build = Path(tmp) / "build"
        done = subprocess.run(["make", "-C", str(ROOT / "firmware"), "-j2", f"BUILD={build}",
                               "servo_rhand", "harness"], capture_output=True, text=True)
        kinds = ["gestsim"] + (["simavr"] if done.returncode == 0 else [])
        print("| board on the pty | trials | median ms | p90 ms | worst ms |")
        print("|---|---:|---:|---:|---:|")
        for kind in kinds:
            delays = sorted(1000 * trial(kind, build, rng, Path(tmp))
                            for _ in range(args.trials))
            print(f"| {kind} | {len(delays)} | {statistics.median(delays):.1f} | "
                  f"{delays[int(0.9 * len(delays)) - 1]:.1f} | {delays[-1]:.1f} |", flush=True)
        if done.returncode != 0:
            print("(simavr: the image or the harness did not build)")


if __name__ == "__main__":
    main()
