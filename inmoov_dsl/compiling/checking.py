"""Every error and warning of a program (pure): each gesture compiled, an error in one
not hiding another's, each diagnostic once. ``gestc check`` and the language server
tell the same."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from ..errors import Diagnostic, Errors, GestError
from ..hardware import Profile
from ..language.program import Program
from .compiled import Compiled
from .compiler import compile_program
from .plan import Plan
from .resolve import resolver
from .robot import profile_for
from .stretch import without_count
from .valuehint import fitted

Told = set[tuple[str, object, str]]  #: (severity, place, message) already told


def untold(found: list[Diagnostic] | tuple[Diagnostic, ...], told: Told) -> list[Diagnostic]:
    """The diagnostics whose place and message are not in ``told`` (which gets them): a
    place that two gestures play, or one plays three times, is told once."""
    out = []
    for d in found:
        key = (d.severity, d.pos, without_count(d.message))
        if key not in told:
            told.add(key)
            out.append(d)
    return out


@dataclass(frozen=True)
class Checked:
    """One gesture compiled: its errors, its warnings, its plan (None: it has errors)."""

    errors: tuple[Diagnostic, ...]
    warnings: tuple[Diagnostic, ...]
    plan: Plan | None


def check_gesture(program: Program, gesture: str, profile: str | Profile | None = None,
                  strict: bool = False,
                  also: Callable[[Program, Compiled, Plan], None] | None = None) -> Checked:
    """Compile ``gesture``: what it tells (``also``: a further check of the compiled
    gesture, whose GestError is an error too). One whose text has errors the parser told
    (``Program.unplayable``) is only resolved: its names are checked, it has no plan."""
    gathered = Errors()
    compiled = plan = None
    with gathered:
        if gesture in program.unplayable():
            resolver(program, profile_for(program, profile)).gesture(gesture)
            return Checked(tuple(gathered.found), (), None)
        compiled, plan = compile_program(program, gesture, profile, None, strict)
        if also is not None:
            also(program, compiled, plan)
    return Checked(tuple(gathered.found), compiled.warnings if compiled else (),
                   None if gathered.found else plan)


def tell(program: Program, each: list[Checked], told: Told | None = None,
         profile: Profile | None = None) -> tuple[list[Diagnostic], list[Diagnostic]]:
    """(errors, warnings) of ``program``'s file: its syntax errors (a value's hint
    fitted to its servo on ``profile``), then those of the gestures checked (``each``),
    each told once (``told``: what was told already, across files)."""
    told = set() if told is None else told
    syntax = program.syntax if profile is None else fitted(program.syntax, profile, program)
    errors: list[Diagnostic] = untold(syntax, told)
    warnings: list[Diagnostic] = []
    for checked in each:
        warnings += untold(checked.warnings, told)
        errors += untold(checked.errors, told)
    if program.syntax:  # among the others, in the file's order
        errors.sort(key=lambda d: (d.pos is None or d.pos.file != program.root,
                                   (d.pos.line, d.pos.column) if d.pos else (0, 0)))
    return errors, warnings


def check_program(program: Program, profile: str | Profile | None = None,
                  strict: bool = False, told: Told | None = None,
                  also: Callable[[Program, Compiled, Plan], None] | None = None
                  ) -> tuple[list[Diagnostic], list[Diagnostic]]:
    """(errors, warnings) of every gesture of ``program``'s own file, each told once
    (``told``: what was told already, across files; ``also``: a further check of each
    compiled gesture, whose GestError is an error too)."""
    each = [check_gesture(program, g, profile, strict, also) for g in checkable(program)]
    try:
        robot = profile_for(program, profile) if program.syntax else None
    except GestError:  # told by each gesture's check
        robot = None
    return tell(program, each, told, robot)


def checkable(program: Program) -> list[str]:
    """The gestures of the file that can be checked: all of them, but those that use a
    name whose definition does not parse (none when a robot or ``use`` line does not):
    their errors are that syntax error's until it is put right."""
    broken = program.broken
    if "*" in broken:
        return []
    tainted = program.users(set(broken)) if broken else set()
    return [g for g in program.own if g not in tainted]
