"""A text's lines as the Language Server Protocol counts them (pure): the one rule of
the editor's server for every line and column. The protocol's line ends are ``\\n``,
``\\r\\n`` and ``\\r``, nothing else: not U+2028, U+0085, a form feed or U+001C, which
Python's ``str.splitlines`` also splits on. The compiler counts lines by ``\\n`` (a lone
``\\r`` is an error to it): ``place`` is where one of its places is for the protocol.
Columns are code points (Python's indices); ``index`` reads an editor's column in the
position encoding agreed at ``initialize``."""

from __future__ import annotations

import bisect
import re
from functools import lru_cache

BREAK = re.compile(r"\r\n|\r|\n")  #: the protocol's line ends
LONE_CR = re.compile(r"\r(?!\n)")  #: a line end to the protocol, not to the compiler


@lru_cache(maxsize=8)
def rows(text: str) -> tuple[str, ...]:
    """The lines of ``text``, without their ends (a text ending in a line end has an
    empty last line, where the cursor goes after it). Kept for the last few texts:
    every request reads the lines of the text it is about."""
    return tuple(BREAK.split(text))


def compiler_rows(text: str) -> tuple[str, ...]:
    """The lines of ``text`` as the compiler numbers them (by ``\\n``; a ``\\r\\n``
    line keeps its ``\\r``)."""
    return tuple(text.split("\n"))


def place(text: str, line: int, column: int) -> tuple[int, int]:
    """The 0-based protocol line and column of the compiler's 1-based ``line`` and
    ``column`` in ``text`` (the same but for the lines after a lone ``\\r``)."""
    moved = _lone(text)
    if not moved or not 1 <= line <= len(moved):
        return line - 1, column - 1
    first, cuts = moved[line - 1]
    k = bisect.bisect_right(cuts, column - 1)
    return first + k, column - 1 - (cuts[k - 1] if k else 0)


def compiler_line(text: str, line: int) -> int:
    """The compiler's 1-based line that protocol line ``line`` (0-based) is on."""
    moved = _lone(text)
    if not moved:
        return line + 1
    return bisect.bisect_right([first for first, _ in moved], line)


@lru_cache(maxsize=8)
def _lone(text: str) -> tuple[tuple[int, tuple[int, ...]], ...]:
    """Per compiler line: the protocol line it starts on, and the column after each
    lone ``\\r`` in it (nothing when the text has none)."""
    if "\r" not in text or not LONE_CR.search(text):
        return ()
    out, first = [], 0
    each = text.split("\n")
    for k, row in enumerate(each):
        if k < len(each) - 1 and row.endswith("\r"):
            row = row[:-1]  # its \r\n: one line end
        cuts = tuple(m.end() for m in LONE_CR.finditer(row))
        out.append((first, cuts))
        first += len(cuts) + 1
    return tuple(out)


def clamp(text: str, line: int, column: int) -> tuple[int, int]:
    """``line`` and ``column`` brought into ``text``: at most its last line, and at
    most the end of that line."""
    lines = rows(text)
    line = max(0, min(line, len(lines) - 1))
    return line, max(0, min(column, len(lines[line])))


def end(text: str) -> tuple[int, int]:
    """The protocol position of the end of ``text``."""
    lines = rows(text)
    return len(lines) - 1, len(lines[-1])


def index(text: str, line: int, units: int, encoding: str = "utf-16") -> int:
    """The index in ``text`` of the protocol position ``line``, ``units`` (counted in
    ``encoding``'s code units: ``utf-8``, ``utf-16`` or ``utf-32``), brought into the
    text: past its last line is its end, past a line's end is that end (never into its
    line end)."""
    if line < 0:
        return 0
    start = 0
    if "\r" not in text:  # the usual text: its line ends found faster
        for _ in range(line):
            start = text.find("\n", start) + 1
            if start == 0:
                return len(text)
        stop = text.find("\n", start)
        row = text[start:stop if stop >= 0 else len(text)]
        return start + _column(row, units, encoding)
    for _ in range(line):
        found = BREAK.search(text, start)
        if found is None:
            return len(text)
        start = found.end()
    stop = BREAK.search(text, start)
    row = text[start:stop.start() if stop else len(text)]
    return start + _column(row, units, encoding)


def _column(row: str, units: int, encoding: str) -> int:
    """The code point of ``row`` at ``units`` code units of ``encoding``."""
    if encoding == "utf-32" or row.isascii():
        return max(0, min(units, len(row)))
    width = (lambda c: len(c.encode("utf-8"))) if encoding == "utf-8" else \
        (lambda c: 2 if ord(c) > 0xFFFF else 1)
    seen = 0
    for k, char in enumerate(row):
        if seen >= units:
            return k
        seen += width(char)
    return len(row)


def edited(text: str, start: tuple[int, int], stop: tuple[int, int], new: str,
           encoding: str = "utf-16") -> str:
    """``text`` with the protocol range from ``start`` to ``stop`` (line, code units)
    replaced by ``new`` (an incremental change of ``textDocument/didChange``); a range
    past the text's end is brought to it, one backwards is taken in order."""
    a = index(text, *start, encoding)
    b = index(text, *stop, encoding)
    a, b = min(a, b), max(a, b)
    return text[:a] + new + text[b:]
