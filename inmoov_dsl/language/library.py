"""The gesture library: where gestures are found, which exist, and what each does.

The search path works like ``PATH``: ``--lib`` directories, the directories of
``GEST_PATH`` (separated like ``PATH``), ``./gestures``, then the library shipped with
the package; the first directory that defines a name wins, and the same name further on
is shadowed (``gestc list`` says so). The same directory or file reached twice is read
once. A name defined in two files of one directory is an error naming both. A file that
does not parse is skipped with a warning naming it, unless the gesture asked for is in
it. A gesture's description is the comment block right above its name; its first line
is the summary ``gestc list --long`` shows.
"""

from __future__ import annotations

import os
import re
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path

from ..errors import Diagnostic, GestError, decode_utf8, did_you_mean
from ..resources import library_dir
from . import syntax as ast
from .parse import parse

ENV = "GEST_PATH"


@dataclass(frozen=True)
class Entry:
    """One library gesture: where it is defined and what it does."""

    name: str
    path: Path
    line: int
    description: str  #: the first line of the comment block above it ("" if none)
    shadows: tuple[Path, ...] = ()  #: files further down the path that define it too


@dataclass(frozen=True)
class Library:
    """What the search path holds: the gestures (first definition wins) and the files
    that do not parse."""

    entries: dict[str, Entry]
    broken: dict[Path, GestError] = field(default_factory=dict)

    def warnings(self) -> list[Diagnostic]:
        """One warning per file skipped, at the place it stops parsing."""
        out = []
        for path, error in self.broken.items():
            first = error.first
            out.append(replace(first, severity="warning",
                               message=f"skipped {path.name}, it does not parse: "
                               f"{first.message}"))
        return out


def library_dirs(extra: Iterable[str | os.PathLike] = (),
                 env: str | None = None, cwd: str | os.PathLike | None = None) -> list[Path]:
    """The directories searched for gestures and for ``use`` imports, first to last.

    ``extra`` (``--lib``) must exist; ``GEST_PATH`` entries and ``./gestures`` are used
    when they do. Each directory appears once, however it is named.
    """
    dirs: list[Path] = []
    for d in extra:
        if not Path(d).is_dir():
            raise GestError(Diagnostic("error", f"library directory '{d}' not found",
                                       hint="--lib takes a directory of .gest files"))
        dirs.append(Path(d))
    value = os.environ.get(ENV, "") if env is None else env
    dirs += [Path(d) for d in value.split(os.pathsep) if d and Path(d).is_dir()]
    local = Path(cwd if cwd is not None else os.getcwd()) / "gestures"
    if local.is_dir():
        dirs.append(local)
    dirs.append(library_dir())
    unique: dict[str, Path] = {}
    for d in dirs:
        unique.setdefault(os.path.normcase(os.path.realpath(d)), d)
    return list(unique.values())


def library_files(dirs: Sequence[Path] | None = None) -> list[Path]:
    """Every .gest file of the library directories, in search order, each file once."""
    files: dict[str, Path] = {}
    for d in (dirs if dirs is not None else library_dirs()):
        for p in sorted(Path(d).glob("*.gest")):
            files.setdefault(os.path.normcase(os.path.realpath(p)), p)
    return list(files.values())


def scan(dirs: Sequence[Path] | None = None) -> Library:
    """The gestures of the search path (imports not counted): the first directory that
    defines a name wins; two files of one directory defining it is an error."""
    found: dict[str, Entry] = {}
    broken: dict[Path, GestError] = {}
    for path in library_files(dirs):
        try:
            text = decode_utf8(path.read_bytes(), str(path))  # without a BOM
            module = parse(text, str(path))
        except GestError as exc:
            broken[path] = exc
            continue
        except (OSError, UnicodeDecodeError) as exc:
            broken[path] = GestError(Diagnostic("error", f"cannot read {path}: {exc}"))
            continue
        lines = [row.rstrip("\r") for row in text.split("\n")]  # as the parser counts
        for item in module.items:
            if not isinstance(item, ast.GestureDef):
                continue
            name = item.name.text
            if name in found:
                first = found[name].path
                if first.parent == path.parent and first != path:
                    raise GestError(Diagnostic(
                        "error", f"gesture '{name}' is defined in two library files of "
                        f"{first.parent}: {first.name} and {path.name}",
                        hint="rename one of them"))
                if first != path:
                    found[name] = replace(found[name], shadows=(*found[name].shadows, path))
                continue
            line = item.name.pos.line
            found[name] = Entry(name, path, line, describe(lines, line, name))
    return Library(found, broken)


