"""The firmware: flash and RAM of every board beside the original servo firmware's
3,872 bytes, and the EEPROM writes that the library's gestures cost the right hand's
board (each gesture played on the built image in simavr, from rest, then a second and a
half of stillness), with the lifetime that gives. With --stored: flash and RAM of
servo_rhand alone, with the stored-gesture player, and with the whole right-hand
library stored, and what each gesture costs in flash.

    python benchmarks/firmware.py [--per-day 1000] [--stored]

Needs make, gcc-avr, avr-libc, arduino-core-avr, simavr, libsimavr-dev (.ci/run's list).
"""

from __future__ import annotations

import argparse
import re
import subprocess
import tempfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from common import ROOT, library_gestures

from inmoov_dsl import load_profile, to_timed
from inmoov_dsl.compiling.compiler import compile_program

ORIGINAL_FLASH = 3872  #: bytes: the original servo firmware, real Servo library, no LTO
CELL_WRITES = 100_000  #: erase/write cycles an ATmega328P EEPROM cell is rated for
EEPROM = 1024  #: bytes


def build(where: Path) -> str:
    done = subprocess.run(["make", "-C", str(ROOT / "firmware"), "-j2", f"BUILD={where}",
                           "all", "harness"], capture_output=True, text=True, check=True)
    return done.stdout


def records(writes: list[float]) -> int:
    """EEPROM byte writes (their times) grouped into records: a record's bytes go out
    one after another, a record comes at least a second after the one before."""
    times = sorted(writes)
    return sum(1 for k, t in enumerate(times) if k == 0 or t - times[k - 1] > 0.5)


def play(simboard: Path, elf: Path, name: str, timed: str) -> tuple[str, int, int]:
    with tempfile.TemporaryDirectory() as tmp:
        done = subprocess.run([str(simboard), str(elf), "--run-on", "1.5", "--eeprom",
                               str(Path(tmp) / "eeprom.bin")], input=timed,
                              capture_output=True, text=True, check=True)
    writes = [float(line.split()[1]) for line in done.stdout.splitlines()
              if line.startswith("eeprom ")]
    return name, len(writes), records(writes)


def stored() -> None:
    """servo_rhand alone, with the player and one empty gesture, with the whole library."""
    from inmoov_dsl.cli import gestc
    from inmoov_dsl.wire.stored import read_blob, read_set

    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for what, options in [("alone", []), ("with the player (`reset`: no pair)",
                                                ["--store", "reset"]),
                              ("with the whole right-hand library", ["--store", "all"])]:
            book = Path(tmp) / str(len(rows))
            gestc.main(["firmware", "rhand", "-o", str(book), *options])
            done = subprocess.run(["make", "-s", "-C", str(book), "servo_rhand"],
                                  capture_output=True, text=True, check=True)
            flash, ram = map(int, re.search(r"flash (\d+) .*RAM (\d+)", done.stdout).groups())
            blob = read_blob(book / "servo_rhand") if options else b""
            rows.append((what, flash, ram, len(blob)))
        flash_set = read_set(blob)
    print("| `servo_rhand` | flash (bytes) | of which stored | RAM (bytes) |")
    print("|---|---:|---:|---:|")
    for what, flash, ram, size in rows:
        print(f"| {what} | {flash:,} ({100 * flash / 30720:.0f}% of 30,720) | {size:,} | "
              f"{ram:,} |")
    wire = {name: len(compile_program(program, name, profile)[0].stream().data)
            for name, program, profile in library_gestures(("rhand",))}
    print()
    print("| gesture | duration (s) | on the wire (bytes) | stored stream (bytes) | "
          "bytes/s |")
    print("|---|---:|---:|---:|---:|")
    total = [0.0, 0, 0]
    for g in flash_set.gestures:
        seconds = g.frames * 0.02
        total = [total[0] + seconds, total[1] + wire[g.name], total[2] + len(g.data)]
        rate = f"{len(g.data) / seconds:.0f}" if seconds else "-"
        print(f"| {g.name} | {seconds:.2f} | {wire[g.name]:,} | {len(g.data):,} | {rate} |")
    print(f"| **{len(flash_set.gestures)} gestures** | {total[0]:.2f} | {total[1]:,} | "
          f"{total[2]:,} | {total[2] / total[0]:.0f} |")


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--per-day", type=int, default=1000, help="gestures a day")
    ap.add_argument("--stored", action="store_true", help="only the stored gestures' figures")
    args = ap.parse_args()
    if args.stored:
        stored()
        return
    with tempfile.TemporaryDirectory() as tmp:
        where = Path(tmp)
        sizes = build(where)
        print(f"| board | flash (bytes) | beside the original's {ORIGINAL_FLASH:,} (no LTO) | "
              f"RAM (bytes) |")
        print("|---|---:|---:|---:|")
        for name, flash, ram in re.findall(r"^(\w+): flash (\d+) of \d+ bytes \(\d+%\), "
                                           r"RAM (\d+)", sizes, re.M):
            ratio = f"{100 * int(flash) / ORIGINAL_FLASH:.0f}%" if name.startswith("servo") \
                else "(a glove)"
            print(f"| `{name}` | {int(flash):,} | {ratio} | {int(ram):,} |")
        print()
        rhand = load_profile("rhand")
        record = len(rhand.boards[0].servos) + 4
        slots = EEPROM // record
        jobs = []
        for name, program, profile in library_gestures(("rhand",)):
            compiled, _ = compile_program(program, name, profile)
            jobs.append((name, to_timed(compiled.stream())))
        simboard, elf = where / "harness" / "simboard", where / "servo_rhand.elf"
        with ThreadPoolExecutor(max_workers=2) as pool:
            rows = list(pool.map(lambda job: play(simboard, elf, *job), jobs))
    print("| gesture | EEPROM bytes written | records |")
    print("|---|---:|---:|")
    for name, written, count in rows:
        print(f"| {name} | {written} | {count} |")
    mean = sum(count for *_, count in rows) / len(rows)
    per_cell = args.per_day * mean / slots  # each record writes each cell of its slot once
    years = CELL_WRITES / per_cell / 365.25
    print()
    print(f"{len(rows)} gestures: {mean:.2f} records a gesture on average; a record is "
          f"{record} bytes, {slots} records go round the {EEPROM:,}-byte EEPROM. "
          f"{args.per_day:,} gestures a day write each cell {per_cell:.1f} times a day: "
          f"{CELL_WRITES:,} writes last {years:.0f} years.")


if __name__ == "__main__":
    main()
