"""Parse .gest text into a syntax tree (stage 1 of the compiler). The Lark LALR parser
is built once per process; syntax errors become GestErrors at their place."""

from __future__ import annotations

import functools
import hashlib
import math
import sys
import threading
from typing import Any

from lark import Lark, Token, Transformer, UnexpectedInput, v_args
from lark import __version__ as lark_version

from ..errors import Diagnostic, GestError, Pos
from ..protocol import MAX_VALUE
from ..resources import grammar_path, private_cache_dir, private_file
from . import syntax as ast
from .indent import GestIndenter
from .parse_errors import SyntaxProblem, lark_problem, pos_span, shown, tok_span

MAX_REPEAT = 1000
MAX_DURATION = 600.0  #: s, the longest single move or wait
MAX_SOURCE = 1_000_000  #: characters in one .gest file, checked before parsing
MAX_LINE = 10_000  #: characters in one line, checked before parsing
MAX_DEPTH = 100  #: repeats within repeats
UNITS = {"s": 1.0, "ms": 0.001}


@functools.cache
def parser() -> Lark:
    """The .gest parser, built once. It builds the syntax tree's dataclasses while it
    parses (Lark's tree-less LALR mode); positions come from the tokens.

    Lark can keep the analysed grammar between runs, but it reads its cache file with
    pickle, which runs whatever the file says: the cache is kept only in this user's
    private cache directory (resources.private_cache_dir), never in the shared temp
    directory Lark would choose, and not at all when no private place can be trusted."""
    text = grammar_path().read_text(encoding="utf-8")
    return Lark(
        text,
        parser="lalr",
        lexer="contextual",
        postlex=GestIndenter(),
        maybe_placeholders=False,
        transformer=_TO_AST,
        cache=_cache_file(text),
    )


def _cache_file(grammar: str) -> str | bool:
    """The private file for Lark's cache of ``grammar``, or False (no cache)."""
    where = private_cache_dir()
    if where is None:
        return False
    digest = hashlib.sha256(f"{grammar}{lark_version}{sys.version_info[:2]}".encode())
    path = where / f"gest-grammar-{digest.hexdigest()[:16]}.lark"
    return str(path) if private_file(path) else False


