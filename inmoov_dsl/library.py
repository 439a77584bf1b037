"""The gesture library: where gestures are found, which exist, and what each does.

Gestures come from, in this order: ``--lib`` directories, the directories of
``GEST_PATH`` (separated like ``PATH``), ``./gestures``, and the library shipped with
the package. A gesture name defined in two of their files is an error naming both.
A gesture's description is the comment block right above its name; its first line is
the summary ``gestc list --long`` shows.
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path

from . import syntax as ast
from .errors import Diagnostic, GestError, did_you_mean
from .parse import parse
from .resources import library_dir

ENV = "GEST_PATH"


@dataclass(frozen=True)
class Entry:
    """One library gesture: where it is defined and what it does."""

    name: str
    path: Path
    line: int
    description: str  #: the first line of the comment block above it ("" if none)


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
    """Every .gest file of the library directories."""
    return [p for d in (dirs if dirs is not None else library_dirs())
            for p in sorted(Path(d).glob("*.gest"))]


def scan_library(dirs: Sequence[Path] | None = None) -> dict[str, Entry]:
    """Gesture name -> its Entry, for every gesture the library files define
    (imports not counted)."""
    found: dict[str, Entry] = {}
    for path in library_files(dirs):
        text = path.read_text(encoding="utf-8")
        lines = text.splitlines()
        for item in parse(text, str(path)).items:
            if not isinstance(item, ast.GestureDef):
                continue
            name = item.name.text
            if name in found:
                raise GestError(Diagnostic(
                    "error", f"gesture '{name}' is defined in two library files: "
                    f"{found[name].path} and {path}", hint="rename one of them"))
            line = item.name.pos.line
            found[name] = Entry(name, path, line, describe(lines, line, name))
    return found


def load_library(dirs: Sequence[Path] | None = None) -> dict[str, Path]:
    """Gesture name -> the library file that defines it (imports not counted)."""
    return {name: entry.path for name, entry in scan_library(dirs).items()}


def describe(lines: Sequence[str], line: int, name: str = "") -> str:
    """The summary of the item at ``line`` (from 1): the first line of the comments
    right above it, without a leading ``name:``."""
    k = line - 2
    while k >= 0 and lines[k].lstrip().startswith("#"):
        k -= 1
    if k + 1 > line - 2:
        return ""
    first = lines[k + 1].strip().lstrip("#").strip()
    if name and first.startswith(f"{name}:"):
        first = first[len(name) + 1:].strip()
    return first


def find_gesture(target: str, gesture: str | None, dirs: Sequence[Path] | None = None
                 ) -> tuple[str, str | None]:
    """What a command line names: a .gest file (and ``gesture`` in it), or a library
    gesture (its file, and that gesture)."""
    if os.path.exists(target) or target.endswith(".gest") or os.sep in target \
            or "/" in target:
        return target, gesture
    library = scan_library(dirs)
    if target in library:
        return str(library[target].path), gesture or target
    hint = did_you_mean(target, library) or "give a .gest file or a name from 'gestc list'"
    raise GestError(Diagnostic("error", f"no file or library gesture '{target}'", hint=hint))
