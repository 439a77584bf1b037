"""The names of a program for one profile, and the targets of a step (stage 2, with
``resolve``): every name looked up in one table (``Targets.lookup``), each pose
expanded once, each target's error told (not only the first's)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import NoReturn

from ..errors import Errors, GestError, Pos
from ..hardware import Profile
from ..language import syntax as ast
from ..language.program import Program
from ..profiles.profile import profiles_with
from . import reaching
from .names import ANYTHING, Entity, Gesture, Group, NameTable, Place, Pose, Servo
from .speech import Speech

MAX_NESTING = 100  #: the deepest chain of calls and repeats, or of poses within poses


class Targets:
    """The names of a Program for one profile, and the targets of a step."""

    def __init__(self, program: Program, profile: Profile):
        self.program = program
        self.profile = profile
        self.src = program.sources
        self.names = NameTable(program, profile, profiles_with)  # the one place it is made
        # what is expanded once and kept: each pose's targets and nesting height, each
        # gesture's nesting height, each move's targets (by the node's id; the program
        # keeps the nodes), and the gestures counted against MAX_TOTAL_STEPS
        self._poses: dict[str, tuple[dict[int, int], int]] = {}
        self._heights: dict[str, int] = {}
        self._moves: dict[int, tuple[tuple[tuple[int, int], ...], tuple]] = {}
        self._speech: dict[int, Speech] = {}
        self._counted: set[str] = set()
        self._total = 0
        # while one gesture expands: (callee, where) -> where its Actions are in the
        # output, so a gesture called again from the same place is copied, not walked
        self._spans: dict[tuple[str, str], tuple[int, int]] = {}

    def fail(self, message: str, pos: Pos | None, hint: str | None = None) -> NoReturn:
        """Raise the GestError ``message`` at ``pos``, with the line it points into."""
        raise GestError(self.src.error(message, pos, hint))

    def lookup(self, name: ast.Name, what: str = ANYTHING) -> Entity:
        """What ``name`` is; an unknown name fails, as an unknown ``what``, with a hint:
        the profile that has it, or the closest known name."""
        found = self.names.get(name.text)
        if found is None:
            self.fail(f"unknown {what} '{name.text}'", name.pos, self.names.hint(name.text))
        return found

    # -- targets ----------------------------------------------------------------
    def targets(self, targets: Sequence[ast.Target], chain: tuple[str, ...] = ()
                ) -> dict[int, int]:
        """Servo index -> value, in order of first mention; later mentions win
        (``chain``: the poses being expanded, outermost first)."""
        out: dict[int, int] = {}
        direct: set[str] = set()
        errors = Errors()
        for t in targets:
            with errors:  # each target's error told, not only the first's
                match self.lookup(t.name, "servo or group" if t.valued else ANYTHING):
                    case Pose():
                        out.update(self._pose(t, chain))
                    case Gesture():
                        self.fail(f"'{t.name.text}' is a gesture: call it on a line of its "
                                  f"own", t.name.pos, "a step can mix servos, groups and "
                                  "poses, not gestures")
                    case Servo() | Group() as found:
                        self._set(t, found, direct, out)
                    case Place():
                        self.fail(f"'{t.name.text}' is a place: a hand goes to it, or the "
                                  f"gaze", t.name.pos, f"right hand to {t.name.text}, or "
                                  f"look at {t.name.text}")
        errors.raise_any()
        return out

    def _pose(self, t: ast.Target, chain: tuple[str, ...]) -> dict[int, int]:
        """The targets of the pose ``t`` names, expanded once (with how deep poses nest
        in it): poses built from poses cost the size of their text, not 2^depth."""
        name = t.name.text
        if t.valued:
            self.fail(f"'{name}' is a pose; it takes no value", t.value_pos,
                      f"write just '{name}'")
        if name in chain:
            cycle = " -> ".join([*chain[chain.index(name):], name])
            self.fail(f"pose '{name}' refers to itself: {cycle}", t.name.pos)
        if name not in self._poses:
            if len(chain) >= MAX_NESTING:
                self.fail(f"poses are nested more than {MAX_NESTING} deep", t.name.pos)
            node = self.program.poses[name]
            inner = self.targets(node.targets, (*chain, name))
            below = [self._poses[x.name.text][1] for x in node.targets if x.name.text in
                     self._poses]  # the poses among its targets, all expanded now
            self._poses[name] = (inner, max(below, default=0) + 1)
        inner, height = self._poses[name]
        if len(chain) + height > MAX_NESTING:
            self.fail(f"poses are nested more than {MAX_NESTING} deep", t.name.pos)
        return inner

    def _set(self, t: ast.Target, found: Servo | Group, direct: set[str],
             out: dict[int, int]) -> None:
        """Set the servo or the group's servos ``t`` names to its value, in ``out``."""
        name = t.name.text
        kind, members = ("servo", (found.name,)) if isinstance(found, Servo) \
            else ("group", found.members)
        if not t.valued:
            self.fail(f"{kind} '{name}' needs a value", t.name.pos, f"for example '{name} 90'")
        if name in direct:
            self.fail(f"'{name}' is set twice in this step", t.name.pos)
        direct.add(name)
        if t.value is None:  # refused by the parser, which told why: the step is not played
            return
        for member in members:
            index = self.profile.index(member)
            servo = self.profile.servos[index]
            if not servo.lo <= t.value <= servo.hi:
                self.fail(f"value {t.value} is outside the range of '{member}' "
                          f"({servo.lo}..{servo.hi})", t.value_pos)
            out[index] = t.value


