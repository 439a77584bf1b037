"""What the tools do with a motion that drives the robot into itself: the compiler
warns of it (``check_plan``, given to the compiler by the commands:
``compiler.plan_checks``); the players refuse it before its first byte (``Guard``),
unless told that the robot's parts are padded (``--allow-contact``).

Every contact is told the one way: when it begins, which part enters which and by how
much, the values of the servos moving then, at the step that moves them. Without
python-fcl nothing can be checked: a robot whose parts can meet is told so once, with
how to get it; a hand alone has nothing to check (docs/collisions.md).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..compiling.actions import Action
from ..compiling.compiled import Compiled
from ..compiling.metrics import held_at, values_sent
from ..compiling.plan import Plan, PlannedStep, Planner
from ..errors import Diagnostic, GestError, Pos, SourceMap
from ..hardware import Profile
from ..protocol import SERVO_FRAME
from .collide import (
    Checker,
    Contact,
    Step,
    Touch,
    checker_for,
    contacts_along,
    first_contacts,
    would_check,
)
from .shapes import INSTALL, need_fcl

MODEL = "gestc urdf shows the model"
ALLOW = "--allow-contact plays it anyway, for a robot whose parts are padded"


def moving_step(plan: Plan, t: float) -> PlannedStep | None:
    """The step that was moving at ``t`` (the last one begun by then that moves a
    servo), or None."""
    begun = [s for s in plan.steps if s.start <= t + 1e-9 and s.servos]
    return begun[-1] if begun else None


def contact_message(checker: Checker, touch: Touch, servos: Sequence[int] = ()) -> str:
    """How every tool words a contact: ``at 1.24 s the right forearm enters the chest
    by 12 mm (r_bicep 150, ...)``, or when it goes deeper later ``at 1.24 s the right
    forearm enters the chest, 24 mm deep at 1.60 s (...)``: when it began (the servos'
    values then), and its deepest."""
    profile, contact, values = checker.profile, touch.contact, touch.values
    named = ", ".join(f"{profile.servos[i].name} {values[i]:.0f}" for i in servos)
    a, b = checker.part(contact.a), checker.part(contact.b)
    later = touch.deepest - touch.at >= SERVO_FRAME / 2
    if contact.depth_mm:
        how = (f"enters {a}, {contact.depth_mm:.0f} mm deep at {touch.deepest:.2f} s"
               if later else f"enters {a} by {contact.depth_mm:.0f} mm")
    else:
        how = (f"comes near {a}, within {contact.distance_mm:.0f} mm at "
               f"{touch.deepest:.2f} s" if later
               else f"comes within {contact.distance_mm:.0f} mm of {a}")
    return f"at {touch.at:.2f} s {b} {how}" + (f" ({named})" if named else "")


def _names(profile: Profile, servos: Sequence[int]) -> str:
    return ", ".join(profile.servos[i].name for i in servos) or "the servos"


def fix_hint(profile: Profile, servos: Sequence[int]) -> str:
    """What to change in the gesture."""
    return (f"move {_names(profile, servos)} less far, or in another order, so the parts "
            f"stay apart ({MODEL})")


def told(plan: Plan, sources: SourceMap | None, checker: Checker, error: bool,
         also: str = "", step: Step | None = None) -> list[Diagnostic]:
    """Each checked pair's first contact in ``plan``, at the step moving when it began
    (errors or warnings; ``also``: more to the hint; ``step``: ``contacts_along``'s)."""
    sources = sources or SourceMap()
    make = sources.error if error else sources.warning
    out = []
    for touch in first_contacts(checker, plan, step):
        moving = moving_step(plan, touch.at)
        servos = moving.servos if moving else ()
        out.append(make(contact_message(checker, touch, servos),
                        moving.pos if moving else None,
                        fix_hint(plan.profile, servos) + (f"; {also}" if also else "")))
    return out


def marks(plan: Plan) -> list[tuple[float, str]] | None:
    """(time it began, what) of each contact in ``plan``, for a drawing or a page; None
    when they cannot be looked for (no python-fcl, or a robot with nothing to check)."""
    if (checker := checker_for(plan.profile)) is None:  # None without python-fcl too
        return None
    return [(touch.at, contact_message(checker, touch))
            for touch in first_contacts(checker, plan)]


def unchecked(profile: Profile) -> Diagnostic | None:
    """The warning that the profile's parts are not checked (python-fcl missing), or
    None: they are, or there is nothing to check."""
    try:
        need_fcl()
    except GestError:
        if would_check(profile):
            return Diagnostic("warning", "the robot's parts are not checked against each "
                              "other: python-fcl is not installed", hint=INSTALL)
    return None


def check_plan(plan: Plan, sources: SourceMap, strict: bool, step: Step | None = None
               ) -> tuple[Diagnostic, ...]:
    """The compiler's check (``compiler.PlanCheck``): each contact a warning (with
    ``strict`` an error, raised). Without python-fcl, the warning that nothing was
    checked (with ``strict``, an error: ``need_fcl``'s). ``step``: called now and then
    (what it raises stops the check: an editor's newer text)."""
    if (missing := unchecked(plan.profile)) is not None:
        if strict:
            need_fcl()
        return (missing,)
    checker = checker_for(plan.profile)
    found = told(plan, sources, checker, strict, step=step) if checker else []
    if strict and found:
        raise GestError(found)
    return tuple(found)


class Guard:
    """A player's check of what it is about to play: ``plan`` refuses a motion with a
    contact (a GestError, before any byte is sent), or with ``allow_contact`` gives its
    contacts as warnings. ``allow``: how the player's user plays it anyway (for the
    hint). Without python-fcl it refuses nothing, and says so once (``missing``)."""

    def __init__(self, profile: Profile, allow_contact: bool = False, allow: str = ALLOW):
        self.profile, self.allow_contact, self.allow = profile, allow_contact, allow
        self.missing = unchecked(profile)  #: the warning that nothing is checked, or None
        self.checker = checker_for(profile) if self.missing is None else None

    def plan(self, plan: Plan, sources: SourceMap | None = None,
             allow_contact: bool | None = None) -> tuple[Diagnostic, ...]:
        """``plan``'s contacts: refused (raised), or warnings when contact is allowed
        (``allow_contact``, else the guard's own)."""
        if self.checker is None:
            return ()
        allowed = self.allow_contact if allow_contact is None else allow_contact
        found = told(plan, sources, self.checker, not allowed, "" if allowed else self.allow)
        if found and not allowed:
            raise GestError(found)
        return tuple(found)

    def check(self, plan: Plan, sources: SourceMap, strict: bool) -> tuple[Diagnostic, ...]:
        """``plan`` as the compiler's check (``compiler.plan_checks``), for a player
        that compiles what it plays."""
        return self.plan(plan, sources)

    def pose(self, values: Sequence[int], moved: Sequence[int] = ()) -> tuple[Diagnostic, ...]:
        """A pose the hand is about to take (profile order; ``moved``: the servos that
        changed for it): refused, or warnings when contact is allowed."""
        if self.checker is None:
            return ()
        row = np.asarray(values, dtype=float)
        deepest: dict[tuple[str, str], Contact] = {}  # the parts as messages name them
        for c in self.checker.contacts_of(row):  # deepest first
            deepest.setdefault((self.checker.part(c.a), self.checker.part(c.b)), c)
        found = [Diagnostic("warning" if self.allow_contact else "error",
                            contact_message(self.checker, Touch(0.0, c, row, 0.0),
                                            moved).removeprefix("at 0.00 s "),
                            hint=f"turn {_names(self.profile, moved)} the other way ({MODEL})"
                            + ("" if self.allow_contact else f"; {self.allow}"))
                 for c in deepest.values()]
        if found and not self.allow_contact:
            raise GestError(found)
        return tuple(found)

    def steps(self, steps: Sequence[Action], pose: Sequence[int],
              sources: SourceMap | None = None, allow_contact: bool | None = None
              ) -> tuple[Diagnostic, ...]:
        """``plan`` of ``steps`` planned from ``pose`` (profile order), as they will play
        from a hand standing there."""
        if self.checker is None or not steps:
            return ()
        planned = Planner(self.profile, sources).plan(list(steps), pose)
        return self.plan(planned, sources, allow_contact)

    def compiled(self, compiled: Compiled) -> tuple[Diagnostic, ...]:
        """A compiled file's contacts, from the values its streams set (held between
        two), every servo frame: refused, or warnings when contact is allowed."""
        if self.checker is None:
            return ()
        times = np.arange(0.0, compiled.duration + SERVO_FRAME, SERVO_FRAME)
        sent = values_sent(self.profile, compiled.streams)
        values = held_at(compiled.start, sent, times).astype(float)
        found = [Diagnostic("warning" if self.allow_contact else "error",
                            contact_message(self.checker, touch), _at(compiled, touch.at),
                            f"compile it again from its .gest file, changed ({MODEL})"
                            + ("" if self.allow_contact else f"; {self.allow}"))
                 for touch in contacts_along(self.checker, times, values)]
        if found and not self.allow_contact:
            raise GestError(found)
        return tuple(found)


def _at(compiled: Compiled, t: float) -> Pos | None:
    """The source line of the step of ``compiled`` playing at ``t``."""
    begun = [s for s in compiled.steps if s.start <= t + 1e-9 and s.file and s.line]
    return Pos(begun[-1].file, begun[-1].line, 1) if begun else None

