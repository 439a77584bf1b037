"""Compile time of long gestures on a 28-servo robot (six boards at 9600 baud).

Target: a 1,000-step gesture in under 1 s, and time growing linearly from 100 to
10,000 steps. Measured in-process: parse, resolve, plan (ruckig), encode.

    python benchmarks/scale.py
"""

from __future__ import annotations

from dataclasses import replace

from common import HERE, best_and_median, random_gesture

from inmoov_dsl import load_profile, measure
from inmoov_dsl.compiling.compiler import compile_program
from inmoov_dsl.language.load import load


def main() -> None:
    profile = load_profile(str(HERE / "inmoov28.toml"))
    print(f"profile {profile.name}: {len(profile.servos)} servos on "
          f"{len(profile.boards)} boards")
    print("| steps | gesture length | bytes (all boards) | compile, best | median | per step |")
    print("|---:|---:|---:|---:|---:|---:|")
    per_step = {}
    for steps in (100, 1_000, 10_000):
        source = random_gesture(list(profile.names), steps)
        runs = 5 if steps <= 1_000 else 3

        def once(source=source):
            return compile_program(load("big.gest", source), "big", profile)[0]

        compiled = once()
        best, median = best_and_median(once, runs)
        per_step[steps] = best / steps
        size = sum(len(s.data) for s in compiled.streams)
        print(f"| {steps:,} | {compiled.duration:,.0f} s | {size:,} | {best * 1000:,.0f} ms | "
              f"{median * 1000:,.0f} ms | {best / steps * 1e6:,.0f} us |")
    print(f"\nper-step time, 10,000 vs 100 steps: {per_step[10_000] / per_step[100]:.2f}x "
          f"(1.0 = linear)")

    # the same robot with every servo on one 9600-baud board: the link is the bottleneck
    one = replace(profile, boards=(replace(profile.boards[0], servos=profile.names),))
    source = random_gesture(list(one.names), 1_000)
    best, _ = best_and_median(lambda: compile_program(load("big.gest", source), "big", one), 3)
    compiled, plan = compile_program(load("big.gest", source), "big", one)
    (r,) = measure(plan, compiled.streams)
    print(f"\n1,000 steps, all 28 servos on one 9600-baud board: {best * 1000:,.0f} ms; "
          f"coverage {100 * r.coverage:.1f}%, worst lag {r.worst_lag:.1f} deg, "
          f"link use {100 * r.utilisation:.0f}%")


if __name__ == "__main__":
    main()
