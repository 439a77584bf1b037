"""Places solved: ``right hand to (x, y, z) mm`` on the ``inmoov`` profile.

Targets: 1,000 seeded random poses of the right arm, each within its servos' ranges and
clear of the body (the collision check), the hand's point there found by yourdfpy on
``gestc urdf``'s model (not by our kinematics). Each target is solved from the rest pose:

- the Robotics Toolbox's ``ik_LM`` alone (one call from the rest pose's angles): its time
  per solve, p50 and p99, and how often that one call succeeds;
- the whole solve of a place (``model.reach.solve``: the toolbox from the pose before,
  then fixed seeds, whole values, the collision check): its time, its success (the hand's
  point, posed by yourdfpy from the values, within 5 mm), the rounding's cost (how much
  further the whole values put the hand than the toolbox's angles);
- MyRobotLab's InMoov loop, written here from its description (``DHRobotArm.moveToGoal``:
  a finite-difference Jacobian (1e-4 rad), its pseudo-inverse, each step 5 % of the
  error, done under 20 mm or after 1,000 steps, limits not kept inside a step), for
  comparison: its success within 20 mm and within 5 mm, and its time.

Then a file of 60 such targets checked: in the process (the library imported) and by
``gestc check`` (a fresh process: the toolbox's import included).

    python benchmarks/reach.py [COUNT]
"""

from __future__ import annotations

import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import yourdfpy
from common import ROOT

sys.path.insert(0, str(ROOT))
from inmoov_dsl.compiling.reaching import Aim, servos_for  # noqa: E402
from inmoov_dsl.errors import GestError, SourceMap  # noqa: E402
from inmoov_dsl.model import ik, joints, reach  # noqa: E402
from inmoov_dsl.model.collide import checker_for  # noqa: E402
from inmoov_dsl.model.urdf import model  # noqa: E402
from inmoov_dsl.profiles.profile import load_profile  # noqa: E402

ARM = ("r_omoplate", "r_shoulder", "r_rotate", "r_bicep")


def hand_point(robot, profile, values) -> np.ndarray:
    robot.update_cfg(dict(zip(joints.names(profile), joints.positions(profile, values),
                              strict=True)))
    return robot.get_transform("right_hand_point")[:3, 3]


def targets(robot, profile, count: int) -> list[np.ndarray]:
    checker, rng = checker_for(profile), np.random.default_rng(2026)
    servos = [profile.servos[profile.index(n)] for n in ARM]
    found = []
    while len(found) < count:
        pose = {s.name: int(rng.integers(s.lo, s.hi + 1)) for s in servos}
        if not checker.contacts(pose):
            found.append(hand_point(robot, profile, [pose.get(s.name, s.rest)
                                                     for s in profile.servos]))
    return found


def mrl_loop(arm, values, goal) -> tuple[np.ndarray, int]:
    """MyRobotLab's loop from its description: angles, and the steps it took."""
    q = arm.q(values)
    row = values.copy()

    def tip(angles):
        row[list(arm.slots)] = arm.values(angles)
        return arm.chain.transforms(row)[arm.tip, :3, 3]

    for step in range(1000):
        here = tip(q)
        error = goal - here
        if np.linalg.norm(error) < 0.020:
            return q, step
        jac = np.stack([(tip(q + np.eye(len(q))[k] * 1e-4) - here) / 1e-4
                        for k in range(len(q))], axis=1)
        q = q + np.linalg.pinv(jac) @ (error * 0.05)
    return np.clip(q, arm.qlim[0], arm.qlim[1]), 1000


def percentile(values, p) -> float:
    return float(np.percentile(values, p))


