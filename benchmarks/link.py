"""The link, gesture by gesture: bytes, duration, frame coverage, worst lag and link use of
every library gesture at 9600 and 115200 baud (hand gestures on rhand, whole-robot ones
on inmoov, one row per board that moves), bytes against naive streaming (every servo
every 20 ms frame); then what one link for the whole robot needs: every board's servos
on one board, at each baud.

    python benchmarks/link.py [--baud 9600 115200]
"""

from __future__ import annotations

import argparse
from dataclasses import replace

from common import library_gestures

from inmoov_dsl import load_profile, measure
from inmoov_dsl.compiling.compiler import compile_program
from inmoov_dsl.hardware import Board

ROBOT_BAUDS = (9600, 19200, 38400, 57600, 115200)


def at_baud(profile, baud):
    return replace(profile, boards=tuple(replace(b, baud=baud) for b in profile.boards))


def one_link(profile, baud):
    """Every servo of ``profile`` on one board: a robot routed through one central link."""
    names = tuple(name for b in profile.boards for name in b.servos)
    servos = tuple(replace(s, board=profile.boards[0].id) for s in profile.servos)
    board = Board(profile.boards[0].id, "whole robot", baud, names)
    return replace(profile, boards=(board,), servos=servos)


def row(name, profile, duration, r) -> str:
    saved = 100 * (1 - r.bytes / r.naive_bytes) if r.naive_bytes else 0.0
    return (f"| {name} | {profile} | {r.board} | {r.baud} | {duration:.2f} s | {r.bytes:,} | "
            f"{r.naive_bytes:,} | {saved:.0f}% | {100 * r.coverage:.1f}% | "
            f"{r.worst_lag:.2f} deg | {100 * r.utilisation:.0f}% / "
            f"{100 * r.peak_utilisation:.0f}% |")


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--baud", type=int, nargs="*", default=[9600, 115200])
    args = ap.parse_args()
    targets = library_gestures()
    print("| gesture | profile | board | baud | duration | bytes | naive bytes | saved | "
          "coverage | worst lag | link use (mean / peak frame) |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for baud in args.baud:
        for name, program, profile in targets:
            compiled, plan = compile_program(program, name, at_baud(profile, baud))
            for r in measure(plan, compiled.streams):
                if not r.idle:  # a board the gesture does not move gets CANCEL only
                    print(row(name, profile.name, compiled.duration, r))
    print()
    print("Whole-robot gestures with all 28 servos on one link:")
    print()
    print("| gesture | baud | bytes | coverage | worst lag | link use (mean / peak frame) |")
    print("|---|---:|---:|---:|---:|---:|")
    inmoov = load_profile("inmoov")
    for name, program, profile in targets:
        if profile.name != inmoov.name:
            continue
        for baud in ROBOT_BAUDS:
            compiled, plan = compile_program(program, name, one_link(inmoov, baud))
            (r,) = measure(plan, compiled.streams)
            print(f"| {name} | {baud} | {r.bytes:,} | {100 * r.coverage:.1f}% | "
                  f"{r.worst_lag:.2f} deg | {100 * r.utilisation:.0f}% / "
                  f"{100 * r.peak_utilisation:.0f}% |")


if __name__ == "__main__":
    main()
