"""The gaze turned to a place (``look at cup``): the head's turn and nod, and the eyes
when the profile has them, so that the ``gaze`` frame's +x points at the place.

Two angles to meet (the place's bearing and elevation seen from the gaze) with two
servos at a time: Newton's method on the model's kinematics, the Jacobian by finite
differences, within each servo's range. The head takes the larger share: it is solved
alone first, then the eyes take ``EYES_SHARE`` of its turn (within their range) and
the head is solved again for the rest; where the head's range ends, the eyes take what
is left; where the head would meet the body, the eyes take a half, two thirds, then all
they can.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..compiling.reaching import FRAMES, SOLVES, Aim
from ..errors import GestError, SourceMap
from ..hardware import Profile
from . import joints
from .kinematics import Chain

LOOKED_DEG = 2.0  #: the gaze is on the place when this close (values are whole)
EYES_SHARE = 1 / 3  #: of the head's turn, what the eyes take when they can


_CHAINS: dict[tuple[str, str], Chain] = {}


def _chain(profile: Profile) -> Chain:
    key = (profile.name, profile.sha256)
    if key not in _CHAINS:
        _CHAINS[key] = Chain(profile)
    return _CHAINS[key]


def _angles(chain: Chain, rows: np.ndarray, tip: int, goal: np.ndarray) -> np.ndarray:
    """The place's bearing and elevation seen from the gaze (radians), for each pose."""
    world = chain.transforms(rows)[:, tip]
    seen = np.einsum("nji,nj->ni", world[:, :3, :3], goal - world[:, :3, 3])
    return np.stack([np.arctan2(seen[:, 1], seen[:, 0]),
                     np.arctan2(seen[:, 2], np.hypot(seen[:, 0], seen[:, 1]))], axis=1)


def _turn(chain: Chain, values: np.ndarray, slots: list[int], limits: np.ndarray,
          tip: int, goal: np.ndarray, steps: int = 12) -> np.ndarray:
    """``values`` with the two servos of ``slots`` turned (within ``limits``) so that the
    gaze points at ``goal`` as nearly as they can."""
    values, eps = values.copy(), 1e-3
    for _ in range(steps):
        rows = np.repeat(values[None], 3, axis=0)
        rows[1, slots[0]] += eps
        rows[2, slots[1]] += eps
        seen = _angles(chain, rows, tip, goal)
        if np.abs(seen[0]).max() < 1e-7:
            break
        jac = ((seen[1:] - seen[0]) / eps).T
        step = np.linalg.lstsq(jac, -seen[0], rcond=None)[0]
        values[slots] = np.clip(values[slots] + step, limits[:, 0], limits[:, 1])
    return values


def solve(profile: Profile, aim: Aim, pose: Sequence[int], sources: SourceMap,
          checker=None) -> dict[int, int]:
    """The head's (and the eyes') values that turn the gaze to ``aim``'s place from
    ``pose``, the robot's parts clear of each other (``checker``: the profile's
    ``collide.Checker``, None: not checked); a GestError at the aim when none do, within
    ``LOOKED_DEG``. The head takes the larger share; where that puts the head into the
    body (nodding down onto the chest), the eyes take more, up to all they can."""
    chain = _chain(profile)
    tip = chain.links.index(FRAMES["look"])
    goal = np.asarray(aim.xyz)
    by_joint = {profile.servos[i].joint: i for i in aim.servos}
    head = [by_joint[j] for j in SOLVES["look"][0]]
    eyes = [by_joint[j] for j in SOLVES["look"][1] if j in by_joint]
    limits = np.array([[s.lo, s.hi] for s in profile.servos], dtype=float)
    start = np.asarray(pose, dtype=float).copy()
    shares = (EYES_SHARE, 0.5, 2 / 3, 1.0) if len(eyes) == 2 else (0.0,)
    worst, blocked = 180.0, None
    for share in shares:
        values = _share(profile, chain, start, head, eyes, limits, tip, goal, share)
        whole = values.copy()
        whole[list(aim.servos)] = np.clip(np.floor(values[list(aim.servos)] + 0.5),
                                          limits[list(aim.servos), 0],
                                          limits[list(aim.servos), 1])
        off = float(np.degrees(np.hypot(*_angles(chain, whole[None], tip, goal)[0])))
        worst = min(worst, off)
        if off > LOOKED_DEG or np.linalg.norm(goal - chain.transforms(whole)[tip, :3, 3]) < 0.05:
            continue
        contacts = checker.contacts_of(whole) if checker is not None else []
        if not contacts:
            return {i: int(whole[i]) for i in aim.servos}
        blocked = blocked or contacts[0]
    if blocked is not None:
        raise GestError(sources.error(
            f"'{aim.label}' puts {checker.into(blocked, aim.servos)}: every turn of the "
            f"head that looks there does", aim.pos, "a place higher up, or further away"))
    raise GestError(sources.error(
        f"'{aim.label}' is out of the head's range: the gaze misses it by "
        f"{worst:.0f} degrees", aim.pos,
        "a place in front of the robot, not too far to a side, above or below"))


def _share(profile: Profile, chain: Chain, start: np.ndarray, head: list[int],
           eyes: list[int], limits: np.ndarray, tip: int, goal: np.ndarray,
           share: float) -> np.ndarray:
    """The pose that looks at ``goal``, the eyes taking ``share`` of the head's turn
    (1: all they can, the head the rest; 0: the eyes held at rest)."""
    values = start.copy()
    for i in eyes:
        values[i] = profile.servos[i].rest
    if share >= 1:
        values = _turn(chain, values, eyes, limits[eyes], tip, goal)
        return _turn(chain, values, head, limits[head], tip, goal)
    values = _turn(chain, values, head, limits[head], tip, goal)
    if share > 0:
        for h, e in zip(head, eyes, strict=True):  # rothead with eye_x, neck with eye_y
            angle = joints.position(profile.servos[h], values[h]) * share
            values[e] = np.clip(joints.value(profile.servos[e], angle), *limits[e])
        values = _turn(chain, values, head, limits[head], tip, goal)
        values = _turn(chain, values, eyes, limits[eyes], tip, goal)
    return values
