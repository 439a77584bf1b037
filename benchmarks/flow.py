"""Moves that flow ``through`` their keyframes against stop-and-go: for a sweep and for
the library's waves rewritten with ``through`` on every move that can take it (no
stagger, not a call), the duration of both plans, the crossings taken at speed and the
slowest of them, and every limit checked: each servo's velocity, acceleration and jerk
on the planned tracks (as a share of its limit), and on the stream the 20 ms rule
(frame coverage) and the link (busiest frame).

    python benchmarks/flow.py
"""

from __future__ import annotations

import re

import numpy as np

from inmoov_dsl import load_library, load_profile, measure
from inmoov_dsl.compiling.compiler import compile_program
from inmoov_dsl.language.load import load

SWEEPS = {
    "sweep": "sweep:\n    wrist 90 through\n    wrist 180\n",
    "sweep, timed": "sweep:\n    wrist 90 over 0.3s through\n    wrist 180 over 0.3s\n",
    "index in 4": "sweep:\n    index 45 through\n    index 90 through\n    index 135 through\n"
                  "    index 180\n",
    "arc": "sweep:\n    index 60 through\n    index 120, middle 90 through\n"
           "    index 180, middle 0\n",
}
WAVES = ("wiggle", "wave", "drum", "bye")
MOVE = re.compile(r"^(\s+)(?!wait\b|hold\b|repeat\b)(\w+ \d.*?)(\s*#.*)?$")


def flowing(text: str) -> str:
    """``text`` with ``through`` on every move step that can take it."""
    out = []
    for line in text.splitlines():
        m = MOVE.match(line)
        if m and "stagger" not in line and ":" not in line:
            line = f"{m[1]}{m[2]} through{m[3] or ''}"
        out.append(line)
    return "\n".join(out) + "\n"


def figures(source: str, name: str, profile):
    compiled, plan = compile_program(load("bench.gest", source), name, profile)
    crossings = []
    for step in plan.steps[:-1]:
        for i in step.servos:
            v = abs(float(plan.tracks[i].velocity(step.end)))
            if v > 1e-6:
                crossings.append(v)
    times = np.linspace(0, plan.duration, 20001)
    worst = [0.0, 0.0, 0.0]
    for servo, track in zip(profile.servos, plan.tracks, strict=True):
        worst[0] = max(worst[0], np.abs(track.velocity(times)).max() / servo.max_velocity)
        worst[1] = max(worst[1], np.abs(track.acceleration(times)).max()
                       / servo.max_acceleration)
        worst[2] = max(worst[2], np.abs(track.coefs[:, 3]).max() / servo.max_jerk)
    (r,) = (r for r in measure(plan, compiled.streams) if r.bytes > 1)
    return plan.duration, crossings, worst, r


def main() -> None:
    rhand = load_profile("rhand")
    library = load_library()
    cases = [(label, src.replace(" through", ""), src, "sweep") for label, src in SWEEPS.items()]
    for name in WAVES:
        text = library[name].read_text()
        cases.append((name, text, flowing(text), name))
    print("| gesture | stop-and-go | through | saved | crossings at speed | slowest "
          "crossing | peak v / a / j of the limits | coverage | busiest frame |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for label, stopping, flows, name in cases:
        before, _, _, _ = figures(stopping, name, rhand)
        after, crossings, worst, r = figures(flows, name, rhand)
        slowest = f"{min(crossings):.0f} deg/s" if crossings else "-"
        print(f"| {label} | {before:.2f} s | {after:.2f} s | "
              f"{100 * (1 - after / before):.0f}% | {len(crossings)} | {slowest} | "
              f"{100 * worst[0]:.0f}% / {100 * worst[1]:.0f}% / {100 * worst[2]:.0f}% | "
              f"{100 * r.coverage:.1f}% | {100 * r.peak_utilisation:.0f}% |")


if __name__ == "__main__":
    main()
