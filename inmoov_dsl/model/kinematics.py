"""Where every link of a profile's model is for a pose (pure, numpy): forward kinematics
over urdf.body's parts, the joints turned as the URDF turns them.

A pose is servo values by servo name (the values gestures use; a servo left out holds
its rest value). Each moving joint turns by ``joints.position`` of its servo (times its
``mimic`` multiplier); a joint no servo of the profile turns stays at rest, as the URDF
has it fixed. Built once per profile (``Chain``); a pose costs a few tens of
microseconds: the joints' rotations in one batch, then one matrix product per tree level.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ..hardware import Profile
from . import joints
from .urdf import body
from .urdf_parts import Part, Shape


def _rpy(rpy: tuple[float, float, float]) -> np.ndarray:
    """The rotation of URDF's roll, pitch, yaw (fixed axes x, y, z)."""
    r, p, y = rpy
    cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
    return np.array([[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                     [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                     [-sp, cp * sr, cp * cr]])


def _origin(part: Part) -> np.ndarray:
    out = np.eye(4)
    out[:3, :3] = _rpy(part.rpy)
    out[:3, 3] = part.xyz
    return out


class Chain:
    """A profile's model as a tree of links: ``links`` root first, each link's ``shape``
    (None: it has none), ``parent`` (its index, -1 for the root) and ``moving`` (whether a
    servo turns the joint that carries it)."""

    def __init__(self, profile: Profile):
        parts = body(profile)
        self.links: list[str] = [p.link for p in parts]
        self.shapes: list[Shape | None] = [p.shape for p in parts]
        index = {name: i for i, name in enumerate(self.links)}
        self.parent: list[int] = [index.get(p.parent, -1) for p in parts]
        servos = {s.joint: (profile.index(s.name), s) for s in profile.servos}
        self._rest = np.array([float(s.rest) for s in profile.servos])
        self._names = {s.name: i for i, s in enumerate(profile.servos)}
        # each moving joint: its link, its axis, its servo's index, radians per value
        moving = []
        for i, part in enumerate(parts):
            master, k = part.mimic or (part.joint, 1.0)
            if part.axis is not None and master in servos:
                slot, servo = servos[master]
                moving.append((i, part.axis, slot, joints.scale(servo) * k))
        self.moving: list[bool] = [False] * len(parts)
        for i, *_ in moving:
            self.moving[i] = True
        self._joint_link = np.array([m[0] for m in moving], dtype=int)
        axes = np.array([m[1] for m in moving], dtype=float).reshape(-1, 3)
        self._turn = _rodrigues(axes / np.linalg.norm(axes, axis=1, keepdims=True))
        self._slot = np.array([m[2] for m in moving], dtype=int)
        self._gain = np.array([m[3] for m in moving], dtype=float)
        self._origin = np.stack([_origin(p) for p in parts])
        self._levels = self._by_depth()
        self._above: list[frozenset[int]] = []  #: each link's moving joints, root down
        for i, p in enumerate(self.parent):
            own = {j for j, link in enumerate(self._joint_link.tolist()) if link == i}
            self._above.append((self._above[p] if p >= 0 else frozenset()) | own)

    def _by_depth(self) -> list[tuple[np.ndarray, np.ndarray]]:
        """(links, their parents) at each depth of the tree below the root."""
        depth = [0] * len(self.links)
        for i, p in enumerate(self.parent):  # parts come after their parent
            depth[i] = depth[p] + 1 if p >= 0 else 0
        return [(np.array(ids), np.array([self.parent[i] for i in ids]))
                for d in range(1, max(depth) + 1)
                if (ids := [i for i, x in enumerate(depth) if x == d])]

    def servos_between(self, i: int, j: int) -> frozenset[int]:
        """The servos (profile indices) whose turning moves link ``i`` and link ``j``
        relative to each other: those of the joints between them in the tree."""
        return frozenset(self._slot[k] for k in self._above[i] ^ self._above[j])

    def values(self, pose: Mapping[str, float]) -> np.ndarray:
        """The pose as an array in the profile's servo order (rest where not given);
        KeyError for a servo the profile does not have."""
        out = self._rest.copy()
        for name, value in pose.items():
            out[self._names[name]] = value
        return out

    def transforms(self, values: np.ndarray) -> np.ndarray:
        """Every link's place (4x4, the base's frame) for servo ``values`` in the
        profile's order: an array (links, 4, 4); for poses (rows, servos), one (rows,
        links, 4, 4), every pose at once."""
        values = np.asarray(values, dtype=float)
        rows = values.reshape(-1, values.shape[-1])
        angles = ((rows[:, self._slot] - self._rest[self._slot]) * self._gain).T
        eye, outer, cross = self._turn  # each (joints, 3, 3); below, (joints, rows, 3, 3)
        c, s = np.cos(angles)[..., None, None], np.sin(angles)[..., None, None]
        turned = eye[:, None] * c + outer[:, None] * (1 - c) + cross[:, None] * s  # Rodrigues
        world = np.repeat(self._origin[:, None], len(rows), axis=1)  # (links, rows, 4, 4)
        links = self._joint_link
        world[links, :, :3, :3] = world[links, :, :3, :3] @ turned
        for ids, parents in self._levels:  # the root's place is its origin; each level
            world[ids] = world[parents] @ world[ids]  # below its parent's, level by level
        world = world.transpose(1, 0, 2, 3)
        return world.reshape(values.shape[:-1] + world.shape[1:])


def _rodrigues(axes: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The identity, a a^T and the cross-product matrix of each unit axis a: a rotation
    by t about a is I cos t + a a^T (1 - cos t) + [a]x sin t."""
    x, y, z = axes.T
    zero = np.zeros_like(x)
    cross = np.stack([np.stack([zero, -z, y], -1), np.stack([z, zero, -x], -1),
                      np.stack([-y, x, zero], -1)], -2)
    return np.broadcast_to(np.eye(3), cross.shape), np.einsum("ni,nj->nij", axes, axes), cross
