"""Every token of a text with what it is, for an editor's semantic highlighting (pure,
over an Analysis): keywords, numbers, units, strings, comments, the robot's profile,
and each name as what the compiler resolves it to (a servo, a group, a pose, a
gesture), marked where it is defined."""

from __future__ import annotations

import re

from ..compiling.names import Gesture, Group, Place, Pose, Servo
from ..language.syntax import KEYWORDS
from ..language.tree import LENGTHS
from .analysis import Analysis
from .knowledge import UNITS
from .lines import rows
from .text import NUMBER, PROFILE, STRING

#: the token types, in the order the editor is told them (the legend)
TYPES = ("keyword", "number", "string", "comment", "namespace", "variable", "enum",
         "enumMember", "function", "property")
MODIFIERS = ("declaration", "defaultLibrary")
KIND = {Servo: "variable", Group: "enum", Pose: "enumMember", Gesture: "function",
        Place: "property"}
TOKEN = re.compile(rf'(?P<comment>#.*)|(?P<string>{STRING.pattern})'
                   rf"|(?P<number>{NUMBER})(?P<unit>[A-Za-z_]+)?|(?P<word>{PROFILE})")
DEFINES = re.compile(r"^(\s*(group|pose)\s+)?([A-Za-z_][A-Za-z0-9_]*)\s*:")


def tokens(found: Analysis) -> list[tuple[int, int, int, str, tuple[str, ...]]]:
    """(line, column, length, type, modifiers), 0-based, of every token that has a
    type, in the text's order."""
    names = found.names
    program = found.program
    defined_here = set() if program is None else {
        n for n, p in program.names().items() if p.file == found.path}
    out = []
    for k, row in enumerate(rows(found.text)):
        defines = DEFINES.match(row)
        robot = row.lstrip().startswith("robot")
        for m in TOKEN.finditer(row):
            kind, start, text = m.lastgroup, m.start(), m.group()
            if kind in ("comment", "string"):
                out.append((k, start, len(text), kind, ()))
            elif m.group("number") is not None:
                number = m.group("number")
                out.append((k, start, len(number), "number", ()))
                if m.group("unit") in UNITS or m.group("unit") in LENGTHS:
                    out.append((k, start + len(number), len(m.group("unit")), "keyword", ()))
            elif text in KEYWORDS:
                out.append((k, start, len(text), "keyword", ()))
            elif robot:
                out.append((k, start, len(text), "namespace", ()))
            else:
                entity = names.get(text) if names is not None else None
                if entity is None:
                    continue
                mods = ()
                if defines is not None and start == defines.start(3):
                    mods = ("declaration",)
                elif text not in defined_here:
                    mods = ("defaultLibrary",)
                out.append((k, start, len(text), KIND[type(entity)], mods))
    return out


def encoded(found: list[tuple[int, int, int, str, tuple[str, ...]]]) -> list[int]:
    """``found`` as the protocol sends it: five numbers a token, each place relative to
    the token before."""
    data: list[int] = []
    line = column = 0
    for k, start, length, kind, mods in found:
        data += [k - line, start - column if k == line else start, length, TYPES.index(kind),
                 sum(1 << MODIFIERS.index(m) for m in mods)]
        line, column = k, start
    return data

