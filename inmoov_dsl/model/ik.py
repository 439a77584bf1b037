"""A hand's place as its arm's joint angles (inverse kinematics, position only), by the
Robotics Toolbox's Levenberg-Marquardt solver (``ETS.ik_LM``, C++ inside), chosen by
measurement (docs/reach.md, benchmarks/reach.py).

An ``ArmChain`` is the arm from its first joint to the hand's point as the toolbox's
elementary transforms, its joints those of the aim's servos, every other joint held
where the pose before the step has it (the torso carries the shoulder, the wrist the
hand's point). Where the toolbox is not installed (the ``reach`` extra), the same
solve is done here by damped least squares on the model's own kinematics: slower, and
said once a compile (``reach.note``).
"""

from __future__ import annotations

import functools
import importlib.util
from collections.abc import Sequence
from typing import Any

import numpy as np

from ..hardware import Profile
from . import joints
from .kinematics import Chain
from .urdf import body

INSTALL = "pip install 'inmoov-dsl[reach]' (the Robotics Toolbox: solves in well under 1 ms)"
TOLERANCE_M = 1e-6  #: the continuous solve's own tolerance, before values are rounded


def installed() -> bool:
    """Whether the toolbox is installed (asked without importing it: seconds)."""
    return importlib.util.find_spec("roboticstoolbox") is not None


@functools.cache
def toolbox() -> tuple[Any, Any] | None:
    """The toolbox's ``ET`` and ``ETS`` (imported once, when a place is first solved),
    or None when it is not installed."""
    try:
        from roboticstoolbox import ET, ETS
    except ImportError:
        return None
    return ET, ETS


class ArmChain:
    """The arm of ``slots`` (servo indices, root first) to link ``tip`` of ``chain``: its
    joints' links, axes and radians per value, and its pieces that no arm servo turns
    at a pose (``pieces``)."""

    def __init__(self, chain: Chain, profile: Profile, slots: Sequence[int], tip: str):
        parts = body(profile)
        by_link = {p.link: p for p in parts}
        self.chain, self.slots = chain, tuple(slots)
        turned = [profile.servos[i].joint for i in slots]
        self.links = [chain.links.index(next(p.link for p in parts if p.joint == j))
                      for j in turned]
        self.axes = [by_link[chain.links[k]].axis for k in self.links]
        self.tip = chain.links.index(tip)
        servos = [profile.servos[i] for i in slots]
        self.rest = np.array([s.rest for s in servos], dtype=float)
        self.gain = np.array([joints.scale(s) for s in servos], dtype=float)
        limits = np.array([[s.lo, s.hi] for s in servos], dtype=float)
        q = (limits - self.rest[:, None]) * self.gain[:, None]
        self.qlim = np.sort(q, axis=1).T  # (2, joints): lowest, highest
        self._ets: dict[bytes, Any] = {}

    def q(self, values: np.ndarray) -> np.ndarray:
        """The arm's joint angles (radians) at servo values (the profile's order)."""
        return (values[list(self.slots)] - self.rest) * self.gain

    def tip_at(self, values: np.ndarray, q: np.ndarray) -> np.ndarray:
        """Where the tip is (the base's frame) at ``values`` with the arm at ``q``."""
        row = values.copy()
        row[list(self.slots)] = self.values(q)
        return self.chain.transforms(row)[self.tip, :3, 3]

    def values(self, q: np.ndarray) -> np.ndarray:
        """The arm's servo values (not rounded) for joint angles ``q``."""
        return self.rest + q / self.gain

    def pieces(self, values: np.ndarray) -> tuple[np.ndarray, list[np.ndarray]]:
        """At the pose ``values``: where the arm's first joint is (its frame before it
        turns), and the fixed transform after each joint (to the next joint's frame
        before it turns, or to the tip)."""
        world, q = self.chain.transforms(values), self.q(values)
        unturned = [world[link] @ _about(axis, -angle)
                    for link, axis, angle in zip(self.links, self.axes, q, strict=True)]
        ends = [*unturned[1:], world[self.tip]]
        after = [np.linalg.inv(world[link]) @ end for link, end in zip(self.links, ends,
                                                                       strict=True)]
        return unturned[0], after

    def at(self, values: np.ndarray) -> tuple[np.ndarray, Any]:
        """The arm at the pose ``values``: where its first joint is, and the toolbox's
        chain of it (None without the toolbox), kept for the pieces it is made of."""
        before, after = self.pieces(values)
        found = toolbox()
        if found is None:
            return before, None
        key = np.round(np.stack(after), 9).tobytes()
        if key not in self._ets:
            if len(self._ets) > 256:
                self._ets.clear()
            et, ets = found
            items = []
            for axis, piece in zip(self.axes, after, strict=True):
                items += [_joint(et, axis), et.SE3(piece)]
            chain = ets(items)
            chain.qlim = self.qlim
            self._ets[key] = chain
        return before, self._ets[key]


