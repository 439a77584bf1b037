"""Parsing a text again after an edit, for an editor (pure): each top-level block (a
gesture, a pose, a group, a ``use``, the robot line) is parsed once for as long as its
text stays the same, wherever it moves; the result is what ``parse`` gives the whole
text, its errors included, without parsing again the blocks the edit did not touch."""

from __future__ import annotations

import dataclasses
import re
from functools import cache
from typing import NamedTuple

from ..errors import Diagnostic, GestError, Pos
from . import syntax as ast
from .indent import STYLE_LINE
from .parse import alone, attempt, attempt_block, blocks, every_error, in_order, prepared
from .parse_errors import SyntaxProblem
from .tree import module_of

Parsed = ast.Module | GestError  #: a block's items (and its flaws), or its errors


class Partial(NamedTuple):
    """What of a text parses, and what does not."""

    module: ast.Module  #: the blocks that parse, as a file
    error: GestError | None  #: every syntax error ``parse`` raises for the text
    #: the names the blocks that do not parse would define (``*``: a robot or ``use``
    #: line, which every name may depend on)
    broken: frozenset[str]
    #: the names of the blocks that parse with errors (a value, a unit, a step's line):
    #: read for their names, never planned
    flawed: frozenset[str]


class BlockParser:
    """``parse`` with a memory of the blocks of the texts it parsed last."""

    def __init__(self) -> None:
        self.seen: dict[tuple[str, str], tuple[int, Parsed]] = {}

    def parse(self, text: str, file: str) -> ast.Module:
        """As ``parse.parse(text, file)``; the blocks it has seen (anywhere in a text it
        parsed last) are not parsed again."""
        found = self.parse_partly(text, file)
        if found.error is not None:
            raise found.error
        return found.module

    def parse_partly(self, text: str, file: str) -> Partial:
        """The blocks of ``text`` that parse, as a file, and its syntax errors."""
        text, lines = prepared(text, file)
        kept: dict[tuple[str, str], tuple[int, Parsed]] = {}
        each: list[Parsed] = []
        found = spans(lines)
        for start, end in found:
            key = (file, "\n".join(lines[start:end]))
            was = self.seen.get(key) or kept.get(key)
            if was is None:
                was = (start, _alone(lines, start, end, file))
            elif was[0] != start:
                was = (start, shifted(was[1], start - was[0]))
            kept[key] = was
            each.append(was[1])
        self.seen = {k: v for k, v in {**self.seen, **kept}.items() if k[0] != file or
                     k in kept}
        parsed = [p for p in each if isinstance(p, ast.Module)]
        items = tuple(i for p in parsed for i in p.items)
        flaws = [d for p in parsed for d in p.flaws]
        flawed = frozenset(defines(lines[found[k][0]]) for k, p in enumerate(each)
                           if isinstance(p, ast.Module) and p.flaws)
        bad = [k for k, p in enumerate(each) if isinstance(p, GestError)]
        if not bad:
            try:
                return Partial(module_of(file, items),
                               GestError(flaws) if flaws else None, frozenset(), flawed)
            except SyntaxProblem as problem:  # a robot line below the first
                return Partial(_without_robots(file, items), GestError(in_order(
                    [problem.error(file, lines).first, *flaws])), frozenset({"*"}), flawed)
        start = found[bad[0]][0]
        first = attempt(alone(lines, start, len(lines)), file, lines)
        if not isinstance(first, GestError):  # the first block with a problem has it
            first = each[bad[0]]
        broken = frozenset(defines(lines[found[k][0]]) for k in bad)
        try:
            module = module_of(file, items)
        except SyntaxProblem:
            module, broken = _without_robots(file, items), broken | {"*"}
        return Partial(module, every_error(first, list(each)), broken, flawed)


def _alone(lines: list[str], start: int, end: int, file: str) -> Parsed:
    """The block of ``lines`` from ``start`` to ``end`` parsed (``attempt_block``) as if
    it were on the text's second line (the first when it is), then moved to its place:
    the lexer sees what it sees at ``start``, one line end before it, and a block costs
    its own length, not its place's (``start`` line ends before it, read each time,
    made a long file's parse quadratic)."""
    if start == 0:
        return attempt_block(lines, 0, end, file)
    near = ["", *lines[start:end + 1]]  # the line after it too: an error's may be there
    return shifted(attempt_block(near, 1, end - start + 1, file), start - 1)


def _without_robots(file: str, items: tuple[ast.Item, ...]) -> ast.Module:
    """``items`` as a file, without the robot lines below the first item."""
    return ast.Module(file, tuple(i for k, i in enumerate(items)
                                  if k == 0 or not isinstance(i, ast.Robot)))


DEFINES = re.compile(r"\s*(?:(robot|use)\b|(?:pose|group)\s+(\w+)|(\w+))")


def defines(line: str) -> str:
    """The name a block whose first line is ``line`` would define (``*``: a robot or
    ``use`` line; an empty name: nothing a name can mean)."""
    m = DEFINES.match(line)
    if m is None:
        return ""
    return "*" if m[1] else (m[2] or m[3] or "")


def spans(lines: list[str]) -> list[tuple[int, int]]:
    """The blocks of ``lines``, and the comments and blank lines above the first."""
    found = blocks(lines)
    head = found[0][0] if found else len(lines)
    return ([(0, head)] if head else []) + found


def shifted(parsed: Parsed, lines: int) -> Parsed:
    """``parsed`` moved down by ``lines`` (up when negative)."""
    if isinstance(parsed, GestError):
        return GestError([_moved(d, lines) for d in parsed.diagnostics])
    return _moved(parsed, lines)


def _moved(node, lines: int):
    if type(node) is Pos:
        return copied(node, line=node.line + lines)
    if type(node) is Diagnostic and STYLE_LINE.search(node.message):  # names a line
        return copied(node, pos=_moved(node.pos, lines), message=STYLE_LINE.sub(
            lambda m: f"{m[1]}{int(m[2]) + lines}{m[3]}", node.message))
    if isinstance(node, tuple):
        return tuple([_moved(n, lines) for n in node])
    fields = _fields(type(node))
    if fields is None:
        return node
    return copied(node, **{f: _moved(getattr(node, f), lines) for f in fields})


def copied(node, **changes):
    """A copy of the frozen dataclass ``node`` with ``changes`` (no __init__ run: the
    values are those of a node already checked; a copy is what an edit makes of each
    block it moves, thousands at a time)."""
    new = object.__new__(type(node))
    new.__dict__.update(node.__dict__, **changes)
    return new


KEPT = {"text", "count", "value", "seconds", "number", "unit", "keyword", "path", "is_file",
        "severity", "message", "hint", "source_line"}  #: fields that hold no place


@cache
def _fields(kind: type) -> tuple[str, ...] | None:
    """The fields of a syntax class (or a Diagnostic) that may hold a place; None for
    what is not a dataclass."""
    if not dataclasses.is_dataclass(kind):
        return None
    return tuple(f.name for f in dataclasses.fields(kind) if f.name not in KEPT)
