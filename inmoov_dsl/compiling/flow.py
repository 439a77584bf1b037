"""Steps that flow ``through`` their keyframes (pure): which steps make a run, and the
velocity each servo crosses each keyframe with.

The community ruckig plans no intermediate waypoints offline, but it plans a move to
a target that is crossed at a given velocity (with zero acceleration such a target is
always reachable: |a| <= sqrt(2 jerk (vmax - |v|)) holds for any |v| <= vmax). A run is
then one segment per step, each from the state the last one left. A servo crosses a
keyframe moving only when the next step keeps it going the same way; it crosses at
no more than the slower of the two segments' mean speeds (taken from their
stop-and-go plans) times ``LIVELINESS``, within its velocity limit, and slowly enough
to speed up or brake to its neighbours' crossings over the segments between
(``settle``). The planner checks each segment and halves a crossing that would make
it overshoot its keyframes or last longer than stop-and-go (``Planner._run``).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

from ruckig import Trajectory

from ..hardware import Profile
from .actions import Action
from .tracks import MotionState

LIVELINESS = 1.5  #: a crossing's speed over the slower neighbouring mean speed, at most
#: the planner's ruckig call: (servos, start state, targets, over, step[, velocities])
Plans = Callable[..., Trajectory]
OVERSHOOT = 0.25  #: degrees a servo may pass a keyframe by (half the encoder's step)


def run_at(steps: Sequence[Action], k: int) -> Sequence[Action]:
    """The steps from ``k`` that make one motion: a move that flows ``through`` its
    keyframe, the moves after it that do too, and the move that ends the run (the step
    alone when it does not flow into a move that starts all its servos at once)."""
    end = k
    while end + 1 < len(steps) and steps[end].through and steps[end].hold == 0 \
            and steps[end + 1].hold == 0 and steps[end + 1].stagger == 0 \
            and not steps[end + 1].branches:
        end += 1
    return steps[k:end + 1]


def keyframes(start: Sequence[int], run: Sequence[Action]) -> list[list[int]]:
    """The pose before the run and after each of its steps."""
    poses = [list(start)]
    for step in run:
        pose = list(poses[-1])
        for i, v in step.targets:
            pose[i] = v
        poses.append(pose)
    return poses


def crossings(profile: Profile, poses: Sequence[Sequence[int]], times: Sequence[float]
              ) -> list[dict[int, float]]:
    """The velocity (degrees/s) each servo crosses each inner keyframe with (servo index
    -> velocity, servos crossing at rest left out). ``poses``: the keyframes (``keyframes``);
    ``times``: each step's stop-and-go duration."""
    count = len(poses) - 2
    found: list[dict[int, float]] = [{} for _ in range(count)]
    for i, servo in enumerate(profile.servos):
        moves = [poses[j + 1][i] - poses[j][i] for j in range(len(poses) - 1)]
        speeds = []
        for j in range(count):
            d_in, d_out = moves[j], moves[j + 1]
            if d_in * d_out <= 0:  # still before or after, or turning back: at rest
                speeds.append(0.0)
                continue
            mean = min(abs(d_in) / max(times[j], 1e-9), abs(d_out) / max(times[j + 1], 1e-9))
            speeds.append(min(LIVELINESS * mean, servo.max_velocity))
        for j, speed in enumerate(settle(speeds, [abs(d) for d in moves],
                                         servo.max_acceleration)):
            if speed > 0:
                found[j][i] = math.copysign(speed, moves[j + 1])
    return found


def settle(speeds: list[float], distances: Sequence[float], acceleration: float
           ) -> list[float]:
    """``speeds`` at the inner keyframes, lowered so that each can be reached from the
    one before and braked to the one after over the distance between, at half the
    acceleration limit (the jerk limit takes the rest); at rest before and after."""
    reach = acceleration  # v^2 = u^2 + 2 (a / 2) d
    out = list(speeds)
    for j in range(len(out)):  # speeding up from the start
        before = out[j - 1] if j else 0.0
        out[j] = min(out[j], math.sqrt(before ** 2 + reach * distances[j]))
    for j in reversed(range(len(out))):  # braking to the end
        after = out[j + 1] if j + 1 < len(out) else 0.0
        out[j] = min(out[j], math.sqrt(after ** 2 + reach * distances[j + 1]))
    return out


def smooth(traj: Trajectory, state: MotionState, target: Sequence[int], moving: list[int],
           alone: float) -> bool:
    """Whether a segment of a run is as good as stopping at its keyframe: no servo
    passes its keyframe or turns back behind where it started (by more than
    ``OVERSHOOT``), and it takes no longer than the stop-and-go move (``alone``)."""
    if traj.duration > alone + 1e-6:
        return False
    for dof, i in enumerate(moving):
        low, high = sorted((state.position[i], target[i]))
        extrema = traj.position_extrema[dof]
        if extrema.min < low - OVERSHOOT or extrema.max > high + OVERSHOOT:
            return False
    return True


def alone(trajectory: Plans, step: Action, before: Sequence[int], after: Sequence[int]
          ) -> float:
    """How long ``step`` takes from rest to rest (its stop-and-go duration)."""
    moving = [i for i, _ in step.targets if after[i] != before[i]]
    if not moving:
        return step.over or 0.0
    return trajectory(moving, MotionState.resting(before), [after[i] for i in moving],
                      step.over, step).duration

def segment(trajectory: Plans, step: Action, state: MotionState, target: Sequence[int],
            cross: dict[int, float], alone: float
            ) -> tuple[Trajectory, list[int], list[float]] | None:
    """The segment of a run from ``state`` to ``target``, crossing it at ``cross``
    (servo -> velocity), at half that, or at rest, whichever is the first that
    neither overshoots nor takes longer than ``alone``; None when nothing moves."""
    while True:
        velocity = [cross.get(i, 0.0) for i in range(len(target))]
        moving = [i for i, x in enumerate(state.position) if x != target[i]
                  or state.velocity[i] or velocity[i]]
        if not moving:
            return None
        traj = trajectory(moving, state, [target[i] for i in moving], step.over, step,
                          [velocity[i] for i in moving])
        if not cross or smooth(traj, state, target, moving, alone):
            return traj, moving, velocity
        slower = {i: v / 2 for i, v in cross.items() if abs(v) > 1.0}
        cross = slower if len(slower) == len(cross) else {}
