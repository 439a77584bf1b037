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
from .timing import step_times

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


def fixes(found: Analysis, line: int) -> list[Fix]:
    """Every fix for the diagnostics of this file on ``line`` (0-based)."""
    out: list[Fix] = []
    for d in found.diagnostics:
        if d.pos is None or d.pos.file != found.path or d.pos.line - 1 != line:
            continue
        out += _fixes(found, d)
    return out


def _fixes(found: Analysis, d: Diagnostic) -> list[Fix]:
    line, column = d.pos.line - 1, d.pos.column - 1
    hint = d.hint or ""
    if meant := MEANT.search(hint):
        return [Fix(f"Change to '{meant[1]}'", line, column, column + d.pos.width,
                    meant[1], d)]
    if use := USE_LINE.search(hint):
        at = after_header(found.text)
        return [Fix(f"Add '{use[1]}'", at, 0, 0, use[1] + "\n", d)]
    if hint == STRETCH_HINT:
        step = step_times(found).get(line)
        if step is not None:
            needed = math.ceil(step.longest * 100 - 1e-6) / 100
            return [Fix(f"Ask for {needed:g} s, the time the limits need", line, column,
                        column + d.pos.width, f"{needed:g}s", d)]
    return []


def after_header(text: str) -> int:
    """The line after the file's robot and ``use`` lines (and the comments above and
    among them): where a new ``use`` line goes."""
    at = 0
    for k, row in enumerate(text.split("\n")):
        if ROBOT_OR_USE.match(row):
            at = k + 1
        elif row.strip() and not row.lstrip().startswith("#"):
            break
    return at
