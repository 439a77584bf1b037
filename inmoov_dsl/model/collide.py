"""Whether a pose drives the robot into itself (pure but for python-fcl): the contacts
between a profile's parts, in the model of ``gestc urdf``.

Built once per profile (``Checker``): the model's parts as FCL objects (shapes.py), the
pairs to check (every pair but the allowed ones, allowed.py) and each pair's clearance.
A pose is servo values by servo name, as gestures give them; ``contacts`` places every
part (kinematics.py) and returns the checked pairs closer than their clearance, with
FCL's distance or depth. A pair's clearance is the profile's (``[collision]``), but
never more than the gap the pair has at rest, less ``TOLERANCE_MM``: parts that stand
that close by design (the upper arms hang 10 mm from the chest) count as touching only
when closer still, so the rest pose is never a contact (docs/collisions.md).
"""

from __future__ import annotations

import dataclasses
import threading
from collections.abc import Callable, Collection, Iterator, Mapping
from dataclasses import dataclass

import numpy as np

from ..compiling.plan import Plan
from ..errors import GestError
from ..hardware import Profile
from ..protocol import SERVO_FRAME
from .allowed import PALM, Allowed, allowed_for
from .kinematics import Chain
from .shapes import Bodies

TOLERANCE_MM = 0.01  #: FCL's distances agree to about a micrometre; ten of them
DEEPER_MM = 1.0  #: a contact the motion starts in counts once it is this much deeper
CHUNK = 50  #: poses swept at once (1 s of motion, a few ms): memory stays small, a stop comes soon
KEEP = 16  #: plans whose contacts are kept

Step = Callable[[], None]
_KEPT: dict[int, tuple] = {}  #: id(plan.tracks) -> (tracks, checker, its first contacts)
_KEPT_LOCK = threading.Lock()


