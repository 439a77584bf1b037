"""The parse tree's rules as the syntax tree's dataclasses (Lark's tree-less LALR mode
calls them as it parses). A value, a unit or a count that is wrong is a flaw: told at its
place while the parse goes on, with a placeholder, so one step's mistakes do not hide the
next ones'."""

from __future__ import annotations

import dataclasses
import math
from typing import Any

from lark import Token, Transformer, v_args

from ..errors import Pos
from ..protocol import MAX_VALUE
from . import syntax as ast
from .parse_errors import Span, SyntaxProblem, pos_span, shown, tok_span

MAX_REPEAT = 1000
MAX_DURATION = 600.0  #: s, the longest single move or wait
MAX_DEPTH = 100  #: repeats within repeats
UNITS = {"s": 1.0, "ms": 0.001}
LENGTHS = {"mm": 0.001, "m": 1.0}  #: a place's units, in metres
MAX_DISTANCE = 100.0  #: m: further than any robot reaches or looks, written by mistake


@v_args(inline=True)
class _ToAst(Transformer):
    """Parse-tree rules -> syntax dataclasses. ``file`` is set for each parse."""

    file = "<string>"
    depths: dict[int, int] = {}  #: id of a Repeat -> how many repeats deep it goes
    #: the problems of a step that leave its shape known (a value, a unit, a count): told
    #: all, each at its place, while the parse goes on with a placeholder
    flaws: list[SyntaxProblem] = []

    def _pos(self, tok: Token) -> Pos:
        return Pos(self.file, tok.line, tok.column, max(1, len(str(tok))))

    def start(self, *items):
        return module_of(self.file, items)

    def _name(self, tok: Token) -> ast.Name:
        return ast.Name(str(tok), self._pos(tok))

    def robot_stmt(self, name: Token):
        if name.type == "STRING":
            path = str(name)[1:-1]
            if not path.endswith(".toml"):
                raise SyntaxProblem(f"a robot is a profile's name or a .toml file, not "
                                    f"'{shown(path)}'", tok_span(name),
                                    'robot inmoov, or robot "my_hand.toml"')
            return ast.Robot(path, self._pos(name), is_file=True)
        return ast.Robot(str(name), self._pos(name))

    def use_stmt(self, path: Token):
        return ast.Use(path[1:-1], self._pos(path))

    def group_def(self, name: Token, *members: Token):
        return ast.GroupDef(self._name(name), tuple(self._name(m) for m in members))

    def pose_def(self, name: Token, *targets: ast.Target):
        return ast.PoseDef(self._name(name), targets)

    def place_def(self, name: Token, point: ast.Point):
        return ast.PlaceDef(self._name(name), point)

    def point(self, *parts: Token):
        """``(x, y, z) mm``: its numbers in metres; a missing or unknown unit, or a
        number too large, is a flaw (the place is then None)."""
        numbers, unit = parts[:3], parts[3] if len(parts) > 3 else None
        first, last = numbers[0], unit or numbers[2]
        pos = Pos(self.file, first.line, first.column - 1, 1)  # from the '('
        if last.line == first.line:
            end = last.column + len(str(last)) + (0 if unit else 1)  # past the ')'
            pos = dataclasses.replace(pos, width=end - pos.column)
        written = tuple(str(n) for n in numbers)
        problem = _point_problem(written, unit, tok_span(unit) if unit else pos_span(pos))
        if problem is not None:
            self.flaws.append(problem)
            return ast.Point(None, pos, None, written, str(unit or ""))
        scale = LENGTHS[str(unit)]
        xyz = tuple(float(n) * scale for n in written)
        return ast.Point(xyz, pos, None, written, str(unit))  # type: ignore[arg-type]

    def _place_of(self, spot: ast.Point | Token) -> ast.Point:
        if isinstance(spot, ast.Point):
            return spot
        name = self._name(spot)
        return ast.Point(None, name.pos, name)

    def reach(self, side: Token, spot):
        to = self._place_of(spot)
        return ast.Reach(str(side), to, self._through(side, to.pos))

    def look(self, keyword: Token, spot):
        to = self._place_of(spot)
        return ast.Reach("look", to, self._through(keyword, to.pos))

    def gesture_line(self, name: Token, step):
        return ast.GestureDef(self._name(name), (step,))

    def gesture_block(self, name: Token, *steps):
        return ast.GestureDef(self._name(name), steps)

    def repeat_block(self, count: Token, *steps):
        return self._repeat(count, steps)

    def repeat_line(self, count: Token, step):
        return self._repeat(count, (step,))

    def _repeat(self, count: Token, body: tuple) -> ast.Repeat:
        """A repeat; one inside more than MAX_DEPTH others is an error (what walks the
        tree, the formatter say, may recurse)."""
        depth = 1 + max((self.depths.get(id(s), 0) for s in body), default=0)
        if depth > MAX_DEPTH:
            raise SyntaxProblem(f"repeats are nested more than {MAX_DEPTH} deep",
                                tok_span(count))
        node = ast.Repeat(self._count(count), body, self._pos(count))
        self.depths[id(node)] = depth
        return node

    def _count(self, tok: Token) -> int:
        text = str(tok)
        digits = text.lstrip("+-")
        # a count with more digits than MAX_REPEAT is too large before int() sees it
        if not digits.isdigit() or len(digits.lstrip("0")) > len(str(MAX_REPEAT)) \
                or not 1 <= int(text) <= MAX_REPEAT:
            self.flaws.append(SyntaxProblem(f"repeat count must be a whole number from 1 "
                                            f"to {MAX_REPEAT}, got {shown(text)}",
                                            tok_span(tok)))
            return 1
        return int(text)

    def wait(self, duration: ast.Duration):
        return ast.Wait(duration, duration.pos, "wait")

    def hold(self, duration: ast.Duration):
        return ast.Wait(duration, duration.pos, "hold")

    def move(self, *parts):
        side = self._name(parts[0]) if isinstance(parts[0], Token) else None
        items = tuple(p for p in parts if isinstance(p, ast.Target | ast.Reach))
        targets = tuple(p for p in items if isinstance(p, ast.Target))
        reaches = tuple(p for p in items if isinstance(p, ast.Reach))
        timing: dict[str, Any] = {}  # over and stagger: a Duration; through: a Pos
        for kind, value, where in (p for p in parts if isinstance(p, tuple)):
            if kind in timing:  # the caret from the second keyword to its value's end
                self.flaws.append(SyntaxProblem(f"'{kind}' is given twice in this step",
                                                pos_span(where)))
            timing.setdefault(kind, value)
        first = side.pos if side else getattr(items[0], "name", items[0]).pos
        return ast.Move(targets, timing.get("over"), timing.get("stagger"), first,
                        timing.get("through"), side, reaches, items)

    def together(self, *parts: ast.Move | ast.Say):
        return ast.Together(parts, parts[0].pos)

    def say(self, keyword: Token, text: Token):
        return ast.Say(text[1:-1], self._pos(keyword), self._pos(text))

    def over(self, keyword: Token, duration: ast.Duration):  # (kind, value, where)
        return ("over", duration, self._through(keyword, duration.pos))

    def stagger(self, keyword: Token, duration: ast.Duration):
        return ("stagger", duration, self._through(keyword, duration.pos))

    def through(self, keyword: Token):
        return ("through", self._pos(keyword), self._pos(keyword))

    def _through(self, keyword: Token, last: Pos) -> Pos:
        """From ``keyword`` to the end of ``last`` (on its line)."""
        start = self._pos(keyword)
        if last.line != start.line:
            return start
        return dataclasses.replace(start, width=last.column + last.width - start.column)

    def target(self, name: Token, value: Token | None = None):
        if value is None:
            return ast.Target(self._name(name), None, None)
        problem = _value_problem(str(value), tok_span(value))
        if problem is not None:  # a value was written: the name is still looked up
            self.flaws.append(problem)
            return ast.Target(self._name(name), None, self._pos(value))
        return ast.Target(self._name(name), int(float(str(value))), self._pos(value))

    def duration(self, number: Token, unit: Token | None = None):
        text = str(number)
        span = (number.line, number.column, len(text) + len(str(unit or "")))
        pos = self._pos(number)
        pos = Pos(pos.file, pos.line, pos.column, span[2])
        problem = _duration_problem(number, unit, span)
        if problem is not None:  # its length unknown: the step's plan is too
            self.flaws.append(problem)
            return ast.Duration(math.nan, pos, text, str(unit or ""))
        return ast.Duration(float(text) * UNITS[str(unit)], pos, text, str(unit))


