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
from .names import ANYTHING, Entity, Gesture, Group, NameTable, Pose, Servo
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
        self._moves: dict[int, tuple[tuple[int, int], ...]] = {}
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
