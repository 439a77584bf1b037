"""The live preview of an editor's text (pure): from the analysis of a text (analysis.py)
and the cursor, the ``View`` a preview page shows (``views.livepage``): the gesture the
cursor is in, its plan and timeline, its steps labelled with their code and the place
picking each puts the cursor, the steps under the cursor, the file's diagnostics.

A text whose gesture does not compile keeps the last view that did, marked stale, with
the new diagnostics: the caller hands back the previous view (``view_of(...,
previous=page.view)``). What a plan draws is made once per plan and kept while its
tracks stay (an edit elsewhere, a cursor that moves); the contacts are looked for aside
(``timeline.contacts``, by the page)."""

from __future__ import annotations

import dataclasses
import re
from collections.abc import Sequence

from ..compiling.plan import Plan
from ..language.program import Program
from ..language.syntax import KEYWORDS
from ..views.timeline import Span, View, motion
from .analysis import Analysis
from .text import NAME, code

GESTURE_LINE = re.compile(rf"({NAME})[ \t]*:")  #: a top-level line that starts a gesture
LABEL = 60  #: characters of a step's code on its label, at most


def view_of(found: Analysis, line: int | None = None, character: int = 0,
            previous: View | None = None, gesture: str | None = None) -> View:
    """The view of ``found`` with the cursor at 0-based ``line``, ``character``: the
    gesture ``gesture`` if given, else the one the cursor is in, else the previous
    view's, else the file's first. ``previous``: the view shown so far (kept, marked
    stale, when the gesture does not compile now; its timeline reused while the plan's
    tracks are the same). ``character`` is the editor's, kept for when a line holds more
    than one step; a line holds one now (``a & b`` is one step)."""
    lines = found.text.split("\n")
    own = tuple(found.program.own) if found.program is not None else gestures_in(lines)
    name = gesture or (gesture_at(lines, line) if line is not None else None)
    if name is None:  # the previous gesture while it is there (or the text is unread)
        kept = previous is not None and (previous.gesture in own or found.program is None)
        name = previous.gesture if kept else (own[0] if own else None)
    diagnostics = tuple(found.diagnostics)
    plan = found.plans.get(name) if name is not None else None
    same = previous is not None and previous.plan is not None and \
        (previous.path, previous.gesture) == (found.path, name)
    if plan is None:
        if same and any(d.severity == "error" for d in diagnostics):
            return dataclasses.replace(previous, diagnostics=diagnostics, stale=True,
                                       gestures=own,
                                       cursor=under(previous.spans, found.path, line))
        return View(found.path, name, found.profile, diagnostics=diagnostics, gestures=own)
    kept = same and previous.plan.tracks is plan.tracks
    spans = previous.spans if same and previous.plan is plan else \
        steps_of(found.program, name, plan, found.path)
    return View(found.path, name, plan.profile, plan,
                previous.motion if kept else motion(plan), spans,
                under(spans, found.path, line), diagnostics, False, own,
                previous.contacts if kept else None, found.program)


def gesture_at(lines: Sequence[str], line: int) -> str | None:
    """The gesture whose block holds 0-based ``line`` (read from the text alone, so a
    text that does not load has one too), or None."""
    for k in range(min(line, len(lines) - 1), -1, -1):
        row = lines[k]
        if row[:1] not in ("", " ", "\t", "#"):
            match = GESTURE_LINE.match(row)
            return match[1] if match and match[1] not in KEYWORDS else None
    return None


def gestures_in(lines: Sequence[str]) -> tuple[str, ...]:
    """The gestures a text defines, in its order, read from the text alone."""
    found = (GESTURE_LINE.match(row) for row in lines if row[:1] not in ("", " ", "\t", "#"))
    return tuple(dict.fromkeys(m[1] for m in found if m and m[1] not in KEYWORDS))


def under(spans: Sequence[Span], path: str, line: int | None) -> tuple[int, ...]:
    """The spans of the step under the cursor at 0-based ``line`` of file ``path``: the
    first time that line's step plays (every step a call on that line plays, the first
    time it plays)."""
    if line is None:
        return ()
    found: list[int] = []
    for k, span in enumerate(spans):
        if span.file == path and span.line == line:
            if found and found[-1] != k - 1:
                break
            found.append(k)
        elif found:
            break
    return tuple(found)


def steps_of(program: Program, gesture: str, plan: Plan, path: str) -> tuple[Span, ...]:
    """Each planned step as a span: its code as its label, and where picking it puts
    the cursor (its own line in the gesture, or the line of the gesture's step that
    calls the gesture it is written in)."""
    sites = [s.call or s.pos for s in plan.steps]  # a call's steps: where it is written
    cache: dict[str, list[str]] = {}
    spans = []
    for k, (step, site) in enumerate(zip(plan.steps, sites, strict=True), 1):
        pos = step.pos if site is None or _same_place(step.pos, site) else site
        spans.append(Span(k, _label(program, step.pos, cache), step.where, step.kind,
                          step.start, step.end, step.asked, step.stretched, step.servos,
                          pos.file if pos else None, pos.line - 1 if pos else None,
                          pos.column - 1 if pos else None))
    return tuple(spans)


def _same_place(a, b) -> bool:
    return a is not None and b is not None and (a.file, a.line) == (b.file, b.line)


def _label(program: Program, pos, cache: dict[str, list[str]]) -> str:
    """The step's code: its line, comment left out, cut to LABEL."""
    if pos is None:
        return ""
    if pos.file not in cache:
        cache[pos.file] = program.texts.get(pos.file, "").split("\n")
    lines = cache[pos.file]
    row = lines[pos.line - 1] if 0 < pos.line <= len(lines) else ""
    said = " ".join(row[:len(code(row).rstrip())].split())
    if row[:1] not in ("", " ", "\t") and (match := GESTURE_LINE.match(said)):
        said = said[match.end():].strip()  # a gesture on one line: its steps
    return said if len(said) <= LABEL else said[:LABEL - 1] + "…"
