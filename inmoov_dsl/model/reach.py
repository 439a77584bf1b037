"""Places as servo values (``right hand to cup``, ``look at cup``): the solver the
compiler asks (``compiling.reaching``), given to it when this module is imported.

A hand's place is solved for its arm's four servos (``ik``), searched from the pose
before the step, then from fixed seeds spread over the joints' ranges (the same file
gives the same values): the first solution whose whole values put the hand's point
within ``REACHED_MM`` of the place and the robot's parts no closer than their
clearance (``collide``) is the answer; a place inside a part the arm does not carry
is refused first. None: the place is out of reach (the best pose's miss
and where it puts the hand are told), or every pose that reaches it is a contact
(the parts are named). The gaze is ``gaze.py``'s.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence

import numpy as np

from ..compiling.reaching import FRAMES, Aim
from ..errors import Diagnostic, GestError, SourceMap
from ..hardware import Profile
from . import gaze, ik, solved
from .collide import Checker, Contact, checker_for
from .kinematics import Chain

REACHED_MM = 5.0  #: the hand's point is at the place when this close (values are whole)
SEEDS = 24  #: fixed starting poses tried after the pose before the step
NEAREST = 6  #: of them, where a place is out of reach, the ones the nearest is sought from
_ARMS: dict[tuple[str, str, str], tuple[Chain, ik.ArmChain, np.ndarray]] = {}


def arm_for(profile: Profile, aim: Aim) -> tuple[Chain, ik.ArmChain, np.ndarray]:
    """The profile's model, the arm of ``aim`` in it and its fixed seeds, made once."""
    key = (profile.name, profile.sha256, aim.what)
    if key not in _ARMS:
        chain = Chain(profile)
        arm = ik.ArmChain(chain, profile, aim.servos, FRAMES[aim.what])
        rng = np.random.default_rng(20261129)
        seeds = rng.uniform(arm.qlim[0], arm.qlim[1], (SEEDS, len(aim.servos)))
        _ARMS[key] = (chain, arm, seeds)
    return _ARMS[key]


def solve(profile: Profile, aim: Aim, pose: Sequence[int], sources: SourceMap
          ) -> dict[int, int]:
    """The values of ``aim``'s servos that put its hand's point (or its gaze) at its
    place from ``pose`` (kept between programs: ``solved``); a GestError at the aim
    when none does."""
    if (kept := solved.found(profile, aim, pose)) is not None:
        return kept
    if aim.what == "look":
        values = gaze.solve(profile, aim, pose, sources, checker_for(profile))
    else:
        values = _arm(profile, aim, pose, sources)
    solved.keep(profile, aim, pose, values)
    return values


def _arm(profile: Profile, aim: Aim, pose: Sequence[int], sources: SourceMap
         ) -> dict[int, int]:
    """A hand's place solved (see the module's docstring)."""
    chain, arm, seeds = arm_for(profile, aim)
    values = np.asarray(pose, dtype=float)
    goal = np.asarray(aim.xyz)
    checker = checker_for(profile)
    if checker is not None:
        _outside(checker, chain, values, goal, aim, sources)
    seeds = starts = np.vstack([np.clip(arm.q(values), arm.qlim[0], arm.qlim[1]), seeds])
    blocked = None  # the first contact of a pose that reaches the place
    best: tuple[float, np.ndarray] | None = None  # the closest miss, its values
    while len(seeds):
        q, used = ik.solve(arm, values, goal, seeds)
        seeds = seeds[used:]
        if q is None:
            break
        found = _rounded(chain, arm, values, goal, arm.values(q), aim)
        best = min(best or found, found, key=lambda f: f[0])
        if found[0] > REACHED_MM:
            continue
        contacts = checker.contacts_of(found[1]) if checker is not None else []
        if not contacts:
            return {i: int(found[1][i]) for i in aim.servos}
        blocked = blocked or (contacts[0], checker)
    if blocked is None:  # as near as the arm comes within its limits
        near = min((_rounded(chain, arm, values, goal, arm.values(
            ik.nearest(arm, values, goal, seed)), aim) for seed in starts[:NEAREST]),
            key=lambda found: found[0])
        contacts = checker.contacts_of(near[1]) if checker is not None else []
        if near[0] <= REACHED_MM and not contacts:
            return {i: int(near[1][i]) for i in aim.servos}  # at a joint's end
        if near[0] <= REACHED_MM:
            blocked = (contacts[0], checker)
        best = min(best or near, near, key=lambda found: found[0])
    raise GestError(_refusal(sources, aim, chain, arm, best, blocked))


def _outside(checker: Checker, chain: Chain, values: np.ndarray, goal: np.ndarray,
             aim: Aim, sources: SourceMap) -> None:
    """A GestError at the aim if its place is inside a part of the robot that its arm
    does not carry (the chest, the head, the other arm) where it stands now."""
    moving = set(aim.servos)
    bodies = checker.bodies
    for n, depth in bodies.around(chain.transforms(values), goal):
        link = bodies.links[n]
        if not chain.servos_between(link, 0) & moving:
            raise GestError(sources.error(
                f"'{aim.label}' is inside {checker.part(chain.links[link])} (by "
                f"{depth:.0f} mm)", aim.pos, "a place in front of the robot, clear of "
                "its body"))


def _rounded(chain: Chain, arm: ik.ArmChain, values: np.ndarray, goal: np.ndarray,
             solved: np.ndarray, aim: Aim) -> tuple[float, np.ndarray]:
    """The whole values nearest ``solved`` (each rounded down or up, within the servo's
    range) that put the tip closest to ``goal``: its miss in mm, the pose."""
    lo, hi = np.ceil(arm.values(arm.qlim[0])), np.floor(arm.values(arm.qlim[1]))
    low, high = np.minimum(lo, hi), np.maximum(lo, hi)
    options = [np.unique(np.clip([np.floor(v), np.ceil(v)], a, b))
               for v, a, b in zip(solved, low, high, strict=True)]
    rows = np.repeat(values[None], np.prod([len(o) for o in options]), axis=0)
    rows[:, list(aim.servos)] = np.array(list(itertools.product(*options)))
    tips = chain.transforms(rows)[:, arm.tip, :3, 3]
    misses = np.linalg.norm(tips - goal, axis=1) * 1000
    k = int(np.argmin(misses))
    return float(misses[k]), rows[k]


def _refusal(sources: SourceMap, aim: Aim, chain: Chain, arm: ik.ArmChain,
             best: tuple[float, np.ndarray], blocked: tuple[Contact, Checker] | None
             ) -> Diagnostic:
    """The error of a place no pose reaches clear of the body."""
    if blocked is not None:
        contact, checker = blocked
        return sources.error(
            f"'{aim.label}' puts {checker.into(contact, aim.servos)}: every pose that "
            f"reaches the place does", aim.pos, "choose a place further from the body")
    miss, values = best
    near = chain.transforms(values)[arm.tip, :3, 3] * 1000
    side = aim.what
    return sources.error(
        f"'{aim.label}' is out of reach: the {side} hand's point comes no closer than "
        f"{miss:.0f} mm", aim.pos,
        f"the nearest place it reaches is ({', '.join(f'{c:.0f}' for c in near)}) mm")


def note() -> str | None:
    """What a compile that solves a hand's place says once: how to get the toolbox,
    when it is not installed (asked without importing it)."""
    if ik.installed():
        return None
    return ("this hand's place is solved without the Robotics Toolbox, slowly; "
            "to solve it in well under a millisecond: " + ik.INSTALL)

