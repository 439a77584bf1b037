"""The fixes an editor offers (pure, over an Analysis): each from the hint of a
diagnostic at the cursor. A misspelt name becomes the one meant, a library gesture gets
its ``use`` line, a stretched move asks for the time its servos' limits need."""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

from ..compiling.stretch import STRETCH_HINT
from ..errors import Diagnostic
from .analysis import Analysis
from .lines import place, rows
from .timing import StepTime, step_times

MEANT = re.compile(r"did you mean '([^']+)'\?")
USE_LINE = re.compile(r'add the line  (use "[^"]+")  to this file')
ROBOT_OR_USE = re.compile(r"\s*(robot|use)\b")


@dataclass(frozen=True)
class Fix:
    """A change to the text: replace ``line``:``column``..``end`` (0-based, on one
    line) with ``text``; ``title`` says it, ``diagnostic`` is what it answers."""

    title: str
    line: int
    column: int
    end: int
    text: str
    diagnostic: Diagnostic
    preferred: bool = True


def fixes(found: Analysis, first: int, last: int | None = None) -> list[Fix]:
    """Every fix for the diagnostics of this file on the lines ``first`` to ``last``
    (0-based, protocol lines; ``last`` None: ``first`` alone). It costs the
    diagnostics, not the range (a range may end anywhere)."""
    last = first if last is None else last
    out: list[Fix] = []
    times: dict[int, StepTime] | None = None
    for d in found.diagnostics:
        if d.pos is None or d.pos.file != found.path:
            continue
        line, column = place(found.text, d.pos.line, d.pos.column)
        if not first <= line <= last:
            continue
        if d.hint == STRETCH_HINT and times is None:
            times = step_times(found)
        out += _fixes(found, d, line, column, times or {})
    return out


def _fixes(found: Analysis, d: Diagnostic, line: int, column: int,
           times: dict[int, StepTime]) -> list[Fix]:
    hint = d.hint or ""
    if meant := MEANT.search(hint):
        return [Fix(f"Change to '{meant[1]}'", line, column, column + d.pos.width,
                    meant[1], d)]
    if use := USE_LINE.search(hint):
        at = after_header(found.text)
        return [Fix(f"Add '{use[1]}'", at, 0, 0, use[1] + "\n", d)]
    if hint == STRETCH_HINT:
        step = times.get(line)
        if step is not None:
            needed = math.ceil(step.longest * 100 - 1e-6) / 100
            return [Fix(f"Ask for {needed:g} s, the time the limits need", line, column,
                        column + d.pos.width, f"{needed:g}s", d)]
    return []


def after_header(text: str) -> int:
    """The line after the file's robot and ``use`` lines (and the comments above and
    among them): where a new ``use`` line goes."""
    at = 0
    for k, row in enumerate(rows(text)):
        if ROBOT_OR_USE.match(row):
            at = k + 1
        elif row.strip() and not row.lstrip().startswith("#"):
            break
    return at
