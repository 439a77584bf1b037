"""Bytes, frame coverage, worst lag and link use of every library gesture, and bytes
against naive streaming (every servo every 20 ms frame).

    python benchmarks/link.py [--baud 115200]
"""

from __future__ import annotations

import argparse
from dataclasses import replace

from inmoov_dsl import load_library, load_profile, measure
from inmoov_dsl.compiler import compile_program, load


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--baud", type=int, nargs="*", default=[9600, 115200])
    ap.add_argument("--profile", default="rhand")
    args = ap.parse_args()
    base = load_profile(args.profile)
    print("| gesture | baud | duration | bytes | naive bytes | saved | coverage | worst lag "
          "| link use (mean / peak frame) |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for baud in args.baud:
        profile = replace(base, boards=tuple(replace(b, baud=baud) for b in base.boards))
        for name, path in sorted(load_library().items()):
            compiled, plan = compile_program(load(str(path)), name, profile)
            for r in measure(plan, compiled.streams):
                print(f"| {name} | {baud} | {compiled.duration:.2f} s | {r.bytes:,} | "
                      f"{r.naive_bytes:,} | {100 * (1 - r.bytes / r.naive_bytes):.0f}% | "
                      f"{100 * r.coverage:.1f}% | {r.worst_lag:.2f} deg | "
                      f"{100 * r.utilisation:.0f}% / {100 * r.peak_utilisation:.0f}% |")


if __name__ == "__main__":
    main()