class Aims(Targets):
    """The places of a step's items, for one profile (``right hand to cup``)."""

    def aims(self, step: ast.Move) -> tuple[reaching.Aim, ...]:
        """Each place item of ``step`` as an Aim, with the servos it turns; a servo that
        two items turn, or that the step also gives a value, is an error at the second
        (every one told)."""
        found: list[reaching.Aim] = []
        turned: dict[int, ast.Reach] = {}
        errors = Errors()
        for r in step.reaches:
            with errors:
                aim = self._aim(r)
                for i in aim.servos:
                    if i in turned:
                        self.fail(f"'{self.profile.servos[i].name}' is turned by "
                                  f"'{aim.label}' and by an item before it in this step",
                                  r.pos, "one place for each hand, and one for the gaze")
                    turned[i] = r
                found.append(aim)
        for t in step.targets:
            with errors:
                if t.value is None and not self._is_pose(t):
                    continue
                for i in self.targets((t,)):
                    if i in turned:
                        self.fail(f"'{self.profile.servos[i].name}' is solved by "
                                  f"'{self._label(turned[i])}' in this step",
                                  t.value_pos or t.name.pos,
                                  "leave its value out, or write the arm's values "
                                  "instead of the place")
        errors.raise_any()
        return tuple(a for a in found if a.xyz is not None)

    def _is_pose(self, t: ast.Target) -> bool:
        return isinstance(self.names.get(t.name.text), Pose)

    def _label(self, r: ast.Reach) -> str:
        where = r.to.name.text if r.to.name else \
            f"({', '.join(r.to.numbers)}) {r.to.unit}".rstrip()
        return f"look at {where}" if r.what == "look" else f"{r.what} hand to {where}"

    def _aim(self, r: ast.Reach) -> reaching.Aim:
        """One place item as an Aim: its place looked up, the servos it turns found."""
        servos, missing = reaching.servos_for(self.profile, r.what)
        if missing:
            part = "head" if r.what == "look" else f"{r.what} arm"
            self.fail(f"profile '{self.profile.name}' has no {part} to turn: "
                      f"'{self._label(r)}' needs servos for joints {', '.join(missing)}",
                      r.pos, "a place needs a robot with that arm or head (robot inmoov); "
                      "a hand alone takes its servos' values")
        xyz, name = r.to.xyz, ""
        if r.to.name is not None:
            found = self.lookup(r.to.name, "place")
            if not isinstance(found, Place):
                self.fail(f"'{r.to.name.text}' is not a place", r.to.name.pos,
                          f"define it: place {r.to.name.text} (350, -200, 300) mm")
            xyz, name = found.xyz, found.name
        return reaching.Aim(r.what, xyz, servos, r.pos, name)  # type: ignore[arg-type]
