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

from ..compiling.plan import Plan, PlannedStep
from ..errors import Diagnostic, GestError, SourceMap
from ..hardware import Profile
from ..protocol import SERVO_FRAME
from .allowed import Allowed, allowed_for
from .kinematics import Chain
from .shapes import Bodies, need_fcl

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


# --- the compiler's check of a plan (docs/collisions.md), given by a command:
# compiler.plan_checks

_CHECKERS: dict[tuple[str, str], Checker | None] = {}  #: (name, sha256) -> its Checker


def checker_for(profile: Profile) -> Checker | None:
    """The profile's ``Checker``, built once; None when it has no model (a servo on a
    joint the model lacks) or no two parts of the robot that can meet (a hand alone:
    only its own fingers and forearm)."""
    key = (profile.name, profile.sha256)
    if key not in _CHECKERS:
        try:
            checker = Checker(profile)
        except GestError:  # a servo the model does not have: no model, no check
            _CHECKERS[key] = None
            return None
        sides = {name.split("_")[0] for pair in checker.pairs for name in pair}
        _CHECKERS[key] = checker if len(sides) > 1 else None
    return _CHECKERS[key]


def part(link: str) -> str:
    """A link's name as a message says it: ``r_upper_arm`` -> ``the right upper arm``."""
    words = link.removesuffix("_link").split("_")
    words[0] = {"r": "right", "l": "left"}.get(words[0], words[0])
    return "the " + " ".join(words)


def first_contacts(checker: Checker, plan: Plan) -> list[tuple[float, Contact, np.ndarray]]:
    """(time, contact, servo values) of each checked pair's first contact in ``plan``
    (the time and values when it began, the contact at its deepest), sampled every servo
    frame; a sample where no servo moved is not checked again."""
    times = np.arange(0.0, plan.duration + SERVO_FRAME, SERVO_FRAME)
    values = np.stack([track.position(times) for track in plan.tracks], axis=1)
    found: dict[tuple[str, str], tuple[float, Contact, np.ndarray]] = {}
    last = None
    for t, row in zip(times.tolist(), values, strict=True):
        if last is not None and np.array_equal(row, last):
            continue
        last = row
        for contact in checker.contacts_of(row):
            begun = found.setdefault((contact.a, contact.b), (t, contact, row))
            if contact.distance_mm < begun[1].distance_mm:  # the deepest it goes
                found[contact.a, contact.b] = (begun[0], contact, begun[2])
    return sorted(found.values(), key=lambda f: f[0])


def moving_step(plan: Plan, t: float) -> PlannedStep | None:
    """The step that was moving at ``t`` (the last one begun by then that moves a
    servo), or None."""
    begun = [s for s in plan.steps if s.start <= t + 1e-9 and s.servos]
    return begun[-1] if begun else None


def check_plan(plan: Plan, sources: SourceMap, strict: bool) -> tuple[Diagnostic, ...]:
    """Each checked pair's first contact in ``plan``: a warning at the step moving when
    it began (an error with ``strict``: raised). Without python-fcl nothing is checked,
    unless ``strict``: then that is the error."""
    try:
        need_fcl()
    except GestError:
        if strict:
            raise
        return ()
    checker = checker_for(plan.profile)
    if checker is None:
        return ()
    make = sources.error if strict else sources.warning
    told = []
    for t, contact, row in first_contacts(checker, plan):
        step = moving_step(plan, t)
        servos = step.servos if step else ()
        named = ", ".join(f"{plan.profile.servos[i].name} {row[i]:.0f}" for i in servos)
        how = (f"enters {part(contact.a)} by {contact.depth_mm:.0f} mm" if contact.depth_mm
               else f"comes within {contact.distance_mm:.0f} mm of {part(contact.a)}")
        told.append(make(
            f"at {t:.2f} s {part(contact.b)} {how}" + (f" ({named})" if named else ""),
            step.pos if step else None,
            "move " + (", ".join(plan.profile.servos[i].name for i in servos) or "the servos")
            + " less far, or in another order, so the parts stay apart "
            "(gestc urdf shows the model)"))
    if strict and told:
        raise GestError(told)
    return tuple(told)
