"""What the compiler knows of the text under the cursor, for an editor (pure, over an
Analysis): what a word or a step is (hover), where a name is defined (definition), the
words that may be typed (completion), and a file's outline."""

from __future__ import annotations

import os
import re
from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path

from ..boards import TABLES
from ..compiling.compiler import compile_program
from ..compiling.names import Gesture, Group, Pose, Servo
from ..compiling.names import Place as Located
from ..compiling.reaching import servos_for
from ..errors import GestError, Pos
from ..language.catalog import scanned
from ..language.library import Entry, library_dirs
from ..language.load import GEST_SUFFIX
from ..profiles.profile import builtin_profiles
from ..voice.hearing import WAV_SUFFIX
from . import places
from .analysis import Analysis
from .lines import rows
from .text import TIMING, Place, code, place, string_at, word_at
from .timing import label, step_times

UNITS = ("s", "ms")
USE = re.compile(r"^\s*use\s*$")
SAY = re.compile(r"(^|[\s&:])say\s*$")


def hover(found: Analysis, line: int, column: int) -> str | None:
    """What is at ``line``, ``column`` (0-based), in words (Markdown): a name (a servo, a
    group, a pose, a gesture), a ``use`` path, a ``say``, or the step of that line
    (when it plays, and whether it was stretched); None when nothing is known."""
    lines = rows(found.text)
    if not 0 <= line < len(lines) or found.program is None:
        return None
    said = _string(found, lines[line], column)
    if said is not None:
        return said
    word = word_at(found.text, line, column)
    parts = [what] if word and (what := _entity(found, word)) else []
    if (item := places.at(found, line, column)) is not None:
        parts.insert(0, f"**{item.label}**: {item.text}")
    step = step_times(found).get(line)
    if step is not None and column >= step.column:
        parts.append(f"**step of {step.gesture}**: {label(step)[2:]}")
    return "\n\n".join(parts) or None


def _entity(found: Analysis, word: str) -> str | None:
    entity = found.names.get(word) if found.names else None
    profile = found.profile
    if isinstance(entity, Servo):
        s = profile.servos[entity.index]
        board = next(b for b in profile.boards if b.id == s.board)
        noun = TABLES[board.kind].noun  # a Maestro's or a PCA9685's: a channel
        place = f"{noun} {s.pin}" if s.pin is not None else f"no {noun} given"
        return (f"**servo {s.name}** (profile {profile.name}): board {board.id} "
                f"({board.name}), {place}; values {s.lo}..{s.hi}, rest {s.rest}; at "
                f"most {s.max_velocity:,.0f} deg/s, {s.max_acceleration:,.0f} deg/s², "
                f"{s.max_jerk:,.0f} deg/s³")
    if isinstance(entity, Group):
        return f"**group {word}**: {', '.join(entity.members)}"
    if isinstance(entity, Located):
        where = ", ".join(f"{c * 1000:g}" for c in entity.xyz or ())
        whose = "" if entity.pos else f" (profile {profile.name})"
        return f"**place {word}**{whose}: ({where}) mm, x forward, y left, z up"
    if isinstance(entity, Pose):
        targets = ", ".join(f"{t.name.text} {t.value}" if t.value is not None
                            else t.name.text for t in entity.node.targets)
        return f"**pose {word}**: {targets}"
    if isinstance(entity, Gesture):
        plan = found.plans.get(word)
        if plan is None:
            try:
                plan = compile_program(found.program, word, profile)[1]
            except GestError as exc:
                return f"**gesture {word}**: does not compile: {exc.first.message}"
        steps = len(plan.steps)
        return (f"**gesture {word}**: {steps} step{'' if steps == 1 else 's'}, "
                f"{plan.duration:.2f} s as planned")
    return None


