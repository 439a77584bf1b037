"""When each step of a file plays (pure, over an Analysis): the planned start and
length of every step of the file's own gestures, a call of another gesture too (from
its first step's start to its last step's end), for inlay hints and hover."""

from __future__ import annotations

from dataclasses import dataclass

from ..compiling.plan import Plan, PlannedStep
from ..language.parse import blocks
from .analysis import Analysis
from .lines import compiler_rows, place, rows
from .text import code


@dataclass(frozen=True)
class StepTime:
    """One step of a gesture as planned: when it starts, how long it lasts (the first
    time it plays, and how many times it plays in its gesture)."""

    gesture: str
    line: int  #: 0-based
    column: int  #: 0-based, where the step starts
    end_column: int  #: 0-based, the end of the step's code (before a comment)
    start: float
    length: float
    asked: float | None
    stretched: bool
    times: int
    longest: float  #: s; the longest it lasts, of every time it plays


def step_times(found: Analysis) -> dict[int, StepTime]:
    """0-based protocol line -> the step that starts on it, for each step of the file's
    gestures (each gesture's own steps and calls, as its own plan times them)."""
    text = found.text
    ends = {first: end for first, end in blocks(list(compiler_rows(text)))}
    lines = rows(text)
    out: dict[int, StepTime] = {}
    for gesture, plan in found.plans.items():
        node = found.program.gestures[gesture] if found.program else None
        if node is None or node.name.pos.file != found.path:
            continue
        first = node.name.pos.line - 1
        mine = [s for s in plan.steps if _inside(s, found.path, first, ends.get(first))]
        for step in mine:
            line, column = place(text, step.pos.line, step.pos.column)
            if line in out and out[line].gesture == gesture:
                out[line] = _again(out[line], step)
                continue
            end = len(code(lines[line]).rstrip()) if line < len(lines) else 0
            out[line] = StepTime(gesture, line, column, end, step.start,
                                 step.end - step.start, step.asked, step.stretched, 1,
                                 step.end - step.start)
        for call in _calls(plan, gesture, text):
            end = len(code(lines[call.line]).rstrip()) if call.line < len(lines) else 0
            seen = out.get(call.line)
            out[call.line] = _again(seen, call) if seen and seen.gesture == gesture else \
                StepTime(gesture, call.line, call.column, end, call.start, call.length,
                         None, False, 1, call.length)
    return out


def _inside(step: PlannedStep, path: str, first: int, end: int | None) -> bool:
    return (step.pos is not None and step.pos.file == path and end is not None
            and first <= step.pos.line - 1 < end)


def _again(seen: StepTime, step: PlannedStep | StepTime) -> StepTime:
    length = step.end - step.start if isinstance(step, PlannedStep) else step.length
    return StepTime(seen.gesture, seen.line, seen.column, seen.end_column, seen.start,
                    seen.length, seen.asked, seen.stretched or step.stretched,
                    seen.times + 1, max(seen.longest, length))


def _calls(plan: Plan, gesture: str, text: str) -> list[StepTime]:
    """Each play of a call of another gesture in ``plan`` (the resolver marks the
    steps each call plays, ``PlannedStep.call``): from its first step's start to its
    last's end (``line`` and ``column`` where the call is written in ``text``, the
    protocol's)."""
    plays: list[list[PlannedStep]] = []
    for step in plan.steps:
        if step.call is not None and (step.opens or not plays or plays[-1][0].call
                                      != step.call):
            plays.append([step])
        elif step.call is not None:
            plays[-1].append(step)
    return [StepTime(gesture, *place(text, play[0].call.line, play[0].call.column), 0,
                     play[0].start, play[-1].end - play[0].start, None, False, 1,
                     play[-1].end - play[0].start) for play in plays]


def label(step: StepTime) -> str:
    """``# 0.60 s`` and more: when the step starts, how long it lasts, how many times
    it plays, and what it asked for when it was stretched."""
    said = f"# at {step.start:.2f} s, {step.length:.2f} s"
    if step.times > 1:
        said += f", {step.times} times"
    if step.stretched and step.asked is not None:
        said += f" (stretched: asked {step.asked:.2f} s)"
    return said
