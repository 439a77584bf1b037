"""When each step of a file plays (pure, over an Analysis): the planned start and
length of every step of the file's own gestures, a call of another gesture too (from
its first step's start to its last step's end), for inlay hints and hover."""

from __future__ import annotations

from dataclasses import dataclass

from ..compiling.plan import Plan, PlannedStep
from ..language import syntax as ast
from ..language.parse import blocks
from ..language.program import Program
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
        for call in _calls(found.program, node.steps, plan, gesture, text):
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


def _calls(program: Program, steps: tuple[ast.Step, ...], plan: Plan, gesture: str,
           text: str) -> list[StepTime]:
    """Each time a step of ``steps`` (a gesture's, in order) calls another gesture: from
    its first planned step's start to its last's end (``line`` and ``column`` where the
    call is written in ``text``, the protocol's). The plan has one step per step of the
    expansion, a call's as many as its gesture expands to; none when the count does not
    come out (not a plan of these steps)."""
    found: list[StepTime] = []
    sizes: dict[str, int] = {}

    def walk(steps: tuple[ast.Step, ...], k: int) -> int:
        for step in steps:
            if isinstance(step, ast.Repeat):
                for _ in range(step.count):
                    k = walk(step.body, k)
                continue
            called = callee(program, step)
            n = 1 if called is None else expanded_size(program, called, sizes)
            if called is not None and n and k + n <= len(plan.steps):
                first, last = plan.steps[k], plan.steps[k + n - 1]
                found.append(StepTime(gesture, *place(text, step.pos.line, step.pos.column),
                                      0, first.start, last.end - first.start, None, False,
                                      1, last.end - first.start))
            k += n
        return k

    if not any(callee(program, s) for s in _flat(steps)):
        return []
    return found if walk(steps, 0) == len(plan.steps) else []


def _flat(steps: tuple[ast.Step, ...]) -> list[ast.Step]:
    """``steps`` and the steps of their repeats, each once."""
    return [inner for s in steps for inner in
            (_flat(s.body) if isinstance(s, ast.Repeat) else [s])]


def callee(program: Program, step: ast.Step) -> str | None:
    """The gesture ``step`` calls, if it is a call: a gesture's name alone."""
    if not isinstance(step, ast.Move) or len(step.targets) != 1:
        return None
    target = step.targets[0]
    name = target.name.text
    return name if not target.valued and name in program.gestures else None


def expanded_size(program: Program, gesture: str, sizes: dict[str, int]) -> int:
    """How many steps ``gesture`` expands to (its calls and repeats), each gesture
    counted once (``sizes``); 0 in a cycle (which does not plan)."""
    if gesture not in sizes:
        sizes[gesture] = 0
        sizes[gesture] = _count(program, program.gestures[gesture].steps, sizes)
    return sizes[gesture]


def _count(program: Program, steps: tuple[ast.Step, ...], sizes: dict[str, int]) -> int:
    total = 0
    for step in steps:
        if isinstance(step, ast.Repeat):
            total += step.count * _count(program, step.body, sizes)
        elif (called := callee(program, step)) is not None:
            total += expanded_size(program, called, sizes)
        else:
            total += 1
    return total


def label(step: StepTime) -> str:
    """``# 0.60 s`` and more: when the step starts, how long it lasts, how many times
    it plays, and what it asked for when it was stretched."""
    said = f"# at {step.start:.2f} s, {step.length:.2f} s"
    if step.times > 1:
        said += f", {step.times} times"
    if step.stretched and step.asked is not None:
        said += f" (stretched: asked {step.asked:.2f} s)"
    return said