@dataclass(frozen=True, eq=False)
class Touch:
    """A pair's contact along a motion: when it began (``at``, the servos' ``values``
    then) and ``contact`` at its deepest, ``deepest`` s."""

    at: float
    contact: Contact
    values: np.ndarray
    deepest: float


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
    profile's ``[collision]`` clearance, 10 mm by default, unless given)."""

    def __init__(self, profile: Profile, allowed: Allowed | None = None,
                 clearance_mm: float | None = None):
        self.profile = profile
        self.allowed = allowed if allowed is not None else allowed_for(profile)
        self.clearance_mm = (profile.clearance_mm if clearance_mm is None
                             else float(clearance_mm))
        self.chain = Chain(profile)
        self.bodies = Bodies(self.chain)
        names = self.bodies.names
        checked = [(i, j) for j in range(len(names)) for i in range(j)
                   if (names[i], names[j]) not in self.allowed]
        self._a = np.array([i for i, _ in checked], dtype=int)
        self._b = np.array([j for _, j in checked], dtype=int)
        links = self.bodies.links
        self._parts = {self.chain.links[i]: part(self.chain.links[i]) for i in links}
        palm = [-1] * len(self.chain.links)  # a hand's links are told as the hand
        for i, p in enumerate(self.chain.parent):
            palm[i] = i if self.chain.links[i].endswith(PALM) else palm[p] if p >= 0 else -1
            if palm[i] >= 0:
                self._parts[self.chain.links[i]] = part(
                    self.chain.links[palm[i]].removesuffix(PALM) + "_hand")
        #: which servos move each checked pair's parts relative to each other
        self._turns = np.zeros((len(checked), len(profile.servos)), dtype=bool)
        for k, (i, j) in enumerate(checked):
            self._turns[k, list(self.chain.servos_between(links[i], links[j]))] = True
        rest = self.bodies.gaps(self.chain.transforms(self.chain.values({})), self._a, self._b)
        self._limit = np.minimum(self.clearance_mm, rest - TOLERANCE_MM)

    def part(self, link: str) -> str:
        """A link as a message names it: ``the right upper arm``; a finger or a palm,
        ``the right hand``."""
        return self._parts.get(link) or part(link)

    def into(self, contact: Contact, moving: Collection[int]) -> str:
        """``the right forearm into the chest (by 12 mm)`` (or ``within 3 mm of``): the
        part the ``moving`` servos carry first."""
        a, b = contact.a, contact.b
        if not self.chain.servos_between(self.chain.links.index(a), 0) & set(moving):
            a, b = b, a
        if contact.depth_mm > 0:
            return f"{self.part(a)} into {self.part(b)} (by {contact.depth_mm:.0f} mm)"
        return f"{self.part(a)} within {max(contact.distance_mm, 0):.0f} mm of {self.part(b)}"

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
        found = self.sweep(np.asarray(values, dtype=float)[None])
        return sorted(found[0][1] if found else [], key=lambda c: c.distance_mm)

    def sweep(self, values: np.ndarray, still: bool = True) -> list[tuple[int, list[Contact]]]:
        """(row, contacts) of each row of ``values`` (poses in the profile's servo order,
        one after another along a motion) where a checked pair is closer than its
        clearance. A pair whose parts no servo of the motion moves relative to each
        other is measured in the first pose only (not at all without ``still``: its
        distance never changes); the others along the motion (``_scan``)."""
        values = np.asarray(values, dtype=float)
        moves = (values != values[:1]).any(axis=0)
        live = self._turns[:, moves].any(axis=1)
        found: dict[int, list[Contact]] = {}
        scans = [(values, np.flatnonzero(live))]
        if still:
            scans.append((values[:1], np.flatnonzero(~live)))
        for rows, pairs in scans:
            for row, contacts in self._scan(rows, pairs):
                found.setdefault(row, []).extend(contacts)
        return sorted(found.items())

    def _scan(self, values: np.ndarray, pairs: np.ndarray) -> Iterator[tuple[int, list[Contact]]]:
        """``sweep`` over the checked pairs ``pairs``: every pose placed at once (numpy);
        FCL asked only of pairs whose bounding spheres are near, and not again while
        neither part can have moved far enough since FCL last measured them to come
        within the pair's clearance (``travel``)."""
        if not pairs.size:
            return
        bodies, a, b, limit = self.bodies, self._a[pairs], self._b[pairs], self._limit[pairs]
        places = self.chain.transforms(values)[:, bodies.links]
        centres = bodies.centres_of(places)
        apart = np.linalg.norm(centres[:, a] - centres[:, b], axis=-1)
        near = apart < bodies.reach(a, b) + self.clearance_mm / 1000
        if len(values) > 1:
            went = travel(places, centres, bodies.radius)
            went = went[:, a] + went[:, b]  #: how far the pair's parts have gone, together
        else:
            went = np.zeros((1, len(a)))
        budget = np.full(len(a), -np.inf)  #: how far they may go before FCL is asked
        gap = np.zeros(len(a))
        for row in np.flatnonzero(near.any(axis=1)).tolist():
            k = np.flatnonzero(near[row])
            k = k[went[row, k] >= budget[k]]
            if not k.size:
                continue
            gap[k] = bodies.gaps_at(places[row], centres[row], a[k], b[k])
            budget[k] = went[row, k] + gap[k] - limit[k]
            close = k[gap[k] < limit[k]]
            if close.size:
                names = bodies.names
                yield row, [Contact(names[a[i]], names[b[i]], round(float(gap[i]), 3))
                            for i in close.tolist()]


def travel(places: np.ndarray, centres: np.ndarray, radius: np.ndarray) -> np.ndarray:
    """How far (mm) each body may have gone by each row of a motion, at most: from one
    row to the next every point of a body moves no more than its centre did plus its
    radius times the angle it turned; summed along the rows (rows, bodies)."""
    shift = np.linalg.norm(np.diff(centres, axis=0), axis=-1)
    turn = np.einsum("tnij,tnij->tn", places[1:, :, :3, :3], places[:-1, :, :3, :3])
    angle = np.arccos(np.clip((turn - 1) / 2, -1.0, 1.0))  # trace R1 R0^T = 1 + 2 cos
    step = (shift + radius * angle) * 1000
    return np.concatenate([np.zeros((1, centres.shape[1])), np.cumsum(step, axis=0)])


# --- a profile's check, and a plan's contacts (what guard.py tells and refuses)

_CHECKERS: dict[tuple[str, str], Checker | None] = {}  #: (name, sha256) -> its Checker


