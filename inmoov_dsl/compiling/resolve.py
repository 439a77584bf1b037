"""Resolve names (stage 2): poses, groups, calls and repeats, for one profile.

A gesture of a Program (see ``program``) becomes a flat tuple of Actions over the
profile's servos. Every name is looked up in one table (``Resolver.lookup``); a
gesture is expanded in one pass, within a step budget.
"""

from __future__ import annotations

import contextlib
import dataclasses
from collections.abc import Sequence

from ..errors import Errors
from ..hardware import Profile
from ..language import syntax as ast
from ..language.program import Program
from . import robot, saying, sides
from .actions import Action, Frame
from .names import ANYTHING, Gesture, call_chain
from .targets import MAX_NESTING, Aims

MAX_STEPS = 100_000  #: the most steps one gesture may expand to
#: the most steps all the gestures of one program may expand to for one profile, each
#: gesture counted once however often it is compiled (``gestc check`` compiles them all)
MAX_TOTAL_STEPS = 1_000_000


class Resolver(Aims):
    """Turns a gesture of a Program into Actions for one profile."""

    def gesture(self, name: str, side: str | None = None, label: str | None = None
                ) -> tuple[Action, ...]:
        """The steps of gesture ``name``, with calls and repeats expanded: at most
        MAX_STEPS of them, and MAX_TOTAL_STEPS for all the gestures of the program;
        played on ``side`` ("left" or "right", ``sides.py``) when given (``label``: what
        errors call the gesture, when not its name)."""
        node = self.program.gestures[name]
        robot.check(self.program, self.profile, name)
        out: list[Action] = []
        self._spans = {}
        self._heights[name] = self._expand(node.steps, Frame((name,), name), out)
        if side is not None:
            self._to_side(out, 0, side, label or name, None)
        if name not in self._counted:
            if self._total + len(out) > MAX_TOTAL_STEPS:
                self.fail(f"with '{name}', the gestures of this program expand to more "
                          f"than {MAX_TOTAL_STEPS:,} steps in all", node.name.pos,
                          "split the file: each gesture's calls and repeats are expanded")
            self._counted.add(name)
            self._total += len(out)
        return tuple(out)

    def _expand(self, steps: Sequence[ast.Step], at: Frame, out: list[Action]) -> int:
        """Append the Actions of ``steps`` to ``out``; return how deep the calls and
        repeats among them nest. A gesture's own steps are each resolved, and every
        error among them told, not only the first."""
        height = 0
        errors = Errors()
        for step in steps:
            with errors if at.depth == 0 else contextlib.nullcontext():
                height = max(height, self._step(step, at, out))
            self._within_budget(len(out), at)
        errors.raise_any()
        return height

    def _step(self, step: ast.Step, at: Frame, out: list[Action]) -> int:
        """Append the Actions of one step to ``out``; return how deep its calls and
        repeats nest."""
        match step:
            case ast.Wait():
                out.append(Action((), hold=step.duration.seconds, pos=step.pos,
                                  where=at.where))
            case ast.Repeat():
                return self._repeat(step, at, out)
            case ast.Together():
                return self._together(step, at, out)
            case ast.Move() if (callee := self._callee(step)) is not None:
                return self._call(step, callee, at, out)
            case ast.Move():
                out.append(self._move(step, at.where))
            case ast.Say():
                out.append(self._say(step, at.where))
        return 0

    def _within_budget(self, steps: int, at: Frame) -> None:
        if steps > MAX_STEPS:
            node = self.program.gestures[at.chain[0]]
            self.fail(f"gesture '{node.name.text}' expands to more than {MAX_STEPS:,} steps",
                      node.name.pos, "lower a repeat count")

    def _nest(self, step: ast.Step, depth: int) -> None:
        if depth > MAX_NESTING:
            self.fail(f"calls and repeats are nested more than {MAX_NESTING} deep", step.pos)

    def _repeat(self, step: ast.Repeat, at: Frame, out: list[Action]) -> int:
        """Expand the body once and copy it; return its nesting height."""
        self._nest(step, at.depth + 1)
        start = len(out)
        below = self._expand(step.body, Frame(at.chain, at.where, at.depth + 1), out)
        self._within_budget(start + (len(out) - start) * step.count, at)
        out.extend(out[start:] * (step.count - 1))
        return below + 1

    def _call(self, step: ast.Move, callee: str, at: Frame, out: list[Action]) -> int:
        """Expand the gesture ``callee``; return its nesting height (which is kept, so a
        gesture reached again further down is too deep at the call)."""
        self._nest(step, at.depth + 1)
        if callee in at.chain:
            cycle = " -> ".join([*at.chain[at.chain.index(callee):], callee])
            self.fail(f"gesture '{callee}' calls itself: {cycle}", step.pos)
        robot.check(self.program, self.profile, callee, step.pos)
        if callee in self._heights:
            self._nest(step, at.depth + 1 + self._heights[callee])
        side = step.side.text if step.side else None
        shown = f"{side} {callee}" if side else callee
        inner = Frame((*at.chain, callee), call_chain(at.where, shown), at.depth + 1)
        span = self._spans.get((callee, inner.where))
        start = len(out)
        if span is not None:  # the same Actions again (a cycle would have failed before)
            self._within_budget(len(out) + span[1] - span[0], at)
            out.extend(out[span[0]:span[1]])
        else:
            self._heights[callee] = self._expand(self.program.gestures[callee].steps, inner,
                                                 out)
            if side:
                self._to_side(out, start, side, callee, step.side)
            self._spans[(callee, inner.where)] = (start, len(out))
        if len(at.chain) == 1:  # a call of the gesture resolved: its steps know where
            out[start:] = [dataclasses.replace(a, call=step.pos, opens=k == 0)
                           for k, a in enumerate(out[start:])]
        return self._heights[callee] + 1

    def _together(self, step: ast.Together, at: Frame, out: list[Action]) -> int:
        """``a & b``: each part expanded on its own, into one Action of their branches;
        a servo moved by two parts fails, naming both. Returns the nesting height."""
        branches: list[tuple[Action, ...]] = []
        owner: dict[int, ast.Move | ast.Say] = {}
        height = 0
        saved, self._spans = self._spans, {}  # the spans are places in one output list
        for part in step.parts:
            branch: list[Action] = []
            if isinstance(part, ast.Say):
                branch.append(self._say(part, at.where))
            elif (callee := self._callee(part)) is not None:
                height = max(height, self._call(part, callee, at, branch))
            else:
                branch.append(self._move(part, at.where))
            for i in sorted(set().union(*(a.servos() for a in branch))):
                if i in owner:
                    first = owner[i]
                    self.fail(f"'{self.profile.servos[i].name}' is moved by two parts of "
                              f"this step: '{saying.label(first)}' at column "
                              f"{first.pos.column} and '{saying.label(part)}'",
                              part.pos, "each part of 'a & b' moves servos of its own")
                owner[i] = part
            branches.append(tuple(branch))
            self._within_budget(len(out) + sum(map(len, branches)), at)
        self._spans = saved
        out.append(Action((), pos=step.pos, where=at.where, branches=tuple(branches)))
        return height

    def _to_side(self, out: list[Action], start: int, side: str, name: str,
                 at: ast.Name | None) -> None:
        """Move ``out[start:]`` (gesture ``name``'s steps) onto ``side`` (``at``: the
        word that asked for it, if one did)."""
        out[start:] = sides.to_side(out[start:], self.profile, side, name,
                                    lambda m, h: self.fail(m, at and at.pos, h))

    def _say(self, step: ast.Say, where: str) -> Action:
        """``say``: its sound and the mouth moving with it (each sound heard once)."""
        if id(step) not in self._speech:
            self._speech[id(step)] = saying.speech(step, self.program, self.profile)
        return Action((), pos=step.pos, where=where, speech=self._speech[id(step)])

    def _callee(self, move: ast.Move) -> str | None:
        """The gesture ``move`` calls, if it is a call: a gesture's name alone."""
        if len(move.targets) != 1 or move.reaches:
            return None
        target = move.targets[0]
        what = "servo or group" if target.valued else ANYTHING
        if not isinstance(self.lookup(target.name, what), Gesture):
            return None
        name = target.name.text
        if target.valued:
            self.fail(f"'{name}' is a gesture; it takes no value", target.value_pos)
        for timing in (move.over, move.stagger, move.through):
            if timing is not None:
                self.fail(f"a gesture call takes no timing: '{name}' sets its own",
                          getattr(timing, "pos", timing), "time the gesture's own steps")
        return name

    def _move(self, step: ast.Move, where: str) -> Action:
        """The Action of a move (its targets resolved once, however often it is played)."""
        key = id(step)
        if key not in self._moves:
            if step.side:
                self.fail(f"'{step.side.text}' goes before a gesture's name, alone on its "
                          f"step", step.side.pos, f"for example '{step.side.text} peace'")
            if step.through and step.stagger:
                self.fail("a step that flows 'through' its keyframe cannot 'stagger'",
                          step.through, "stagger the step before, or after, instead")
            self._moves[key] = (tuple(self.targets(step.targets).items()), self.aims(step))
        targets, aims = self._moves[key]
        return Action(targets, aims=aims, over=step.over.seconds if step.over else None,
                      stagger=step.stagger.seconds if step.stagger else 0.0, pos=step.pos,
                      over_pos=step.over.pos if step.over else None, where=where,
                      through=step.through is not None)


def resolver(program: Program, profile: Profile) -> Resolver:
    """The Resolver of ``program`` for ``profile``, made once and kept in the program:
    names are checked once and what is expanded stays expanded, so compiling every
    gesture of a file costs about the file's size, not its square."""
    found = program.resolvers.get(id(profile))
    if found is None or found.profile is not profile:  # it holds the profile: no id reuse
        found = program.resolvers[id(profile)] = Resolver(program, profile)
    return found
