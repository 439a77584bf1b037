"""Every error and warning of a program (pure): each gesture compiled, an error in one
not hiding another's, each diagnostic once. ``gestc check`` and the language server
tell the same."""

from __future__ import annotations

from collections.abc import Callable

from ..errors import Diagnostic, Errors
from ..language.program import Program
from ..profiles.data import Profile
from .compiled import Compiled
from .compiler import compile_program
from .plan import Plan
from .stretch import without_count

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


def check_program(program: Program, profile: str | Profile | None = None,
                  strict: bool = False, told: Told | None = None,
                  also: Callable[[Program, Compiled, Plan], None] | None = None
                  ) -> tuple[list[Diagnostic], list[Diagnostic]]:
    """(errors, warnings) of every gesture of ``program``'s own file, each told once
    (``told``: what was told already, across files; ``also``: a further check of each
    compiled gesture, whose GestError is an error too)."""
    told = set() if told is None else told
    errors: list[Diagnostic] = []
    warnings: list[Diagnostic] = []
    for gesture in program.own:
        gathered = Errors()
        with gathered:
            compiled, plan = compile_program(program, gesture, profile, None, strict)
            warnings += untold(compiled.warnings, told)
            if also is not None:
                also(program, compiled, plan)
        errors += untold(gathered.found, told)
    return errors, warnings
