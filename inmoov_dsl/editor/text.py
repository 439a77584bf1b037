"""The words of a line of gesture code, as an editor points at them (pure)."""

from __future__ import annotations

import re

NAME = r"[A-Za-z_][A-Za-z0-9_]*"  #: the grammar's NAME
PROFILE = r"[A-Za-z_][A-Za-z0-9_-]*"  #: ``robot rhand-maestro``: the grammar's ROBOT_NAME
NUMBER = r"[+-]?(?:\d+(?:\.\d*)?|\.\d+)"  #: the grammar's NUMBER
WORD = re.compile(NAME)
STRING = re.compile(r'"[^"]*"?')


def code(line: str) -> str:
    """``line`` with its strings and its comment blanked (the same length): what is
    left are the names, keywords, numbers and punctuation."""
    blanked = STRING.sub(lambda m: " " * len(m.group()), line)
    cut = blanked.find("#")
    return blanked if cut < 0 else blanked[:cut] + " " * (len(blanked) - cut)


def word_at(text: str, line: int, column: int) -> str | None:
    """The name at 0-based ``line`` and ``column`` of ``text`` (not in a comment or a
    string), or None."""
    lines = text.split("\n")
    if not 0 <= line < len(lines):
        return None
    for match in WORD.finditer(code(lines[line])):
        if match.start() <= column <= match.end():
            return match.group()
    return None


def string_at(line: str, column: int) -> tuple[int, int, str] | None:
    """(start, end, text) of the string that ``column`` (0-based) is in or just after
    the opening quote of, the quotes left out; None outside a string."""
    for match in STRING.finditer(line):
        closed = match.group().endswith('"') and len(match.group()) > 1
        end = match.end() - (1 if closed else 0)
        if match.start() < column <= end:
            return match.start() + 1, end, line[match.start() + 1:end]
    return None
