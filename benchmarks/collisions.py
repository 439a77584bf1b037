"""What the self-collision check costs, and how often the robot would meet itself
(docs/collisions.md): one pose (every checked pair), each of the library's whole-robot
gestures (its plan checked every 20 ms), the whole library, the check a live request
pays before its first byte, and the share of random arm poses that put two parts within
the clearance or into each other, as this project's check and as trimesh's collision
manager on the URDF's meshed collision geometry (yourdfpy) each count them.

Times are the wall clock (``time.perf_counter``) around the calls a command makes; the
share of poses is counted twice, by the check and by a library that shares none of its
code but FCL's core (trimesh meshes the URDF's shapes and keeps its own scene).

    python benchmarks/collisions.py [--poses 2000] [--repeat 20]

Needs the collide extra (python-fcl), and the web extra for the trimesh count; ~1 min.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))  # trimesh_reference: the tests' other library

from inmoov_dsl.compiling.compiler import compile_program  # noqa: E402
from inmoov_dsl.compiling.plan import Planner  # noqa: E402
from inmoov_dsl.language.load import load  # noqa: E402
from inmoov_dsl.live.session import line_steps  # noqa: E402
from inmoov_dsl.model.collide import Checker, checker_for, first_contacts  # noqa: E402
from inmoov_dsl.model.guard import Guard  # noqa: E402
from inmoov_dsl.profiles.profile import load_profile  # noqa: E402

ARM = ("r_bicep", "r_rotate", "r_shoulder", "r_omoplate")
REQUESTS = ("r_bicep 60 over 1s", "r_shoulder 90, r_omoplate 30 over 2s", "wave_hello")


def timed(call, repeat: int) -> float:
    """The median wall time of ``call()`` (s)."""
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        call()
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def poses(checker: Checker, count: int, seed: int, servos=None) -> np.ndarray:
    """``count`` random poses, the named servos (all by default) uniform in range."""
    rng = np.random.default_rng(seed)
    out = np.tile(checker.chain.values({}), (count, 1))
    for i, s in enumerate(checker.profile.servos):
        if servos is None or s.name in servos:
            out[:, i] = rng.uniform(s.lo, s.hi, count)
    return out


def one_pose(checker: Checker, repeat: int) -> None:
    """One pose, every checked pair."""
    rest = checker.chain.values({})
    arm, whole = poses(checker, 200, 1, ARM), poses(checker, 200, 2)
    print(f"one pose, all {len(checker.pairs)} checked pairs: rest "
          f"{timed(lambda: checker.contacts_of(rest), repeat * 20) * 1e6:.0f} us, random "
          f"right arm {timed(lambda: [checker.contacts_of(v) for v in arm], 3) / 200 * 1e6:.0f}"
          f" us, random whole robot "
          f"{timed(lambda: [checker.contacts_of(v) for v in whole], 3) / 200 * 1e6:.0f} us")


def gestures(repeat: int) -> None:
    """Each whole-robot gesture of the library, then the whole library."""
    total = count = 0.0
    for path in sorted((ROOT / "gestures").glob("*.gest")):
        program = load(str(path))
        for name in program.own:
            _, plan = compile_program(program, name)
            checker = checker_for(plan.profile)
            if checker is None:
                continue
            took = timed(lambda c=checker, p=plan: first_contacts(c, p), repeat)
            total, count = total + took, count + 1
            print(f"  {path.name} {name}: {plan.duration:.1f} s of motion, checked in "
                  f"{took * 1000:.1f} ms")
    print(f"the library: {int(count)} whole-robot gestures checked in {total:.3f} s")


def requests(repeat: int) -> None:
    """What the drive loop's guard pays for a request from rest: planning its steps
    and checking them (the service does it before its 202, off the drive loop)."""
    profile = load_profile("inmoov")
    guard = Guard(profile)
    program = load("<bench>", "robot inmoov\nwave_hello:\n    r_shoulder 100 over 1.5s\n"
                   "    r_bicep 80 over 1s\n    r_rotate 60 over 0.5s\n"
                   "    r_rotate 120 over 0.5s\n")
    rest = [s.rest for s in profile.servos]
    for text in REQUESTS:
        steps, sources = line_steps(text, program, profile)
        plan = timed(lambda s=steps, m=sources: Planner(profile, m).plan(s, rest), repeat)
        both = timed(lambda s=steps, m=sources: guard.steps(s, rest, m), repeat)
        print(f"  request '{text}': planned in {plan * 1000:.2f} ms, planned and checked "
              f"in {both * 1000:.2f} ms")


def shares(checker: Checker, count: int) -> None:
    """The share of random right-arm poses with a contact, ours and trimesh's."""
    values = poses(checker, count, 3, ARM)
    ours = [checker.contacts_of(v) for v in values]
    near = sum(bool(c) for c in ours) / count
    into = sum(any(x.distance_mm < 0 for x in c) for c in ours) / count
    print(f"random right-arm poses ({count:,}): {near:.1%} within the clearance, "
          f"{into:.1%} with parts inside each other (this check)")
    try:
        from trimesh_reference import Reference

        reference = Reference(checker.profile)
    except ImportError:
        print("  (trimesh's count needs the web extra: yourdfpy, trimesh)")
        return
    hits = sum(bool(reference.overlapping(v, checker.pairs)) for v in values)
    print(f"  trimesh on the URDF's meshed collision shapes: {hits / count:.1%} with parts "
          "inside each other")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--poses", type=int, default=2000)
    ap.add_argument("--repeat", type=int, default=20)
    args = ap.parse_args()
    t = time.perf_counter()
    checker = Checker(load_profile("inmoov"))
    print(f"building the InMoov's check (its pairs' file kept): "
          f"{(time.perf_counter() - t) * 1000:.0f} ms")
    one_pose(checker, args.repeat)
    gestures(args.repeat)
    requests(args.repeat)
    shares(checker, args.poses)


if __name__ == "__main__":
    main()