def _about(axis: Sequence[float], angle: float) -> np.ndarray:
    """A 4x4 turn by ``angle`` about a unit ``axis``."""
    a = np.asarray(axis, dtype=float)
    a = a / np.linalg.norm(a)
    cross = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    out = np.eye(4)
    out[:3, :3] = np.eye(3) + np.sin(angle) * cross + (1 - np.cos(angle)) * cross @ cross
    return out


def _joint(et: Any, axis: Sequence[float]) -> Any:
    """The toolbox's turning joint about a principal ``axis`` (the model's are)."""
    k = int(np.argmax(np.abs(axis)))
    if abs(abs(axis[k]) - 1) > 1e-9 or sum(abs(c) for c in axis) > 1 + 1e-9:
        raise ValueError(f"a joint about {axis}: the model's arms turn about x, y or z")
    return (et.Rx, et.Ry, et.Rz)[k](flip=bool(axis[k] < 0))


def solve(arm: ArmChain, values: np.ndarray, goal: np.ndarray, seeds: np.ndarray
          ) -> tuple[np.ndarray | None, int]:
    """Joint angles within the joints' limits that put the arm's tip at ``goal`` (the
    base's frame), searched from each row of ``seeds`` in turn, and how many rows were
    used; (None, all of them) when no search ends within the limits at the place."""
    before, chain = arm.at(values)
    if chain is None:
        for k, seed in enumerate(seeds):
            q = nearest(arm, values, goal, seed)
            if np.linalg.norm(arm.tip_at(values, q) - goal) < 1e-4:
                return q, k + 1
        return None, len(seeds)
    local = np.linalg.inv(before) @ np.append(goal, 1.0)
    wanted = np.eye(4)
    wanted[:3, 3] = local[:3]
    mask = np.array([1, 1, 1, 0, 0, 0.0])
    for k, seed in enumerate(seeds):  # one search each: the toolbox's restarts are random
        found = chain.ik_LM(wanted, q0=seed, ilimit=60, slimit=1, tol=TOLERANCE_M,
                            mask=mask, joint_limits=False)
        q = (np.asarray(found.q, dtype=float) + np.pi) % (2 * np.pi) - np.pi  # a turn is a turn
        if found.success and np.all(q >= arm.qlim[0] - 1e-9) and np.all(q <= arm.qlim[1] + 1e-9):
            return np.clip(q, arm.qlim[0], arm.qlim[1]), k + 1
    return None, len(seeds)


def nearest(arm: ArmChain, values: np.ndarray, goal: np.ndarray, seed: np.ndarray,
            steps: int = 100) -> np.ndarray:
    """Damped least squares on the model's kinematics, the Jacobian by finite
    differences (every pose of a step in one batch), clamped to the limits: the
    fallback without the toolbox, and where a place is out of reach, the joint angles
    that come nearest it (the toolbox's solver stops where it fails)."""
    q, eps, damping = np.array(seed, dtype=float), 1e-6, 1e-4
    rows = np.repeat(values[None], len(q) + 1, axis=0)
    slots = list(arm.slots)
    for _ in range(steps):
        rows[:, slots] = arm.values(q)
        rows[1:, slots] += np.eye(len(q)) * eps / arm.gain
        tips = arm.chain.transforms(rows)[:, arm.tip, :3, 3]
        error = goal - tips[0]
        if np.linalg.norm(error) < TOLERANCE_M:
            break
        jac = ((tips[1:] - tips[0]) / eps).T
        step = jac.T @ np.linalg.solve(jac @ jac.T + damping * np.eye(3), error)
        q = np.clip(q + step, arm.qlim[0], arm.qlim[1])
    return q
