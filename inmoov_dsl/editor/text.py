"""The words of a line of gesture code, as an editor points at them (pure)."""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass

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
STARTS = frozenset({"step", "part", "target", "pose"})  #: where a step's target starts


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
    ``Place``. In a comment or a string: ``nothing``."""
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
    start = column
    if tokens and tokens[-1].end == len(prefix) and tokens[-1].kind in ("name", "number"):
        typed = tokens.pop()
        start = typed.start - len(head)
        if typed.kind == "number" or (tokens and tokens[-1].kind == "number"
                                      and tokens[-1].end == typed.start):
            durations = {"over", "stagger", "wait", "hold"}
            before = tokens[-1 if typed.kind == "number" else -2:]
            ok = bool(before) and before[0].text in durations
            return Place("unit", column if typed.kind == "number" else start) if ok \
                else Place("nothing", start)
    if prefix[:1] in (" ", "\t"):
        return _step(tokens, Place("step", start, _defining(lines, line)))
    return _top(tokens, Place("top", start, first=not any(
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


def _top(tokens: list[Token], at: Place) -> Place:
    """A line that is not indented: ``robot``, ``use``, ``group``, ``pose`` or a
    gesture's name and its step."""
    if not tokens:
        return at
    nothing = Place("nothing", at.start)
    first = tokens[0].text
    colon = next((k for k, t in enumerate(tokens) if t.text == ":"), None)
    if first == "robot":
        return Place("profile", at.start) if len(tokens) == 1 else nothing
    if colon is None or tokens[0].kind != "name":
        return nothing
    rest = tokens[colon + 1:]
    if first == "group":
        return Place("member", at.start) if not rest or rest[-1].text == "," else nothing
    defined = tokens[1].text if colon == 2 and tokens[1].kind == "name" else ""
    if first == "pose":
        return _step(rest, Place("pose", at.start, defined))
    if first in KEYWORDS or colon != 1:
        return nothing
    return _step(rest, Place("step", at.start, first))


def _step(tokens: list[Token], at: Place) -> Place:
    """The place after ``tokens``, the words of a step (or a pose's targets) so far,
    starting at ``at``."""
    state, name, written = at.kind, "", frozenset[str]()
    pose = at.kind == "pose"
    for token in tokens:
        state = _next(state, token, pose)
        if token.text == "&":
            written = frozenset()
        elif state == "named":
            name = token.text
        elif token.text in TIMING and state in ("over", "timed"):
            written |= {token.text}
    if state in STARTS or state == "side":
        return Place(state, at.start, at.name)
    if state in ("waited", "overed"):
        return Place("unit", at.start)
    if state in ("named", "valued", "timed") and not pose:
        return Place("timing" if state != "named" else "named", at.start, name, written)
    return Place("nothing", at.start)


def _next(state: str, token: Token, pose: bool) -> str:
    """The state of a step after ``token`` (``nothing``: nothing may follow)."""
    kind, text = token.kind, token.text
    if state in STARTS:
        if kind != "name":
            return "nothing"
        wanted = {"repeat": "repeat", "wait": "wait", "hold": "wait", "say": "say",
                  "left": "side", "right": "side"}.get(text)
        allowed = {"step": ("repeat", "wait", "say", "side"), "part": ("say", "side")}
        if wanted is not None:
            return wanted if wanted in allowed.get(state, ()) else "nothing"
        return "nothing" if text in KEYWORDS else "named"
    simple = {("repeat", "number"): "count", ("say", "string"): "said",
              ("wait", "number"): "waited", ("waited", "name"): "end",
              ("over", "number"): "overed", ("named", "number"): "valued"}
    if (state, kind) in simple:
        return simple[(state, kind)]
    if state == "count" and text == ":":
        return "step"
    if state == "side":
        return "called" if kind == "name" and text not in KEYWORDS else "nothing"
    if text == "&" and not pose and state in ("said", "called", "named", "valued", "timed",
                                              "overed"):
        return "part"
    if text == "," and state in ("named", "valued"):
        return "pose" if pose else "target"
    if not pose and kind == "name" and state in ("named", "valued", "timed", "overed"):
        if state == "overed" and text not in TIMING:
            return "timed"  # the unit
        return {"over": "over", "stagger": "over", "through": "timed"}.get(text, "nothing")
    return "nothing"
