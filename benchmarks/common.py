"""Shared helpers for the benchmarks: timing, generated gestures, a board's byte log."""

from __future__ import annotations

import random
import statistics
import time
from collections.abc import Callable
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent


def arrivals(log: Path) -> list[tuple[float, int]]:
    """(time, byte) of every byte a gestsim board has received (its ``--log``: when each
    started on the wire, by the monotonic clock)."""
    return [(float(t), int(b)) for t, b in map(str.split, log.read_text().splitlines())]


def best_and_median(fn: Callable[[], object], runs: int) -> tuple[float, float]:
    """(best, median) wall time of ``fn`` in seconds."""
    times = []
    for _ in range(runs):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times), statistics.median(times)


def library_gestures(profiles=("rhand", "inmoov")):
    """(name, program, profile) of every library gesture, each on the first of
    ``profiles`` that has its servos (hand gestures on the hand, the rest on the robot)."""
    from inmoov_dsl import GestError, load_library, load_profile
    from inmoov_dsl.compiling.resolve import Resolver
    from inmoov_dsl.language.load import load

    loaded = [load_profile(p) for p in profiles]
    out = []
    for name, path in sorted(load_library().items()):
        program = load(str(path))
        for profile in loaded:
            try:
                Resolver(program, profile).gesture(name)
            except GestError:
                continue
            out.append((name, program, profile))
            break
    return out


def random_gesture(names: list[str], steps: int, seed: int = 1) -> str:
    """A gesture of ``steps`` lines like a person writes them: moves of 1..8 servos by
    up to 60 degrees (some timed), and short waits."""
    rng = random.Random(seed)
    pose = dict.fromkeys(names, 90)
    lines = ["big:"]
    for _ in range(steps):
        if rng.random() < 0.1:
            lines.append(f"    wait {rng.randint(20, 300)}ms")
            continue
        targets = []
        for name in rng.sample(names, rng.randint(1, 8)):
            pose[name] = min(180, max(0, pose[name] + rng.randint(-60, 60)))
            targets.append(f"{name} {pose[name]}")
        move = ", ".join(targets)
        if rng.random() < 0.3:
            move += f" over {rng.randint(200, 600)}ms"
        lines.append(f"    {move}")
    return "\n".join(lines) + "\n"
