"""Parsing a text again after an edit, for an editor (pure): each top-level block (a
gesture, a pose, a group, a ``use``, the robot line) is parsed once for as long as its
text stays the same, wherever it moves; the result is what ``parse`` gives the whole
text, its errors included, without parsing again the blocks the edit did not touch."""

from __future__ import annotations

import dataclasses
import re
from functools import cache

from ..errors import GestError, Pos
from . import syntax as ast
from .parse import alone, attempt, blocks, every_error, module_of, prepared
from .parse_errors import SyntaxProblem

Parsed = tuple[ast.Item, ...] | GestError  #: a block's items, or its first problem


class BlockParser:
    """``parse`` with a memory of the blocks of the texts it parsed last."""

    def __init__(self) -> None:
        self.seen: dict[tuple[str, str], tuple[int, Parsed]] = {}

    def parse(self, text: str, file: str) -> ast.Module:
        """As ``parse.parse(text, file)``; the blocks it has seen (anywhere in a text it
        parsed last) are not parsed again."""
        module, error, _broken = self.parse_partly(text, file)
        if error is not None:
            raise error
        return module

    def parse_partly(self, text: str, file: str
                     ) -> tuple[ast.Module, GestError | None, frozenset[str]]:
        """The blocks of ``text`` that parse, as a file; the syntax errors ``parse``
        raises for it (None: none); and the names the blocks that do not parse would
        define (``*``: a robot or ``use`` line, which every name may depend on)."""
        text, lines = prepared(text, file)
        kept: dict[tuple[str, str], tuple[int, Parsed]] = {}
        each: list[Parsed] = []
        found = spans(lines)
        for start, end in found:
            key = (file, "\n".join(lines[start:end]))
            was = self.seen.get(key) or kept.get(key)
            if was is None:
                parsed = attempt(alone(lines, start, end), file, lines)
                was = (start, parsed.items if isinstance(parsed, ast.Module) else parsed)
            elif was[0] != start:
                was = (start, shifted(was[1], start - was[0]))
            kept[key] = was
            each.append(was[1])
        self.seen = {k: v for k, v in {**self.seen, **kept}.items() if k[0] != file or
                     k in kept}
        items = tuple(i for parsed in each if not isinstance(parsed, GestError)
                      for i in parsed)
        bad = [k for k, parsed in enumerate(each) if isinstance(parsed, GestError)]
        if not bad:
            try:
                return module_of(file, items), None, frozenset()
            except SyntaxProblem as problem:  # a robot line below the first
                return _without_robots(file, items), problem.error(file, lines), \
                    frozenset({"*"})
        start = found[bad[0]][0]
        first = attempt(alone(lines, start, len(lines)), file, lines)
        if not isinstance(first, GestError):  # the first block with a problem has it
            first = each[bad[0]]
        broken = frozenset(defines(lines[found[k][0]]) for k in bad)
        try:
            module = module_of(file, items)
        except SyntaxProblem:
            module, broken = _without_robots(file, items), broken | {"*"}
        return module, every_error(first, list(each)), broken


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
    return tuple(_moved(item, lines) for item in parsed)


def _moved(node, lines: int):
    if type(node) is Pos:
        return copied(node, line=node.line + lines)
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
