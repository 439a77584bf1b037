"""Plan every step with ruckig (stage 3): jerk-limited, time-optimal or timed moves.

Each step is one ruckig trajectory for all the servos it moves, starting at rest
from the pose the previous step left and ending at rest on its keyframe (the
community ruckig computes no intermediate waypoints offline), except a run of steps
that flow ``through`` their keyframes (flow.py: each segment ends at the crossing
velocities chosen for it) and ``a & b`` (each branch planned on its own from the
step's start). The result is, per servo, a piecewise cubic over the whole gesture
(tracks.py), built from ruckig's own phase data and evaluated with numpy.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from dataclasses import dataclass

from ruckig import InputParameter, Result, Ruckig, Synchronization, Trajectory

from ..errors import Diagnostic, GestError, Pos, SourceMap
from ..hardware import Profile
from . import flow, speech
from .actions import Action
from .speech import Speech
from .stretch import STRETCH_HINT, TIMES, stretch_message
from .tracks import MotionState, Track, TrackBuilder

MAX_GESTURE_DURATION = 3600.0  #: s; a compile's work is bounded by this
_EPS = 1e-6  #: s; durations closer than this are equal


@dataclass(frozen=True)
class PlannedStep:
    """What the planner made of one step, for reports."""

    where: str
    pos: Pos | None
    kind: str  #: "move" or "hold"
    start: float
    end: float
    asked: float | None  #: the step's ``over`` (or hold) duration
    stretched: bool
    servos: tuple[int, ...]  #: indices of the servos that move
    call: Pos | None = None  #: ``Action.call``: the call it plays in, where it is written
    opens: bool = False  #: the first step of one play of that call
    solved: tuple = ()  #: ``Action.solved``: its places and the values they solved to


@dataclass(frozen=True)
class Plan:
    """A planned gesture: every servo's track, what became of each step, its length (s)
    and what the planner warns about."""

    profile: Profile
    tracks: tuple[Track, ...]  #: one per profile servo
    steps: tuple[PlannedStep, ...]
    start: tuple[int, ...]
    final: tuple[int, ...]
    duration: float
    warnings: tuple[Diagnostic, ...]
    sounds: tuple[tuple[float, Speech], ...] = ()  #: (start, s) of each ``say``'s sound
    #: indices of the servos its steps name, moving or not: each is held at its final
    #: value when the gesture ends, written once if it never moves (``boards/frames.py``)
    named: frozenset[int] = frozenset()


#: what a step tells its gesture besides its report: warnings, and (start, sound) pairs
Told = tuple[list[Diagnostic], list[tuple[float, Speech]]]


class Planner:
    """Plans Actions for one profile; keeps one ruckig instance per number of servos."""

    def __init__(self, profile: Profile, sources: SourceMap | None = None):
        self.profile = profile
        self.sources = sources or SourceMap()
        self._ruckig: dict[int, tuple[Ruckig, InputParameter, Trajectory]] = {}

    def _solver(self, dofs: int) -> tuple[Ruckig, InputParameter, Trajectory]:
        if dofs not in self._ruckig:
            self._ruckig[dofs] = (Ruckig(dofs), InputParameter(dofs), Trajectory(dofs))
        return self._ruckig[dofs]

    def plan(self, steps: Sequence[Action], start: Sequence[int], strict: bool = False) -> Plan:
        """Plan ``steps`` from the pose ``start``; a stretched move warns (or, with
        ``strict``, is an error)."""
        pose = list(start)
        builders = [TrackBuilder(v) for v in pose]
        reports: list[PlannedStep] = []
        branched: list[Diagnostic] = []  # the warnings of 'a & b' steps' branches
        sounds: list[tuple[float, Speech]] = []
        # a stretch is told once per place and message, however often the step is
        # played (a call in a repeat): (pos, message) -> how many times
        stretched: dict[tuple[Pos | None, str], int] = {}
        now, k = 0.0, 0
        while k < len(steps):
            run = flow.run_at(steps, k)
            planned = self._run(run, now, pose, builders) if len(run) > 1 else \
                [self._step(steps[k], now, pose, builders, strict, (branched, sounds))]
            for step, (report, needed) in zip(run, planned, strict=True):
                if report.stretched:
                    key = (step.over_pos or step.pos, stretch_message(needed, step.over))
                    stretched[key] = stretched.get(key, 0) + 1
                reports.append(report if step.call is None and not step.solved else
                               dataclasses.replace(report, call=step.call, opens=step.opens,
                                                   solved=step.solved))
                now = report.end
            k += len(run)
            if now > MAX_GESTURE_DURATION:
                raise GestError(self.sources.error(
                    f"the gesture lasts more than {MAX_GESTURE_DURATION:g} s", run[-1].pos,
                    "split it into shorter gestures"))
        make = self.sources.error if strict else self.sources.warning
        told = tuple(make(message + (TIMES.format(count) if count > 1 else ""), pos,
                          STRETCH_HINT)
                     for (pos, message), count in stretched.items()) + \
            tuple(dict.fromkeys(branched))  # a branch played again warns once
        if strict and told:
            raise GestError(told)
        return Plan(self.profile, tuple(b.build() for b in builders), tuple(reports),
                    tuple(start), tuple(pose), now, () if strict else told, tuple(sounds),
                    frozenset().union(*(step.servos() for step in steps)))

    def _trajectory(self, servos: list[int], start: MotionState, target: Sequence[float],
                    over: float | None, step: Action | None,
                    velocity: Sequence[float] | None = None) -> Trajectory:
        """One ruckig trajectory for ``servos`` (indices), from their state in ``start``
        to ``target`` (one value each), at rest or crossing it at ``velocity`` (one
        each), all arriving together no sooner than ``over``, within each servo's
        limits."""
        ruckig, inp, traj = self._solver(len(servos))
        limits = [self.profile.servos[i] for i in servos]
        inp.current_position = [float(start.position[i]) for i in servos]
        inp.current_velocity = [float(start.velocity[i]) for i in servos]
        inp.current_acceleration = [float(start.acceleration[i]) for i in servos]
        inp.target_position = [float(v) for v in target]
        inp.target_velocity = [float(v) for v in velocity or [0.0] * len(servos)]
        inp.target_acceleration = [0.0] * len(servos)
        inp.max_velocity = [s.max_velocity for s in limits]
        inp.max_acceleration = [s.max_acceleration for s in limits]
        inp.max_jerk = [s.max_jerk for s in limits]
        inp.synchronization = Synchronization.Time
        inp.minimum_duration = over
        _calculate(ruckig, inp, traj, step, self.sources)
        return traj

    def _step(self, step: Action, now: float, pose: list[int], builders: list[TrackBuilder],
              strict: bool, told: Told) -> tuple[PlannedStep, float]:
        """A hold, ``a & b`` (``_together``: its branches' warnings and sounds go to
        ``told``), a ``say`` (the mouth follows its sound) or a move from rest to rest
        (``_move``)."""
        if step.hold > 0:
            return PlannedStep(step.where, step.pos, "hold", now, now + step.hold, step.hold,
                               False, ()), step.hold
        if step.branches:
            return self._together(step, now, pose, builders, strict, told)
        if step.speech is not None:
            length, wait = speech.follow(step.speech, self.profile, now, pose, builders)
            told[1].append((now + wait, step.speech))
            return PlannedStep(step.where, step.pos, "say", now, now + length, None, False,
                               (step.speech.servo,)), length
        return self._move(step, now, pose, builders)

    def _together(self, step: Action, now: float, pose: list[int],
                  builders: list[TrackBuilder], strict: bool, told: Told
                  ) -> tuple[PlannedStep, float]:
        """``a & b``: each branch planned on its own from the step's start, its servos'
        tracks joined to the gesture's; the step lasts as long as its longest branch."""
        plans = [(self.plan(branch, pose, strict), branch) for branch in step.branches]
        for plan, branch in plans:
            for i in set().union(*(a.servos() for a in branch)):
                builders[i].extend(plan.tracks[i], now)
                pose[i] = plan.final[i]
            told[0].extend(plan.warnings)
            told[1].extend((now + t, s) for t, s in plan.sounds)
        duration = max(plan.duration for plan, _ in plans)
        return PlannedStep(step.where, step.pos, "move", now, now + duration, None, False,
                           tuple(sorted(step.servos()))), duration

    def _move(self, step: Action, now: float, pose: list[int], builders: list[TrackBuilder]
              ) -> tuple[PlannedStep, float]:
        """One ruckig trajectory for every servo the step moves, from rest to rest;
        appends it to the servos' tracks and updates ``pose``. Also returns how long
        each servo's move takes (the step is longer by its stagger)."""
        moving = [(k, i, v) for k, (i, v) in enumerate(step.targets) if v != pose[i]]
        if not moving:
            hold = step.over or 0.0
            return PlannedStep(step.where, step.pos, "move", now, now + hold, step.over,
                               False, ()), hold
        idx = [i for _, i, _ in moving]
        traj = self._trajectory(idx, MotionState.resting(pose), [v for _, _, v in moving],
                                step.over, step)
        move_time = traj.duration
        duration = max(k for k, _, _ in moving) * step.stagger + move_time
        for dof, (k, i, v) in enumerate(moving):
            offset = k * step.stagger
            builders[i].phases(now + offset, traj.profiles[0][dof])
            # the exact keyframe from the step's end on (never later than it)
            builders[i].hold(min(now + offset + move_time, now + duration), float(v))
            pose[i] = v
        stretched = step.over is not None and move_time > step.over + _EPS
        return PlannedStep(step.where, step.pos, "move", now, now + duration, step.over,
                           stretched, tuple(idx)), move_time

    def _run(self, run: Sequence[Action], now: float, pose: list[int],
             builders: list[TrackBuilder]) -> list[tuple[PlannedStep, float]]:
        """Moves that flow through their keyframes (flow.py): one segment per step, each
        from the state the last one left, crossing its keyframe as ``flow.crossings``
        chose, or slower where that would overshoot or last longer than a stop."""
        poses = flow.keyframes(pose, run)
        alone = [flow.alone(self._trajectory, step, poses[j], poses[j + 1])
                 for j, step in enumerate(run)]
        cross = [*flow.crossings(self.profile, poses, alone), {}]
        state, out = MotionState.resting(pose), []
        for j, step in enumerate(run):
            target = poses[j + 1]
            found = flow.segment(self._trajectory, step, state, target, cross[j], alone[j])
            if found is None:  # nothing moves: a pause as long as its 'over'
                hold = step.over or 0.0
                out.append((PlannedStep(step.where, step.pos, "move", now, now + hold,
                                        step.over, False, ()), hold))
                now += hold
                continue
            traj, moving, velocity = found
            for dof, i in enumerate(moving):
                builders[i].phases(now, traj.profiles[0][dof])
                if not velocity[i]:
                    builders[i].hold(now + traj.duration, float(target[i]))
            stretched = step.over is not None and traj.duration > step.over + _EPS
            out.append((PlannedStep(step.where, step.pos, "move", now, now + traj.duration,
                                    step.over, stretched, tuple(moving)), traj.duration))
            state = MotionState(tuple(map(float, target)), tuple(velocity),
                                (0.0,) * len(target))
            now += traj.duration
        pose[:] = poses[-1]
        return out

    def take_over(self, state: MotionState, targets: Sequence[int], over: float | None = None,
                  step: Action | None = None) -> Plan:
        """Plan from a moving state to ``targets`` (one per servo), all arriving together,
        at rest, no sooner than ``over``: a new step takes over a running move with the
        hand's current position, velocity and acceleration (no jump, no stop first)."""
        moving = [i for i, x in enumerate(state.position)
                  if abs(x - targets[i]) > _EPS or abs(state.velocity[i]) > _EPS
                  or abs(state.acceleration[i]) > _EPS]
        builders = [TrackBuilder(float(x)) for x in state.position]
        duration = over or 0.0
        move_time = 0.0
        if moving:
            traj = self._trajectory(moving, state, [targets[i] for i in moving], over, step)
            move_time = traj.duration
            duration = max(duration, move_time)
            for dof, i in enumerate(moving):
                builders[i].phases(0.0, traj.profiles[0][dof])
        for i, b in enumerate(builders):
            b.hold(move_time, float(targets[i]))
        stretched = over is not None and move_time > over + _EPS
        warnings = ()
        if stretched:
            warnings = (self.sources.warning(stretch_message(move_time, over),
                                             step and (step.over_pos or step.pos)),)
        report = PlannedStep(step.where if step else "", step and step.pos, "move", 0.0,
                             duration, over, stretched, tuple(moving))
        start = tuple(int(math.floor(x + 0.5)) for x in state.position)
        return Plan(self.profile, tuple(b.build() for b in builders), (report,), start,
                    tuple(int(v) for v in targets), duration, warnings,
                    named=frozenset(step.servos()) if step else frozenset())


def _calculate(ruckig: Ruckig, inp: InputParameter, traj: Trajectory, step: Action | None,
               sources: SourceMap) -> None:
    """ruckig's trajectory for ``inp``; any failure of ruckig (a result that is not
    a success, an exception, a duration that is not finite) is a GestError at the
    step."""
    try:
        result = ruckig.calculate(inp, traj)
        ok = result in (Result.Working, Result.Finished)
        why = "" if ok else result.name
    except Exception as exc:  # noqa: BLE001 - a foreign library: whatever it raises
        first = (str(exc).strip().splitlines() or [type(exc).__name__])[0]
        ok, why = False, first.removeprefix("[ruckig] ").removesuffix(" input:")
    if ok and not (math.isfinite(traj.duration) and traj.duration >= 0):
        ok, why = False, f"a duration of {traj.duration}"
    if not ok:
        where = f" of '{step.where}'" if step is not None and step.where else ""
        raise GestError(sources.error(
            f"cannot plan this step{where}: ruckig failed ({why})",
            step.pos if step is not None else None,
            "the servos it moves may have limits too far apart for this duration: "
            "try another 'over', or check the profile's limits"))
