"""Whether a pose drives the robot into itself (pure but for python-fcl): the contacts
between a profile's parts, in the model of ``gestc urdf``.

Built once per profile (``Checker``): the model's parts as FCL objects (shapes.py), the
pairs to check (every pair but the allowed ones, allowed.py) and each pair's clearance.
A pose is servo values by servo name, as gestures give them; ``contacts`` places every
part (kinematics.py) and returns the checked pairs closer than their clearance, with
FCL's distance or depth. A pair's clearance is the profile's (``CLEARANCE_MM``), but
never more than the gap the pair has at rest, less ``TOLERANCE_MM``: parts that stand
that close by design (the upper arms hang 10 mm from the chest) count as touching only
when closer still, so the rest pose is never a contact (docs/collisions.md).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from ..hardware import Profile
from .allowed import Allowed, allowed_for
from .kinematics import Chain
from .shapes import Bodies

TOLERANCE_MM = 0.01  #: FCL's distances agree to about a micrometre; ten of them


@dataclass(frozen=True)
class Contact:
    """Two parts (links) closer than their clearance: ``distance_mm`` between them, less
    than 0 when one enters the other (by ``depth_mm``)."""

    a: str
    b: str
    distance_mm: float

    @property
    def depth_mm(self) -> float:
        """How far one part is inside the other (0: they only come too close)."""
        return max(0.0, -self.distance_mm)


class Checker:
    """A profile's self-collision check. ``allowed``: the pairs never checked (the
    profile's file, or made now); ``clearance_mm``: closer than this is touching (the
    allowed pairs' own, 10 mm, unless given)."""

    def __init__(self, profile: Profile, allowed: Allowed | None = None,
                 clearance_mm: float | None = None):
        self.profile = profile
        self.allowed = allowed if allowed is not None else allowed_for(profile)
        self.clearance_mm = (self.allowed.clearance_mm if clearance_mm is None
                             else float(clearance_mm))
        self.chain = Chain(profile)
        self.bodies = Bodies(self.chain)
        names = self.bodies.names
        checked = [(i, j) for j in range(len(names)) for i in range(j)
                   if (names[i], names[j]) not in self.allowed]
        self._a = np.array([i for i, _ in checked], dtype=int)
        self._b = np.array([j for _, j in checked], dtype=int)
        rest = self.bodies.gaps(self.chain.transforms(self.chain.values({})), self._a, self._b)
        self._limit = np.minimum(self.clearance_mm, rest - TOLERANCE_MM)

    @property
    def pairs(self) -> list[tuple[str, str]]:
        """The pairs checked, by link name."""
        names = self.bodies.names
        return [(names[i], names[j]) for i, j in zip(self._a, self._b, strict=True)]

    def limit_mm(self, a: str, b: str) -> float:
        """The clearance of the checked pair (``a``, ``b``); KeyError if it is not one."""
        pairs = self.pairs
        k = pairs.index((a, b)) if (a, b) in pairs else pairs.index((b, a))
        return float(self._limit[k])

    def contacts(self, pose: Mapping[str, float]) -> list[Contact]:
        """The checked pairs closer than their clearance when the servos hold ``pose``
        (servo name -> value; a servo not named holds its rest value), deepest first."""
        return self.contacts_of(self.chain.values(pose))

    def contacts_of(self, values: np.ndarray) -> list[Contact]:
        """``contacts`` of servo values in the profile's order."""
        transforms = self.chain.transforms(np.asarray(values, dtype=float))
        near = np.flatnonzero(self.bodies.near(transforms, self._a, self._b,
                                               self.clearance_mm))
        gaps = self.bodies.gaps(transforms, self._a[near], self._b[near])
        close = gaps < self._limit[near]
        names = self.bodies.names
        found = [Contact(names[self._a[k]], names[self._b[k]], round(float(gap), 3))
                 for k, gap in zip(near[close].tolist(), gaps[close].tolist(), strict=True)]
        return sorted(found, key=lambda c: c.distance_mm)
