"""From opening the port to the board's first byte: our firmware behind each Arduino's
bootloader in simavr (firmware/harness, ``simboard --bootloader``), served on a pty in
real time as a board on its USB port is. Opening the port raises DTR and resets the
board into its bootloader; the figures are the wall time from the open to the first
byte the board sends (our firmware's WAIT), with nothing sent, with one stray byte in
the bootloader's window (0xFF: the CANCEL a host probes with), and with a host that
probes every 100 ms as gestplay did before it learnt to listen first.

The bootloaders are the hexes Debian ships (arduino-core-avr), but the Uno's: Debian's
optiboot does not fit the Uno's flash, and `make -C firmware optiboot` builds the same
source to fit. A stray byte is sent at the profile's baud (9600 for a hand, 115200 for a
Mega; at another baud than its own the bootloader reads it garbled, as a real UART
does) and, for the Uno and the Nano, at the bootloader's own baud (a profile at 115200).

    python benchmarks/boot.py [--runs 5] [--uno HEX] [--nano HEX] [--mega HEX]

(--uno etc.: another hex for that board, e.g. Arduino's own.) Needs make, gcc-avr,
avr-libc, arduino-core-avr, simavr, libsimavr-dev; POSIX; ~3 min.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import serial

ROOT = Path(__file__).resolve().parent.parent
DEBIAN = Path("/usr/share/arduino/hardware/arduino/avr/bootloaders")
PROBE = 0.1  #: s between the probing host's CANCELs
LIMIT = 15.0  #: s; the longest we wait for a first byte
STRAYS = (0.05, 0.3, 0.7)  #: s after the open when the one stray byte goes


@dataclass(frozen=True)
class Board:
    """An Arduino with our firmware behind its bootloader."""

    name: str
    sketch: str
    hex: Path
    baud: int  #: the profile's, our firmware's
    own: int  #: the bootloader's


def boards(build: Path, args: argparse.Namespace) -> list[Board]:
    """The three boards, each with the hex given for it or the default."""
    def named(board: str, given: Path | None, default: str) -> str:
        return f"{board} ({given.name})" if given else f"{board} ({default})"

    return [
        Board(named("Uno", args.uno, "optiboot, built from Debian's source"), "servo_rhand",
              args.uno or build / "bootloaders" / "optiboot_atmega328.hex", 9600, 115200),
        Board(named("old Nano", args.nano, "ATmegaBOOT, Debian's"), "servo_rhand",
              args.nano or DEBIAN / "atmega" / "ATmegaBOOT_168_atmega328.hex", 9600, 57600),
        Board(named("Mega 2560", args.mega, "stk500v2, Debian's"), "servo_inmoov_right",
              args.mega or DEBIAN / "stk500v2" / "stk500boot_v2_mega2560.hex", 115200, 115200),
    ]


def first_byte(path: str, board: Board, sends: list[tuple[float, int]],
               at: int | None = None) -> float | None:
    """Seconds from the port's open (DTR rising: a reset) to the first byte the board
    sends, while ``sends`` (s after the open, byte) go out at baud ``at`` (the port is
    set back to the firmware's baud 20 ms after each); None after LIMIT s. The port is
    closed as a program leaves it by default (HUPCL: DTR drops), so the next open
    resets the board again."""
    port = serial.Serial(path, board.baud, timeout=0)
    start = time.monotonic()
    port.reset_input_buffer()  # what the board said while the port was closed
    sends = sorted(sends)
    back = None  # when to set the port back to the firmware's baud
    try:
        while (now := time.monotonic() - start) < LIMIT:
            if sends and sends[0][0] <= now:
                if at:
                    port.baudrate = at
                port.write(bytes([sends.pop(0)[1]]))
                back = now + 0.02 if at else None
            if back is not None and now >= back:
                port.baudrate, back = board.baud, None
            if port.read(1):
                return now
            time.sleep(0.001)
        return None
    finally:
        port.close()
        time.sleep(0.3)  # the harness sees the port closed (DTR down) before the next open


def shown(t: float | None) -> str:
    return f"{t:.2f} s" if t is not None else f"none in {LIMIT:.0f} s"


def measure(build: Path, board: Board, runs: int) -> list[str]:
    """The table's rows for ``board``: one with the stray byte at the profile's baud,
    one at the bootloader's own if it differs."""
    proc = subprocess.Popen([str(build / "harness" / "simboard"),
                             str(build / f"{board.sketch}.elf"), "--pty", "--baud",
                             str(board.baud), "--bootloader", str(board.hex)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    path = proc.stdout.readline().strip()
    if not path.startswith("/dev/"):
        return [f"| {board.name} | (the harness did not start: {proc.stderr.read().strip()}) |"]
    try:
        time.sleep(2.0)  # powered up a while ago: the bootloader has run the firmware
        quiet = [first_byte(path, board, []) for _ in range(runs)]
        known = [t for t in quiet if t is not None]
        spread = f"{statistics.median(known):.2f} s ({min(known):.2f}-{max(known):.2f})" \
            if known else shown(None)
        rows = []
        for at in dict.fromkeys((board.baud, board.own)):
            strays = [shown(first_byte(path, board, [(t, 0xFF)], at)) for t in STRAYS]
            probing = [(PROBE * k, 0xFF) for k in range(1, int(LIMIT / PROBE))]
            then_quiet = [(PROBE * k, 0xFF) for k in range(1, 40)]
            cells = [f"{board.name}", f"{at}", spread, *strays,
                     shown(first_byte(path, board, probing, at)),
                     shown(first_byte(path, board, then_quiet, at))]
            rows.append("| " + " | ".join(cells) + " |")
        return rows
    finally:
        proc.kill()
        proc.wait()


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=5, help="opens with nothing sent (default 5)")
    ap.add_argument("--uno", type=Path, help="the Uno's bootloader hex")
    ap.add_argument("--nano", type=Path, help="the old Nano's")
    ap.add_argument("--mega", type=Path, help="the Mega's")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        build = Path(tmp)
        done = subprocess.run(["make", "-C", str(ROOT / "firmware"), "-j2", f"BUILD={build}",
                               "servo_rhand", "servo_inmoov_right", "harness", "optiboot"],
                              capture_output=True, text=True)
        if done.returncode != 0:
            sys.exit(f"the images or the harness did not build:\n{done.stdout}{done.stderr}")
        print("| board (bootloader) | stray bytes at (baud) | nothing sent: first byte, "
              f"median of {args.runs} (range) | " +
              " | ".join(f"one 0xFF at {t} s" for t in STRAYS) +
              " | 0xFF every 0.1 s | 0xFF every 0.1 s for 3.9 s, then nothing |")
        print("|---|---:|---:|" + "---:|" * (len(STRAYS) + 2))
        for board in boards(build, args):
            for row in measure(build, board, args.runs):
                print(row, flush=True)


if __name__ == "__main__":
    main()