def checker_for(profile: Profile) -> Checker | None:
    """The profile's ``Checker``, built once; None when it has no model (a servo on a
    joint the model lacks), no two parts of the robot that can meet (a hand alone:
    only its own fingers and forearm) or no python-fcl."""
    key = (profile.name, profile.sha256)
    if key not in _CHECKERS and not would_check(profile):
        _CHECKERS[key] = None  # not built at all: a hand's gestures pay nothing
    if key not in _CHECKERS:
        try:
            checker = Checker(profile)
        except GestError:  # a servo the model does not have: no model, no check
            _CHECKERS[key] = None
            return None
        sides = {name.split("_")[0] for pair in checker.pairs for name in pair}
        _CHECKERS[key] = checker if len(sides) > 1 else None
    return _CHECKERS[key]


def would_check(profile: Profile) -> bool:
    """Whether the profile's robot has parts that can meet (python-fcl or not): its
    model's parts are on more than one side (a hand alone is on one)."""
    try:
        chain = Chain(profile)
    except GestError:
        return False
    return len({link.split("_")[0] for link, shape in zip(chain.links, chain.shapes,
                                                           strict=True) if shape}) > 1


def part(link: str) -> str:
    """A link's name as a message says it: ``r_upper_arm`` -> ``the right upper arm``."""
    words = link.removesuffix("_link").split("_")
    words[0] = {"r": "right", "l": "left"}.get(words[0], words[0])
    return "the " + " ".join(words)


def first_contacts(checker: Checker, plan: Plan, step: Step | None = None
                   ) -> list[Touch]:
    """Each checked pair's first contact in ``plan`` (when it began, at its deepest),
    sampled every servo frame. The newest plans' are kept: the editor's check and its
    preview page ask for the same plan's (``step``: as ``contacts_along``)."""
    with _KEPT_LOCK:
        kept = _KEPT.get(id(plan.tracks))
    if kept is not None and kept[0] is plan.tracks and kept[1] is checker:
        return list(kept[2])
    times = np.arange(0.0, plan.duration + SERVO_FRAME, SERVO_FRAME)
    values = np.tile(np.asarray(plan.final, dtype=float), (len(times), 1))
    for i in {i for step in plan.steps for i in step.servos}:  # the others stay put
        values[:, i] = plan.tracks[i].position(times)
    found = contacts_along(checker, times, values, step)
    with _KEPT_LOCK:
        _KEPT.pop(id(plan.tracks), None)
        _KEPT[id(plan.tracks)] = (plan.tracks, checker, tuple(found))
        while len(_KEPT) > KEEP:
            del _KEPT[next(iter(_KEPT))]
    return found


def contacts_along(checker: Checker, times: np.ndarray, values: np.ndarray,
                   step: Step | None = None) -> list[Touch]:
    """``first_contacts`` of a motion: servo ``values`` (rows, profile order) at
    ``times``; two parts as messages name them are one pair (a hand's palm and fingers
    are the hand). A pair already touching in the first pose is the motion's only where
    it goes DEEPER_MM further in: a robot that starts in contact may move out of it.
    Swept CHUNK poses at a time, ``step()`` called before each (what it raises stops the
    sweep: an editor's newer text)."""
    found: dict[tuple[str, str], Touch] = {}
    already: dict[tuple[str, str], float] = {}
    for lo in range(0, len(values), CHUNK):
        if step is not None:
            step()
        first = max(lo - 1, 0)  # and the pose before: what moved into the chunk moves
        for row, contacts in checker.sweep(values[first:lo + CHUNK], still=False):
            row += first  # (a still pair: no deeper)
            for contact in contacts if row >= lo else ():  # (the pose before: seen)
                pair = (checker.part(contact.a), checker.part(contact.b))
                if row == 0:
                    already[pair] = contact.distance_mm
                    continue
                if pair in already and contact.distance_mm > already[pair] - DEEPER_MM:
                    continue
                at = float(times[row])
                begun = found.setdefault(pair, Touch(at, contact, values[row], at))
                if contact.distance_mm < begun.contact.distance_mm:  # the deepest it goes
                    found[pair] = dataclasses.replace(begun, contact=contact, deepest=at)
    return sorted(found.values(), key=lambda f: f.at)