def _string(found: Analysis, line: str, column: int) -> str | None:
    """A ``use`` path: the file it is; a ``say``: its sound's length."""
    inside = string_at(line, column)
    if inside is None:
        return None
    before = line[:inside[0] - 1]
    if USE.match(before):
        used = [f for f in found.program.texts if f != found.path
                and Path(f).as_posix().endswith(inside[2])]
        return f"**use**: {used[0]}" if used else None
    if SAY.search(before):
        for plan in found.plans.values():
            for _start, speech in plan.sounds:
                if speech.sound.source == inside[2]:
                    where = f" ({speech.sound.path})" if speech.sound.path else ""
                    return f"**say**: {speech.sound.duration:.2f} s of sound{where}"
    return None


@dataclass(frozen=True)
class Completion:
    """A word that may be typed: what it is, in a word (``servo``, ``gesture``...), a
    longer ``detail``, the library file a ``use`` line must bring in for it, and the
    column where the word it replaces starts (None: a file's name, in its string)."""

    word: str
    what: str
    detail: str
    use: str | None = None
    start: int | None = None


#: what each place offers (``text.Place``): the kinds of names, and the keywords
NAMES = {"member": ("servo",), "pose": ("servo", "group", "pose"),
         "target": ("servo", "group", "pose"), "step": ("servo", "group", "pose", "gesture"),
         "part": ("servo", "group", "pose", "gesture"), "side": ("gesture",),
         "place": ("place",)}
WORDS = {"step": ("hold", "left", "look", "repeat", "right", "say", "wait"),
         "part": ("left", "look", "right", "say")}


def completions(found: Analysis, line: int, column: int,
                lib: Sequence[str] = ()) -> list[Completion]:
    """What may be typed at ``line``, ``column``, as the grammar allows there
    (``text.place``): in a ``use`` string the gesture files beside the file and in the
    library, in a ``say`` string the sounds (.wav) there; where a step starts the names
    in scope (servos, groups, poses, gestures but the one being defined), the library's
    gestures not yet in scope (each with its ``use`` line) and the step keywords (``say``
    on a robot with a voice, ``left`` and ``right`` on one with two sides); after
    a value the timing keywords, after a duration's number the units; at the start of a
    top-level line its keywords; after ``robot`` the profiles."""
    lines = rows(found.text)
    row = lines[line] if 0 <= line < len(lines) else ""
    inside = string_at(row, column)
    if inside is not None:
        before = row[:inside[0] - 1]
        if USE.match(before):
            return [Completion(f, "file", "gesture file") for f in
                    _files(found.path, GEST_SUFFIX, lib) if f != Path(found.path).name]
        if SAY.search(before):
            return [Completion(f, "sound", "sound file") for f in
                    _files(found.path, WAV_SUFFIX, lib)]
        return []
    at = place(found.text, line, column)
    return [replace(c, start=at.start) for c in _offered(found, at, lib)]


def _offered(found: Analysis, at: Place, lib: Sequence[str]) -> list[Completion]:
    """What ``at`` offers (see ``completions``)."""
    if at.kind in NAMES:
        robot = found.profile
        unable = set() if robot is None else {
            *(() if robot.sides else ("left", "right")), *(() if robot.voice else ("say",)),
            *(("look",) if servos_for(robot, "look")[1] else ())}
        return _names(found, NAMES[at.kind], at.name, lib) + [
            Completion(k, "keyword", "keyword") for k in WORDS.get(at.kind, ())
            if k not in unable]
    if at.kind == "top":
        return [Completion(k, "keyword", "keyword") for k in ("group", "place", "pose",
                                                              "robot", "use")
                if k != "robot" or at.first]
    if at.kind == "profile":
        return [Completion(p, "profile", "robot profile") for p in builtin_profiles()]
    if at.kind == "unit":
        return [Completion(u, "unit", "unit") for u in UNITS]
    if at.kind == "named" and (
            isinstance(_scope(found).get(at.name), Servo | Group | Gesture)
            or at.name in dict(_library(tuple(map(str, library_dirs(list(lib))))))):
        return []  # a value follows a servo or a group; a call takes no timing
    if at.kind in ("named", "timing"):
        return [Completion(k, "keyword", "keyword") for k in TIMING if k not in at.written
                and not {k, *at.written} >= {"stagger", "through"}]
    return []