@v_args(inline=True)
class _ToAst(Transformer):
    """Parse-tree rules -> syntax dataclasses. ``file`` is set for each parse."""

    file = "<string>"
    depths: dict[int, int] = {}  #: id of a Repeat -> how many repeats deep it goes

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
            raise SyntaxProblem(f"repeat count must be a whole number from 1 to "
                                f"{MAX_REPEAT}, got {shown(text)}", tok_span(tok))
        return int(text)

    def wait(self, duration: ast.Duration):
        return ast.Wait(duration, duration.pos, "wait")

    def hold(self, duration: ast.Duration):
        return ast.Wait(duration, duration.pos, "hold")

    def move(self, *parts):
        side = self._name(parts[0]) if isinstance(parts[0], Token) else None
        targets = tuple(p for p in parts if isinstance(p, ast.Target))
        timing: dict[str, Any] = {}  # over and stagger: a Duration; through: a Pos
        for kind, value in (p for p in parts if isinstance(p, tuple)):
            if kind in timing:
                raise SyntaxProblem(f"'{kind}' is given twice in this step",
                                    pos_span(getattr(value, "pos", value)))
            timing[kind] = value
        return ast.Move(targets, timing.get("over"), timing.get("stagger"),
                        (side or targets[0].name).pos, timing.get("through"), side)

    def together(self, *parts: ast.Move | ast.Say):
        return ast.Together(parts, parts[0].pos)

    def say(self, keyword: Token, text: Token):
        return ast.Say(text[1:-1], self._pos(keyword), self._pos(text))

    def over(self, duration: ast.Duration):  # the timings: (kind, value)
        return ("over", duration)

    def stagger(self, duration: ast.Duration):
        return ("stagger", duration)

    def through(self, keyword: Token):
        return ("through", self._pos(keyword))

    def target(self, name: Token, value: Token | None = None):
        if value is None:
            return ast.Target(self._name(name), None, None)
        text = str(value)
        number = float(text)  # inf when it has hundreds of digits
        outside = SyntaxProblem(f"value {shown(text)} is outside 0..{MAX_VALUE}",
                                tok_span(value), f"0 is straight, {MAX_VALUE} is curled")
        if not math.isfinite(number) or abs(number) > 1e9:
            raise outside
        if number != int(number) or "." in text:
            lo, hi = int(number // 1), int(number // 1) + 1
            raise SyntaxProblem(f"values are whole degrees, got {shown(text)}",
                                tok_span(value), f"use {lo} or {hi}")
        if not 0 <= number <= MAX_VALUE:
            raise outside
        return ast.Target(self._name(name), int(number), self._pos(value))

    def duration(self, number: Token, unit: Token | None = None):
        text = str(number)
        if unit is None:
            raise SyntaxProblem(f"the duration {shown(text)} needs a unit", tok_span(number),
                                f"write {shown(text)}s or {shown(text)}ms")
        if str(unit) not in UNITS:
            raise SyntaxProblem(f"unknown unit '{shown(str(unit))}'", tok_span(unit),
                                f"use s or ms, as in {shown(text)}s or {shown(text)}ms")
        seconds = float(text) * UNITS[str(unit)]  # inf when it has hundreds of digits
        span = (number.line, number.column, len(text) + len(str(unit)))
        if not seconds > 0:
            raise SyntaxProblem(f"a duration must be greater than 0, got {shown(text)}{unit}",
                                span)
        if seconds > MAX_DURATION:
            raise SyntaxProblem(f"duration {shown(text)}{unit} is too long (at most "
                                f"{MAX_DURATION:g} s per step)", span,
                                "split a long hold into several waits")
        pos = self._pos(number)
        return ast.Duration(seconds, Pos(pos.file, pos.line, pos.column, span[2]), text,
                            str(unit))


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


_TO_AST = _ToAst()
_LOCK = threading.Lock()  # the parser and its transformer are shared


def parse(text: str, file: str = "<string>") -> ast.Module:
    """Parse one .gest source text; raise GestError on any syntax problem: every one it
    has, an error in one gesture (one top-level block) not hiding those of the others. A
    text longer than MAX_SOURCE characters, or with a line longer than MAX_LINE, is
    refused before parsing."""
    text, lines = prepared(text, file)
    parsed = attempt(text, file, lines)
    if isinstance(parsed, ast.Module):
        return parsed
    # each block alone: its errors (a block's end is no file's end: an error there is
    # the cut's, and one at the file's end is the first already)
    raise every_error(parsed, [attempt(alone(lines, start, end), file, lines)
                               for start, end in blocks(lines)])


def prepared(text: str, file: str) -> tuple[str, list[str]]:
    """``text`` ending in a newline, and its lines; GestError for a text too large."""
    size = len(text)
    if not text.endswith("\n"):
        text += "\n"
    lines = text[:-1].split("\n")  # Lark counts lines by \n only
    try:
        _check_size(text, size, lines)
    except SyntaxProblem as problem:
        raise problem.error(file, lines) from None
    return text, lines


def alone(lines: list[str], start: int, end: int) -> str:
    """The block of ``lines`` from ``start`` to ``end`` (0-based), as a text whose lines
    keep their numbers."""
    return "\n" * start + "\n".join(lines[start:end]) + "\n"


def every_error(first: GestError, each: list[ast.Module | GestError]) -> GestError:
    """The text's errors: its ``first``, and each block's (``each``) but those at a
    block's end (the cut's); a line keeps its first error (the whole file's first)."""
    found = [first, *(p for p in each if isinstance(p, GestError)
                      and not p.first.message.startswith("unexpected end of the file"))]
    errors: dict[int, Diagnostic] = {}
    for error in found:
        errors.setdefault(error.first.pos.line, error.first)
    return GestError(sorted(errors.values(), key=lambda d: (d.pos.line, d.pos.column)))


def attempt(text: str, file: str, lines: list[str]) -> ast.Module | GestError:
    """``text`` (the file's ``lines``, or a block of them) parsed, or its first syntax
    problem."""
    try:
        with _LOCK:
            _TO_AST.file, _TO_AST.depths = file, {}
            return parser().parse(text)
    except SyntaxProblem as problem:  # tree-less mode: callbacks' exceptions come as they are
        return problem.error(file, lines)
    except UnexpectedInput as exc:
        return lark_problem(exc, text, lines).error(file, lines)


def blocks(lines: list[str]) -> list[tuple[int, int]]:
    """(first, end) line index of each top-level block: a line that starts at column 1
    (not a comment) and the indented, blank and comment lines after it."""
    starts = [k for k, line in enumerate(lines)
              if line[:1] not in ("", " ", "\t", "#") and not line.startswith("\ufeff#")]
    return list(zip(starts, [*starts[1:], len(lines)][:len(starts)], strict=True))


def _check_size(text: str, size: int, lines: list[str]) -> None:
    """Refuse a text of more than MAX_SOURCE characters (``size``), or with a line of
    more than MAX_LINE, before Lark sees it."""
    if size > MAX_SOURCE:
        line = text.count("\n", 0, MAX_SOURCE) + 1
        column = MAX_SOURCE - (text.rfind("\n", 0, MAX_SOURCE) + 1) + 1
        raise SyntaxProblem(f"the file is longer than {MAX_SOURCE:,} characters ({size:,}): "
                            f"it is not parsed", (line, column, 1),
                            "split it into several files joined with 'use'")
    for number, line_text in enumerate(lines, 1):
        if len(line_text) > MAX_LINE:
            raise SyntaxProblem(f"this line is longer than {MAX_LINE:,} characters "
                                f"({len(line_text):,})", (number, MAX_LINE + 1, 1),
                                "put one step on each line; build a long pose from smaller "
                                "poses")
