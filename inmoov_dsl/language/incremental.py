"""Parsing a text again after an edit, for an editor (pure): each top-level block (a
gesture, a pose, a group, a ``use``, the robot line) is parsed once for as long as its
text stays the same, wherever it moves; the result is what ``parse`` gives the whole
text, its errors included, without parsing again the blocks the edit did not touch."""

from __future__ import annotations

import dataclasses
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
        text, lines = prepared(text, file)
        kept: dict[tuple[str, str], tuple[int, Parsed]] = {}
        each: list[Parsed] = []
        for start, end in spans(lines):
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
        bad = next((k for k, p in enumerate(each) if isinstance(p, GestError)), None)
        if bad is None:
            try:
                return module_of(file, tuple(i for items in each for i in items))
            except SyntaxProblem as problem:
                raise problem.error(file, lines) from None
        start = spans(lines)[bad][0]
        first = attempt("\n" * start + "\n".join(lines[start:]) + "\n", file, lines)
        assert isinstance(first, GestError)  # the first block with a problem has it
        raise every_error(first, list(each))


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
