"""Places as servo values (stage 2b, between resolve and plan): each ``right hand to
cup`` or ``look at cup`` of a gesture solved from the pose before its step.

The resolver turns such an item into an ``Aim`` (where, and the servos it may turn);
``solve`` walks a gesture's actions in order, keeping the pose each step leaves, and
asks the solver for each aim's values (the same aim from the same pose once: a call
in a repeat is solved once). The solver is the robot model's inverse kinematics
(``model.reach``): the compiler does not import the model, so the model gives it
(``provide``) when its package is imported, as every front end and the package's own
``inmoov_dsl.compile_source`` do.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

from ..errors import Diagnostic, GestError, Pos, SourceMap
from ..hardware import Profile
from .actions import Action

#: the joints each kind of aim solves, by the model's joint names, the ones a profile
#: must have first (a hand's arm: raise sideways, forward, turn, bend; the gaze: turn and
#: nod the head, then the eyes when it has them); the frame it puts at the place
SOLVES: Mapping[str, tuple[tuple[str, ...], tuple[str, ...]]] = {
    "right": (("r_omoplate", "r_shoulder", "r_rotate", "r_bicep"), ()),
    "left": (("l_omoplate", "l_shoulder", "l_rotate", "l_bicep"), ()),
    "look": (("rothead", "neck"), ("eye_x", "eye_y")),
}
FRAMES = {"right": "right_hand_point", "left": "left_hand_point", "look": "gaze"}
#: the most places one compile solves (each from its own pose before; a place met again
#: from the same pose is solved once): a few milliseconds each, so a compile's work stays
#: bounded whatever the text asks
MAX_SOLVES = 2000


@dataclass(frozen=True)
class Aim:
    """A hand's point to put at a place (``what``: ``right`` or ``left``), or the gaze to
    turn to it (``look``); ``servos``: the profile's servos it turns (indices)."""

    what: str
    xyz: tuple[float, float, float]  #: metres, the robot's base frame
    servos: tuple[int, ...]
    pos: Pos | None = None  #: the item, in its file
    place: str = ""  #: the place's name, when it has one

    @property
    def label(self) -> str:
        """The item as a message quotes it: ``right hand to cup``."""
        where = self.place or "(" + ", ".join(f"{c * 1000:g}" for c in self.xyz) + ") mm"
        return f"look at {where}" if self.what == "look" else f"{self.what} hand to {where}"


#: (profile, aim, the pose before its step) -> the aim's servos' values, or a Diagnostic
#: (out of reach, into the body) at ``aim.pos``
Solver = Callable[[Profile, Aim, Sequence[int], SourceMap], dict[int, int]]
Note = Callable[[], str | None]  #: what a compile that solves a hand's place warns once
_SOLVER: list[tuple[Solver, Note]] = []


def provide(solver: Solver, note: Note) -> None:
    """Make ``solver`` the one that turns aims into values (``model.reach`` does), and
    ``note`` what is said once of how it solves them (None: nothing)."""
    _SOLVER[:] = [(solver, note)]


def servos_for(profile: Profile, what: str) -> tuple[tuple[int, ...], tuple[str, ...]]:
    """The profile's servos an aim of ``what`` turns (indices), and the joints it lacks
    of those it needs."""
    needed, optional = SOLVES[what]
    by_joint = {s.joint: i for i, s in enumerate(profile.servos)}
    found = tuple(by_joint[j] for j in (*needed, *optional) if j in by_joint)
    return found, tuple(j for j in needed if j not in by_joint)


def solve(actions: Sequence[Action], start: Sequence[int], profile: Profile,
          sources: SourceMap, strict: bool = False
          ) -> tuple[tuple[Action, ...], tuple[Diagnostic, ...]]:
    """``actions`` with every aim replaced by the values it solves to from the pose
    before its step (``start`` before the first), and the solver's note as a warning
    at the first hand's place (with ``strict``, an error); the actions as they are when
    none has an aim. Every aim's error is told, not only the first's."""
    if not any(_aims(a) for a in actions):
        return tuple(actions), ()
    if not _SOLVER:
        raise GestError(Diagnostic("error", "this program compiles places without the "
                                   "robot model: import inmoov_dsl.model first"))
    memo: dict[tuple, dict[int, int] | tuple[Diagnostic, ...]] = {}
    errors: list[Diagnostic] = []
    out = _walk(actions, list(start), profile, sources, memo, errors)
    hands = [aim for aim, _ in memo if aim.what != "look"]
    said = _SOLVER[0][1]() if hands else None
    notes: tuple[Diagnostic, ...] = ()
    if said is not None and strict:
        errors.insert(0, sources.error(said, hands[0].pos))
    elif said is not None:
        notes = (sources.warning(said, hands[0].pos),)
    if errors:
        raise GestError(tuple(dict.fromkeys(errors)))
    return out, notes


def _aims(action: Action) -> bool:
    return bool(action.aims) or any(_aims(a) for b in action.branches for a in b)


def _walk(actions: Sequence[Action], pose: list[int], profile: Profile, sources: SourceMap,
          memo: dict, errors: list[Diagnostic]) -> tuple[Action, ...]:
    """Solve ``actions`` in order from ``pose``, which is left as the last one leaves it."""
    out = []
    for action in actions:
        if action.branches:
            start, after = list(pose), list(pose)
            branches = []
            for branch in action.branches:
                ahead = list(start)
                branches.append(_walk(branch, ahead, profile, sources, memo, errors))
                for i, (a, b) in enumerate(zip(start, ahead, strict=True)):
                    after[i] = b if a != b else after[i]
            pose[:] = after
            action = dataclasses.replace(action, branches=tuple(branches))
        if action.aims:
            action = _solved(action, pose, profile, sources, memo, errors)
        for i, value in action.targets:
            pose[i] = value
        out.append(action)
    return tuple(out)


def _solved(action: Action, pose: list[int], profile: Profile, sources: SourceMap,
            memo: dict, errors: list[Diagnostic]) -> Action:
    """``action`` with its aims' values among its targets (after the ones written)."""
    targets = dict(action.targets)
    solved = []
    for aim in action.aims:
        key = (aim, tuple(pose))
        if key not in memo and len(memo) >= MAX_SOLVES:
            errors.append(sources.error(
                f"this gesture asks for more than {MAX_SOLVES:,} places to be solved",
                aim.pos, "a place met again from the same pose is solved once: repeat "
                "the same moves, or write values"))
            continue
        if key not in memo:
            try:
                memo[key] = _SOLVER[0][0](profile, aim, tuple(pose), sources)
            except GestError as error:
                memo[key] = error.diagnostics
        found = memo[key]
        if isinstance(found, tuple):
            errors.extend(found)
            continue
        targets.update(found)
        solved.append((aim, tuple(found.items())))
    return dataclasses.replace(action, targets=tuple(targets.items()), aims=(),
                               solved=tuple(solved))


def solved(steps: Sequence[Action], pose: Sequence[int], profile: Profile,
           sources: SourceMap | None) -> tuple[list[Action], tuple[Diagnostic, ...]]:
    """``solve`` for the live front ends: a request's steps from the pose the hand is
    going to (``sources`` None: steps with no text)."""
    found, notes = solve(steps, pose, profile, sources or SourceMap())
    return list(found), notes
