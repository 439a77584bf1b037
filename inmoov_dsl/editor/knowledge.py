"""What the compiler knows of a name, for an editor (pure): what a word under the cursor
is (hover), where it is defined and written (definition, references), the words that
may be typed (completion), and a file's outline."""

from __future__ import annotations

import re
from pathlib import Path

from ..compiling.compiler import compile_program
from ..compiling.names import Gesture, Group, NameTable, Pose, Servo
from ..compiling.robot import profile_for
from ..errors import GestError, Pos
from ..language.load import load
from ..language.program import Program
from ..language.syntax import KEYWORDS
from ..profiles.data import Profile
from ..profiles.profile import profiles_with

WORD = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
UNITS = ("s", "ms")


def _program(text: str, path: str) -> tuple[Program, Profile, NameTable] | None:
    try:
        program = load(str(Path(path)), text)
        profile = profile_for(program)
        return program, profile, NameTable(program, profile, profiles_with)
    except GestError:
        return None


def word_at(text: str, line: int, column: int) -> str | None:
    """The name at 0-based ``line`` and ``column`` of ``text``, or None."""
    lines = text.split("\n")
    if not 0 <= line < len(lines):
        return None
    for match in WORD.finditer(lines[line]):
        if match.start() <= column <= match.end():
            return match.group()
    return None


def hover(text: str, path: str, line: int, column: int) -> str | None:
    """What the name at ``line``, ``column`` (0-based) is, in words (Markdown), or None."""
    word = word_at(text, line, column)
    found = _program(text, path) if word else None
    if found is None:
        return None
    program, profile, names = found
    entity = names.get(word)
    if isinstance(entity, Servo):
        s = profile.servos[entity.index]
        board = next(b for b in profile.boards if b.id == s.board)
        return (f"**servo {s.name}** (profile {profile.name}): board {board.id} "
                f"({board.name}), pin {s.pin}; values {s.lo}..{s.hi}, rest {s.rest}; at "
                f"most {s.max_velocity:,.0f} deg/s, {s.max_acceleration:,.0f} deg/s², "
                f"{s.max_jerk:,.0f} deg/s³")
    if isinstance(entity, Group):
        return f"**group {word}**: {', '.join(entity.members)}"
    if isinstance(entity, Pose):
        targets = ", ".join(f"{t.name.text} {t.value}" if t.value is not None
                            else t.name.text for t in entity.node.targets)
        return f"**pose {word}**: {targets}"
    if isinstance(entity, Gesture):
        try:
            compiled, plan = compile_program(program, word, profile)
        except GestError as exc:
            return f"**gesture {word}**: does not compile: {exc.first.message}"
        steps = len(plan.steps)
        return (f"**gesture {word}**: {steps} step{'' if steps == 1 else 's'}, "
                f"{compiled.duration:.2f} s as planned")
    return None


def completions(text: str, path: str) -> list[tuple[str, str]]:
    """(word, what it is) of every name in scope (servos, groups, poses, gestures),
    the keywords and the units."""
    found = _program(text, path)
    out: list[tuple[str, str]] = []
    if found is not None:
        for name, entity in sorted(found[2].entries().items()):
            out.append((name, type(entity).__name__.lower()))
    out += [(k, "keyword") for k in sorted(KEYWORDS)]
    out += [(u, "unit") for u in UNITS]
    return out


def definition(text: str, path: str, line: int, column: int) -> Pos | None:
    """Where the group, pose or gesture under the cursor is defined (this file, a file
    it uses, the library), or None."""
    word = word_at(text, line, column)
    found = _program(text, path) if word else None
    return None if found is None else found[0].names().get(word)


def references(text: str, path: str, line: int, column: int) -> list[tuple[int, int, int]]:
    """(line, column, width), 0-based, of every place in ``text`` the name under the
    cursor is written (comments and strings left out)."""
    word = word_at(text, line, column)
    if word is None:
        return []
    out = []
    for k, row in enumerate(text.split("\n")):
        code = re.sub(r'"[^"]*"', lambda m: " " * len(m.group()), row.split("#", 1)[0])
        out += [(k, m.start(), len(word)) for m in WORD.finditer(code) if m.group() == word]
    return out


def outline(text: str, path: str) -> list[tuple[str, str, Pos]]:
    """(name, kind, where) of each group, pose and gesture the file itself defines, in
    the file's order."""
    found = _program(text, path)
    if found is None:
        return []
    program, here = found[0], str(Path(path))
    items = [(name, kind, node.name.pos) for kind, table in (
        ("group", program.groups), ("pose", program.poses), ("gesture", program.gestures))
        for name, node in table.items() if node.name.pos.file == here]
    return sorted(items, key=lambda item: (item[2].line, item[2].column))