def main() -> None:
    count = int(sys.argv[1]) if len(sys.argv) > 1 else 1000
    profile = load_profile("inmoov")
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "inmoov.urdf"
        path.write_text(model(profile))
        robot = yourdfpy.URDF.load(str(path), load_meshes=False)
    goals = targets(robot, profile, count)
    rest = np.array([s.rest for s in profile.servos], dtype=float)
    servos, _ = servos_for(profile, "right")
    sources = SourceMap()
    lm_times, lm_ok, solve_times, misses, rounding, failed = [], 0, [], [], [], 0
    mrl = {"times": [], "within20": 0, "within5": 0}
    for goal in goals:
        aim = Aim("right", tuple(goal), servos)
        chain, arm, _seeds = reach.arm_for(profile, aim)
        before, ets = arm.at(rest)
        local = np.linalg.inv(before) @ np.append(goal, 1.0)
        wanted = np.eye(4)
        wanted[:3, 3] = local[:3]
        start = time.perf_counter()
        found = ets.ik_LM(wanted, q0=arm.q(rest), ilimit=60, slimit=1, tol=ik.TOLERANCE_M,
                          mask=np.array([1, 1, 1, 0, 0, 0.0]), joint_limits=True)
        lm_times.append(time.perf_counter() - start)
        lm_ok += bool(found.success)
        start = time.perf_counter()
        try:
            values = reach.solve(profile, aim, rest, sources)
        except GestError:
            failed += 1
            continue
        solve_times.append(time.perf_counter() - start)
        whole = rest.copy()
        for i, v in values.items():
            whole[i] = v
        miss = np.linalg.norm(hand_point(robot, profile, whole) - goal) * 1000
        misses.append(miss)
        exact = rest.copy()
        q, _used = ik.solve(arm, rest, goal, arm.q(whole)[None])
        exact[list(servos)] = arm.values(q) if q is not None else whole[list(servos)]
        rounding.append(miss - np.linalg.norm(hand_point(robot, profile, exact) - goal) * 1000)
        start = time.perf_counter()
        q, _steps = mrl_loop(arm, rest, goal)
        mrl["times"].append(time.perf_counter() - start)
        mrl_values = rest.copy()
        mrl_values[list(servos)] = arm.values(q)
        off = np.linalg.norm(hand_point(robot, profile, mrl_values) - goal) * 1000
        mrl["within20"] += off <= 20
        mrl["within5"] += off <= 5
    solved = sum(m <= 5 for m in misses)
    ms = 1000
    print(f"targets: {count} reachable (seeded poses clear of the body, points by yourdfpy)")
    print(f"toolbox ik_LM, one call from rest: p50 {percentile(lm_times, 50) * ms:.3f} ms, "
          f"p99 {percentile(lm_times, 99) * ms:.3f} ms, succeeded {lm_ok}/{count}")
    print(f"whole solve of a place: p50 {percentile(solve_times, 50) * ms:.2f} ms, "
          f"p99 {percentile(solve_times, 99) * ms:.2f} ms; within 5 mm (yourdfpy): "
          f"{solved}/{count} ({100 * solved / count:.1f} %), refused {failed}")
    print(f"rounding to whole values: median {statistics.median(rounding):+.2f} mm, "
          f"worst {max(rounding):+.2f} mm; miss median {statistics.median(misses):.2f} mm, "
          f"worst {max(misses):.2f} mm")
    print(f"MyRobotLab's loop: within 20 mm {mrl['within20']}/{len(mrl['times'])}, within "
          f"5 mm {mrl['within5']}/{len(mrl['times'])}, p50 "
          f"{percentile(mrl['times'], 50) * ms:.1f} ms, p99 "
          f"{percentile(mrl['times'], 99) * ms:.1f} ms")
    check_file(goals[:60])


def check_file(goals: list[np.ndarray]) -> None:
    """A file of len(goals) places, checked in the process and by ``gestc check``."""
    from inmoov_dsl.cli import gestc

    text = "robot inmoov\n" + "".join(
        f"g{k}: right hand to ({x * 1000:.0f}, {y * 1000:.0f}, {z * 1000:.0f}) mm over 4s\n"
        for k, (x, y, z) in enumerate(goals))
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "places.gest"
        path.write_text(text)
        start = time.perf_counter()
        gestc.main(["check", str(path)])
        inside = time.perf_counter() - start
        start = time.perf_counter()
        subprocess.run([sys.executable, "-m", "inmoov_dsl.cli.gestc", "check", str(path)],
                       capture_output=True, check=False)
        fresh = time.perf_counter() - start
        start = time.perf_counter()
        subprocess.run([sys.executable, "-c", "import roboticstoolbox"], check=True)
        toolbox = time.perf_counter() - start
    print(f"a file of {len(goals)} places checked: {inside:.2f} s in the process, "
          f"{fresh:.2f} s by gestc check in a fresh process (python -c 'import "
          f"roboticstoolbox' alone: {toolbox:.2f} s)")


if __name__ == "__main__":
    main()
