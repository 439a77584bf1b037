"""When each step of a file plays (pure, over an Analysis): the planned start and
length of every step of the file's own gestures, for inlay hints and hover."""

from __future__ import annotations

from dataclasses import dataclass

from ..compiling.plan import PlannedStep
from ..language.parse import blocks
from .analysis import Analysis
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
    """0-based line -> the step that starts on it, for each step of the file's gestures
    (each gesture's own steps, as its own plan times them)."""
    lines = found.text.split("\n")
    ends = {first: end for first, end in blocks(lines)}
    out: dict[int, StepTime] = {}
    for gesture, plan in found.plans.items():
        node = found.program.gestures[gesture] if found.program else None
        if node is None or node.name.pos.file != found.path:
            continue
        first = node.name.pos.line - 1
        mine = [s for s in plan.steps if _inside(s, found.path, first, ends.get(first))]
        for step in mine:
            line = step.pos.line - 1
            if line in out and out[line].gesture == gesture:
                out[line] = _again(out[line], step)
                continue
            end = len(code(lines[line]).rstrip()) if line < len(lines) else 0
            out[line] = StepTime(gesture, line, step.pos.column - 1, end, step.start,
                                 step.end - step.start, step.asked, step.stretched, 1,
                                 step.end - step.start)
    return out


def _inside(step: PlannedStep, path: str, first: int, end: int | None) -> bool:
    return (step.pos is not None and step.pos.file == path and end is not None
            and first <= step.pos.line - 1 < end)


def _again(seen: StepTime, step: PlannedStep) -> StepTime:
    return StepTime(seen.gesture, seen.line, seen.column, seen.end_column, seen.start,
                    seen.length, seen.asked, seen.stretched or step.stretched,
                    seen.times + 1, max(seen.longest, step.end - step.start))


def label(step: StepTime) -> str:
    """``# 0.60 s`` and more: when the step starts, how long it lasts, how many times
    it plays, and what it asked for when it was stretched."""
    said = f"# at {step.start:.2f} s, {step.length:.2f} s"
    if step.times > 1:
        said += f", {step.times} times"
    if step.stretched and step.asked is not None:
        said += f" (stretched: asked {step.asked:.2f} s)"
    return said