def _names(found: Analysis, kinds: Sequence[str], defining: str, lib: Sequence[str]
           ) -> list[Completion]:
    """The names in scope of ``kinds`` (but ``defining``), sorted; with gestures, the
    library's not yet in scope."""
    known = _scope(found)
    out = [Completion(name, what, what) for name, entity in sorted(known.items())
           if (what := type(entity).__name__.lower()) in kinds and name != defining]
    if "gesture" in kinds and found.program is not None:
        for name, entry in sorted(_library(tuple(map(str, library_dirs(list(lib)))))):
            if name not in known and name != defining:
                out.append(Completion(name, "gesture", f"library gesture, in "
                                      f"{entry.path.name}: {entry.description}".rstrip(": "),
                                      entry.path.name))
    return out


def _scope(found: Analysis) -> dict[str, Servo | Group | Pose | Gesture | Located]:
    """Every name in scope -> what it is: the analysis's names, or, when they do not
    resolve (two things of one name), the robot's and the program's as they are."""
    if found.names is not None:
        return found.names.entries()
    out: dict[str, Servo | Group | Pose | Gesture | Located] = {}
    if found.profile is not None:
        out.update((n, Servo(n, i)) for i, n in enumerate(found.profile.names))
        out.update((n, Group(n, tuple(m))) for n, m in found.profile.groups.items())
        out.update((n, Located(n, xyz)) for n, xyz in found.profile.places.items())
    if found.program is not None:
        program = found.program
        out.update((n, Group(n, tuple(m.text for m in g.members)))
                   for n, g in program.groups.items())
        out.update((n, Pose(node)) for n, node in program.poses.items())
        out.update((n, Located(n, node.point.xyz, node.name.pos))
                   for n, node in program.places.items())
        out.update((n, Gesture(node)) for n, node in program.gestures.items())
    return out


def _library(dirs: tuple[str, ...]) -> list[tuple[str, Entry]]:
    """The library's gestures along ``dirs`` (``catalog.scanned``: read again only when
    one of its files changed; a completion asks at every key)."""
    return list(scanned(dirs).entries.items())


def _files(path: str, suffix: str, lib: Sequence[str]) -> list[str]:
    """The names of the files ending in ``suffix`` beside ``path`` and along the
    library's folders, as a ``use`` or a ``say`` finds them."""
    names: dict[str, None] = {}
    for folder in [os.path.dirname(path) or ".", *map(str, library_dirs(list(lib)))]:
        try:
            entries = sorted(os.listdir(folder))
        except OSError:
            continue
        names.update((e, None) for e in entries if e.lower().endswith(suffix))
    return list(names)


def definition(found: Analysis, line: int, column: int) -> Pos | None:
    """Where the group, pose or gesture under the cursor is defined (this file, a file
    it uses, the library), or None."""
    word = word_at(found.text, line, column)
    if word is None or found.program is None:
        return None
    return found.program.names().get(word)


def references(text: str, word: str) -> list[tuple[int, int, int]]:
    """(line, column, width), 0-based, of every place in ``text`` that writes the name
    ``word`` (comments and strings left out)."""
    pattern = re.compile(rf"(?<![A-Za-z0-9_]){re.escape(word)}(?![A-Za-z0-9_])")
    return [(k, m.start(), len(word)) for k, row in enumerate(rows(text))
            if word in row for m in pattern.finditer(code(row))]


def outline(found: Analysis) -> list[tuple[str, str, Pos]]:
    """(name, kind, where) of each group, pose and gesture the file itself defines, in
    the file's order."""
    program = found.program
    if program is None:
        return []
    items = [(name, kind, node.name.pos) for kind, table in (
        ("group", program.groups), ("pose", program.poses), ("gesture", program.gestures))
        for name, node in table.items() if node.name.pos.file == found.path]
    return sorted(items, key=lambda item: (item[2].line, item[2].column))
