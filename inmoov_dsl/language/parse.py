"""Parse .gest text into a syntax tree (stage 1 of the compiler). The Lark LALR parser
is built once per process; syntax errors become GestErrors at their place."""

from __future__ import annotations

import functools
import hashlib
import sys
import threading

from lark import Lark, LarkError, UnexpectedInput
from lark import __version__ as lark_version

from ..errors import Diagnostic, GestError
from ..resources import grammar_path, private_cache_dir, private_file
from . import syntax as ast
from .indent import GestIndenter
from .parse_errors import SyntaxProblem, lark_problem
from .tree import TO_AST

MAX_SOURCE = 1_000_000  #: characters in one .gest file, checked before parsing
MAX_LINE = 10_000  #: characters in one line, checked before parsing


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
        transformer=TO_AST,
        cache=_cache_file(text),
    )


@functools.cache
def _asking() -> Lark:
    """The grammar as a parser that builds no tree: asked what may come next
    (``accepts``), never to parse a file, so the syntax tree's transformer (which keeps
    a parse's flaws) is not shared with it."""
    text = grammar_path().read_text(encoding="utf-8")
    return Lark(text, parser="lalr", lexer="contextual", postlex=GestIndenter(),
                maybe_placeholders=False, tree_class=None,
                cache=_cache_file(text, "asking"))


def accepts(text: str) -> frozenset[str] | None:
    """The grammar's terminals (``NAME``, ``OVER``, ``_NL``, ...) that may come after
    ``text``, the start of a file cut anywhere; None when ``text`` does not parse. The
    blocks the end of the text would close are left open (the cut is not an end)."""
    interactive = _asking().parse_interactive(text)
    try:
        for token in interactive.iter_parse():  # each given before it is fed
            if token.type == "_DEDENT":
                break
    except (LarkError, SyntaxProblem):  # what the parser, the lexer or the indenter refuses
        return None
    return frozenset(interactive.accepts())


def _cache_file(grammar: str, kind: str = "") -> str | bool:
    """The private file for Lark's cache of ``grammar`` (built as ``kind``), or False
    (no cache)."""
    where = private_cache_dir()
    if where is None:
        return False
    digest = hashlib.sha256(f"{grammar}{lark_version}{sys.version_info[:2]}".encode())
    path = where / f"gest-grammar{kind and '-' + kind}-{digest.hexdigest()[:16]}.lark"
    return str(path) if private_file(path) else False


_LOCK = threading.Lock()  # the parser and its transformer are shared


def parse(text: str, file: str = "<string>") -> ast.Module:
    """Parse one .gest source text; raise GestError on any syntax problem: every one it
    has, an error in one gesture (one top-level block) not hiding those of the others,
    nor one step's those of the next. A text longer than MAX_SOURCE characters, or with a
    line longer than MAX_LINE, is refused before parsing."""
    text, lines = prepared(text, file)
    parsed = attempt(text, file, lines)
    if isinstance(parsed, ast.Module):
        if parsed.flaws:
            raise GestError(parsed.flaws)
        return parsed
    raise every_error(parsed, [attempt_block(lines, start, end, file)
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


CUT = "unexpected end of the file"  #: how a block's end, read alone, is told


def every_error(first: GestError, each: list[ast.Module | GestError]) -> GestError:
    """The text's errors: its ``first``, and each block's (``each``: its errors, or the
    flaws of one that parses) but those at a block's end (the cut's: one at the file's
    end is the first already); the line of the first keeps that one."""
    head = first.first
    found = [head, *(d for parsed in each for d in (
        parsed.diagnostics if isinstance(parsed, GestError) else parsed.flaws)
        if not d.message.startswith(CUT) and d.pos.line != head.pos.line)]
    return GestError(in_order(found))


def in_order(found: list[Diagnostic]) -> list[Diagnostic]:
    """``found`` in the file's order, each told once."""
    once = {(d.pos.line, d.pos.column, d.message): d for d in reversed(found)}
    return sorted(once.values(), key=lambda d: (d.pos.line, d.pos.column))


def attempt(text: str, file: str, lines: list[str]) -> ast.Module | GestError:
    """``text`` (the file's ``lines``, or a block of them) parsed, its flaws kept in it,
    or its first syntax problem."""
    try:
        with _LOCK:
            TO_AST.file, TO_AST.depths, TO_AST.flaws = file, {}, []
            module = parser().parse(text)
            flaws = TO_AST.flaws
    except SyntaxProblem as problem:  # tree-less mode: callbacks' exceptions come as they are
        return problem.error(file, lines)
    except UnexpectedInput as exc:
        return lark_problem(exc, text, lines).error(file, lines)
    if not flaws:
        return module
    return ast.Module(file, module.items, tuple(in_order(
        [p.error(file, lines).first for p in flaws])))


MAX_SKIPPED = 100  #: lines of one block left out so that those after them are read
#: lines read again, in all, to go on past the lines left out of one block: a long block
#: is read again fewer times (each time to its next error), so that it costs what a few
#: reads of the file do, never hundreds
MAX_REREAD = 5000


def attempt_block(lines: list[str], start: int, end: int, file: str
                  ) -> ast.Module | GestError:
    """The block of ``lines`` from ``start`` to ``end`` parsed alone (``attempt``). A line
    of its steps that does not parse is told and left out, so that the lines after it
    are read too: the block then parses with that error among its flaws."""
    own, told, skipped = lines[start:end], [], set()
    most = min(MAX_SKIPPED, MAX_REREAD // max(1, end - start))
    while True:
        parsed = attempt("\n" * start + "\n".join(own) + "\n", file, lines)
        if isinstance(parsed, ast.Module):
            return parsed if not told else ast.Module(file, parsed.items,
                                                      tuple(in_order([*told, *parsed.flaws])))
        k = parsed.first.pos.line - 1 - start
        if not 0 < k < len(own) or k in skipped or len(skipped) >= most or \
                not _starts(own[0]):
            # the block's name line, a line left out (what is left is not the text's), or
            # lines before the first block
            return GestError(told) if told else parsed
        told.append(parsed.first)
        skipped.add(k)
        own[k] = _left_out(own, k)


def _left_out(own: list[str], k: int) -> str:
    """What stands for line ``k`` of a block's lines (``own``), which does not parse: an
    empty line, or a repeat of its indentation when the lines below are indented under
    it (a ``repeat 2`` without its colon), so that those are read as its body."""
    indent = len(own[k]) - len(own[k].lstrip(" \t"))
    below = next((row for row in own[k + 1:] if row.strip() and
                  not row.lstrip().startswith("#")), "")
    if len(below) - len(below.lstrip(" \t")) > indent:
        return own[k][:indent] + "repeat 1:"
    return ""


def blocks(lines: list[str]) -> list[tuple[int, int]]:
    """(first, end) line index of each top-level block: a line that starts at column 1
    (not a comment) and the indented, blank and comment lines after it."""
    starts = [k for k, line in enumerate(lines) if _starts(line)]
    return list(zip(starts, [*starts[1:], len(lines)][:len(starts)], strict=True))


def _starts(line: str) -> bool:
    """Does ``line`` start a top-level block (at column 1, not a comment)?"""
    return line[:1] not in ("", " ", "\t", "#") and not line.startswith("\ufeff#")


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