def _value_problem(text: str, span: Span) -> SyntaxProblem | None:
    """What is wrong with a servo's value as written, or None."""
    number = float(text)  # inf when it has hundreds of digits
    if not math.isfinite(number) or abs(number) > 1e9 or not 0 <= number <= MAX_VALUE:
        return SyntaxProblem(f"value {shown(text)} is outside 0..{MAX_VALUE}", span,
                             f"no servo takes more than 0..{MAX_VALUE}; its profile "
                             "may give it less")
    if number != int(number) or "." in text:
        lo = int(number // 1)
        return SyntaxProblem(f"values are whole degrees, got {shown(text)}", span,
                             f"use {lo} or {lo + 1}")
    return None


def _point_problem(numbers: tuple[str, ...], unit: Token | None, span: Span
                   ) -> SyntaxProblem | None:
    """What is wrong with a place as written, or None."""
    shown_place = f"({', '.join(shown(n) for n in numbers)})"
    if unit is None:
        return SyntaxProblem(f"the place {shown_place} needs a unit", span,
                             f"write {shown_place} mm or {shown_place} m")
    if str(unit) not in LENGTHS:
        return SyntaxProblem(f"unknown unit '{shown(str(unit))}' for a place", span,
                             f"use mm or m, as in {shown_place} mm")
    far = [n for n in numbers
           if not abs(float(n) * LENGTHS[str(unit)]) <= MAX_DISTANCE]  # inf and nan too
    if far:
        return SyntaxProblem(f"{shown(far[0])}{unit} is further than any robot reaches "
                             f"(at most {MAX_DISTANCE:g} m from its base)", span)
    return None


def _duration_problem(number: Token, unit: Token | None, span: Span
                      ) -> SyntaxProblem | None:
    """What is wrong with a duration as written (``span``: where it is), or None."""
    text = str(number)
    if unit is None:
        return SyntaxProblem(f"the duration {shown(text)} needs a unit", tok_span(number),
                             f"write {shown(text)}s or {shown(text)}ms")
    if str(unit) not in UNITS:
        return SyntaxProblem(f"unknown unit '{shown(str(unit))}'", tok_span(unit),
                             f"use s or ms, as in {shown(text)}s or {shown(text)}ms")
    seconds = float(text) * UNITS[str(unit)]  # inf when it has hundreds of digits
    if not seconds > 0:
        return SyntaxProblem(f"a duration must be greater than 0, got {shown(text)}{unit}",
                             span)
    if seconds > MAX_DURATION:
        return SyntaxProblem(f"duration {shown(text)}{unit} is too long (at most "
                             f"{MAX_DURATION:g} s per step)", span,
                             "split a long hold into several waits")
    return None


def module_of(file: str, items: tuple[ast.Item, ...]) -> ast.Module:
    """The file of ``items``; a SyntaxProblem unless its robot line, if any, is its
    first."""
    for item in items[1:]:
        if isinstance(item, ast.Robot):
            raise SyntaxProblem("a file names its robot once, on its first line",
                                pos_span(item.pos), "move the robot line to the top of "
                                "the file, above its gestures" if not isinstance(
                                    items[0], ast.Robot) else "keep one robot line")
    return ast.Module(file, tuple(items))


TO_AST = _ToAst()  #: the one builder: parse sets its file and clears its state, under its lock
