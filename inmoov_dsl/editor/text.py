"""The words of a line of gesture code, as an editor points at them (pure)."""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass

from ..language.parse import accepts
from ..language.syntax import KEYWORDS
from .lines import rows

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
    lines = rows(text)
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


#: the words of a line up to the cursor: a string (closed or not), a comment's start, a
#: number, a name (a keyword too), punctuation, anything else
TOKEN = re.compile(rf'(?P<string>"[^"]*"?)|(?P<comment>#)|(?P<number>{NUMBER})|'
                   rf'(?P<name>{NAME})|(?P<mark>[:,&])|(?P<other>\S)')
TIMING = ("over", "stagger", "through")  #: the timing keywords, in the grammar's order


@dataclass(frozen=True)
class Token:
    """A word of the code before the cursor: ``kind`` (a TOKEN group) and ``text``."""

    kind: str
    text: str
    start: int  #: in the logical line (its continued lines joined)
    end: int


@dataclass(frozen=True)
class Place:
    """What the grammar lets be typed at the cursor, as ``place`` tells it. ``kind``:
    ``top`` (a top-level line's keyword), ``profile`` (after ``robot``), ``member`` (a
    group's servo), ``pose`` (a pose's target), ``step`` (a step's start), ``part``
    (after ``&``), ``target`` (after ``,``), ``side`` (after ``left``/``right``),
    ``named`` (after a target's name, ``name``), ``timing`` (after a value), ``unit``
    (after a duration's number), ``nothing``."""

    kind: str
    start: int  #: 0-based column where the word being typed starts (the cursor's: none)
    name: str = ""  #: ``named``: the name; else the gesture or pose being defined
    written: frozenset[str] = frozenset()  #: ``timing``: what the step's part has
    first: bool = False  #: ``top``: no code before this line (the robot line may be)


def place(text: str, line: int, column: int) -> Place:
    """What may be typed at 0-based ``line`` and ``column`` of ``text``, from the code
    before the cursor (its line and the lines it continues with a backslash): see
    ``Place``. The grammar says what may come next (``parse.accepts``); the words before
    say which of a step's names it is. In a comment or a string: ``nothing``."""
    lines = rows(text)
    if not 0 <= line < len(lines):
        return Place("nothing", max(column, 0))
    row = lines[line]
    column = max(0, min(column, len(row)))
    head, top = _continued(lines, line)
    prefix = head + row[:column]
    tokens = [Token(m.lastgroup or "other", m.group(), m.start(), m.end())
              for m in TOKEN.finditer(prefix)]
    if any(t.kind == "comment" for t in tokens) or (
            tokens and tokens[-1].kind == "string" and tokens[-1].end == len(prefix)
            and (len(tokens[-1].text) == 1 or not tokens[-1].text.endswith('"'))):
        return Place("nothing", column)
    start, before = column, prefix
    if tokens and tokens[-1].end == len(prefix) and tokens[-1].kind in ("name", "number"):
        typed = tokens.pop()  # the word being typed: what may stand in its place
        start, before = typed.start - len(head), prefix[:typed.start]
        if typed.kind == "number":  # a value or a duration: its unit after it
            ends = accepts(f"{STEP}{prefix.lstrip()}" if prefix[:1] in (" ", "\t") else prefix)
            return Place("unit" if ends and "UNIT" in ends else "nothing",
                         column if ends and "UNIT" in ends else start)
        if typed.kind == "name" and tokens and tokens[-1].kind == "number" \
                and tokens[-1].end == typed.start:  # a unit, typed after its number
            before = prefix[:tokens[-1].end]
    step = prefix[:1] in (" ", "\t")
    allowed = accepts(f"{STEP}{before.lstrip()}" if step else before)
    if allowed is None:
        return Place("nothing", start)
    if "UNIT" in allowed:  # after a duration's number: its unit
        return Place("unit", start)
    defined = _defining(lines, line) if step else _named(tokens)
    return _kind(allowed, tokens, Place("step", start, defined, first=not any(
        code(row).strip() for row in lines[:top])))


def _continued(lines: Sequence[str], line: int) -> tuple[str, int]:
    """The lines that ``line`` continues (each ending in a backslash), joined, each
    backslash a space; and the first of them (``line`` when none)."""
    head = ""
    k = line - 1
    while k >= 0 and (cut := code(lines[k]).rstrip()).endswith("\\"):
        head = lines[k][:len(cut) - 1] + " " + head
        k -= 1
    return head, k + 1


def _defining(lines: Sequence[str], line: int) -> str:
    """The name of the gesture whose block ``line`` is in ("" when none)."""
    for row in reversed(lines[:line]):
        if row[:1] not in (" ", "\t", "") and code(row).strip():
            found = re.match(rf"({NAME})\s*:", row)
            return found.group(1) if found and found.group(1) not in KEYWORDS else ""
    return ""


STEP = "_:\n    "  #: a gesture's head: an indented line is one of its steps


def _named(tokens: list[Token]) -> str:
    """The name a top-level line defines (a gesture's or a pose's), "" when none."""
    words = [t.text for t in tokens]
    if len(words) > 1 and words[1] == ":" and words[0] not in KEYWORDS:
        return words[0]
    if len(words) > 2 and words[0] == "pose" and words[2] == ":":
        return words[1]
    return ""


def _kind(allowed: frozenset[str], tokens: list[Token], at: Place) -> Place:
    """The place where the grammar allows ``allowed`` after ``tokens``."""
    last = tokens[-1].text if tokens else ""
    first = tokens[0].text if tokens else ""
    if "ROBOT_NAME" in allowed:
        return Place("profile", at.start)
    if allowed & {"GROUP", "POSE", "USE"}:
        return Place("top", at.start, first=at.first)
    if first in ("group", "pose") and last in (":", ","):
        return Place("member" if first == "group" else "pose", at.start, at.name)
    if first in ("group", "pose", "use", "robot"):
        return Place("nothing", at.start)
    if "REPEAT" in allowed:
        return Place("step", at.start, at.name)
    if {"SAY", "NAME"} <= allowed:
        return Place("part", at.start, at.name)
    if allowed == {"LPAR", "NAME"}:  # after 'right hand to', 'look at'
        return Place("place", at.start, at.name)
    if "NAME" in allowed and allowed <= {"NAME", "SIDE", "LOOK", "HAND"}:
        kind = "side" if last in ("left", "right") else "target" if last == "," else ""
        return Place(kind or "nothing", at.start, at.name)
    part = tokens[max((k for k, t in enumerate(tokens) if t.text == "&"), default=-1) + 1:]
    written = frozenset(t.text for t in part if t.text in TIMING)
    named = [t.text for k, t in enumerate(part) if t.kind == "name" and t.text not in
             KEYWORDS and not (k and part[k - 1].end == t.start)]  # (not a unit)
    if "NUMBER" in allowed and last not in KEYWORDS and tokens[-1].kind == "name":
        return Place("named", at.start, last, written)
    if allowed & {"OVER", "STAGGER", "THROUGH"}:
        return Place("timing", at.start, named[-1] if named else "", written)
    return Place("nothing", at.start)