def scan_library(dirs: Sequence[Path] | None = None) -> dict[str, Entry]:
    """Gesture name -> its Entry, for every gesture the search path defines (the first
    definition of each name; imports not counted)."""
    return scan(dirs).entries


def load_library(dirs: Sequence[Path] | None = None) -> dict[str, Path]:
    """Gesture name -> the library file that defines it (imports not counted)."""
    return {name: entry.path for name, entry in scan_library(dirs).items()}


def describe(lines: Sequence[str], line: int, name: str = "") -> str:
    """The summary of the item at ``line`` (from 1): the first line of the comments
    right above it, without a leading ``name:``."""
    top = comments_above(lines, line)
    if top == line:
        return ""
    first = lines[top - 1].strip().lstrip("#").strip()
    if name and first.startswith(f"{name}:"):
        first = first[len(name) + 1:].strip()
    return first


def comments_above(lines: Sequence[str], line: int) -> int:
    """The first line (from 1) of the comment block right above line ``line``, which
    describes the item there; ``line`` itself when no comment is right above it."""
    top = line
    while top > 1 and lines[top - 2].lstrip().startswith("#"):
        top -= 1
    return top


def file_meant(target: str, dirs: Sequence[Path] | None = None) -> str:
    """The file a path on the command line means: itself if it is there; ``NAME.gest``
    for ``NAME``; a library file of that name (``peace.gest``) for a bare file name. One
    that is nowhere is an error, with a hint at the gesture the user may mean."""
    if target == "-" or os.path.exists(target):
        return target
    if not target.endswith(".gest") and os.path.isfile(target + ".gest"):
        return target + ".gest"
    name = os.path.basename(target)
    name = name if name.endswith(".gest") else f"{name}.gest"
    if os.path.basename(target) == target:
        for d in (dirs if dirs is not None else library_dirs()):
            if (Path(d) / name).is_file():
                return str(Path(d) / name)
    stem = name[:-len(".gest")]
    known = scan(dirs).entries
    close = did_you_mean(stem, known)
    hint = (f"'{stem}' is a library gesture: give its name alone, {stem}" if stem in known
            else close and f"{close} (a library gesture: give its name alone)")
    raise GestError(Diagnostic("error", f"cannot find '{target}'", hint=hint))


def find_gesture(target: str, gesture: str | None, dirs: Sequence[Path] | None = None,
                 warn: Callable[[Diagnostic], None] | None = None
                 ) -> tuple[str, str | None]:
    """What a command line names: a .gest file (and ``gesture`` in it), or a library
    gesture (its file, and that gesture). ``NAME`` is the file ``NAME.gest`` here when
    there is one (and no file ``NAME``), before the library's gesture of that name.
    Library files that do not parse go to ``warn``, unless the gesture asked for is in
    one of them: then its error is the answer."""
    if os.path.exists(target) or target.endswith(".gest") or os.sep in target \
            or "/" in target or os.path.isfile(target + ".gest"):
        return file_meant(target, dirs), gesture
    library = scan(dirs)
    if target in library.entries:
        for d in library.warnings():
            if warn is not None:
                warn(d)
        return str(library.entries[target].path), gesture or target
    defines = re.compile(rf"^{re.escape(target)}\s*:", re.M)
    for path, error in library.broken.items():
        try:
            if defines.search(path.read_text(encoding="utf-8-sig", errors="replace")):
                raise error
        except OSError:
            continue
    hint = did_you_mean(target, library.entries) or \
        "give a .gest file or a name from 'gestc list'"
    raise GestError(Diagnostic("error", f"no file or library gesture '{target}'", hint=hint))
