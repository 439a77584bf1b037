"""Load a program: a .gest file and every file it ``use``s, parsed, with its names.

File access goes through an injected ``read`` function, so loading stays testable;
what a ``use`` may open is decided here (docs/security.md).
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from . import syntax as ast
from .errors import Diagnostic, GestError, Pos, SourceMap
from .parse import parse

GEST_SUFFIX = ".gest"

Reader = Callable[[str], str]  #: path -> its text


@dataclass
class Program:
    """A .gest file with everything it imports, and the names they define."""

    root: str
    sources: SourceMap = field(default_factory=SourceMap)
    texts: dict[str, str] = field(default_factory=dict)
    gestures: dict[str, ast.GestureDef] = field(default_factory=dict)
    poses: dict[str, ast.PoseDef] = field(default_factory=dict)
    groups: dict[str, ast.GroupDef] = field(default_factory=dict)
    own: list[str] = field(default_factory=list)  #: gestures defined in the root file
    search: tuple[str, ...] = ()  #: where its ``use`` lines look, after beside each file
    #: one resolve.Resolver per profile (see ``resolve.resolver``), and the SHA-256 of
    #: every text
    resolvers: dict[int, Any] = field(default_factory=dict, repr=False)
    digests: dict[str, str] = field(default_factory=dict, repr=False)

    def names(self) -> dict[str, Pos]:
        """Every group, pose and gesture the program defines -> where it is defined."""
        found: dict[str, Pos] = {}
        for table in (self.groups, self.poses, self.gestures):
            for name, node in table.items():
                found[name] = node.name.pos
        return found


def load_program(path: str, read: Reader, search: Sequence[str] = (),
                 text: str | None = None, first_wins: bool = False) -> Program:
    """Parse ``path`` (or ``text`` under that name) and every file it ``use``s.

    Imports are looked up beside the importing file, then in ``search``; each file is
    read once. Duplicate definitions are errors naming both places, unless
    ``first_wins`` (a library along its search path): then a name already defined by
    another file is shadowed, and only one file defining it twice is an error.
    """
    loader = _Loader(Program(path, search=tuple(search)), read, search, first_wins)
    loader.visit(path, read(path) if text is None else text, True)
    if loader.errors:
        raise GestError(loader.errors)
    return loader.program


class _Loader:
    """What loading one program keeps track of: the files seen, the names defined."""

    def __init__(self, program: Program, read: Reader, search: Sequence[str],
                 first_wins: bool):
        self.program = program
        self.read = read
        self.search = search
        self.first_wins = first_wins
        self.seen: set[str] = set()
        self.defined: dict[str, Pos] = {}
        self.errors: list[Diagnostic] = []

    def visit(self, file: str, source: str, is_root: bool) -> None:
        """Parse ``file``, define its names and visit the files it uses (once each)."""
        program = self.program
        self.seen.add(_key(file))
        program.sources.add(file, source)
        program.texts[file] = source
        for item in parse(source, file).items:
            match item:
                case ast.Use():
                    found, text = _find_import(item, file, self.search, self.read,
                                               program.sources)
                    if _key(found) not in self.seen:
                        self.visit(found, text, False)
                case _ if self._defines(item, file):
                    self._add(item, is_root)

    def _defines(self, item: ast.GroupDef | ast.PoseDef | ast.GestureDef, file: str) -> bool:
        """Whether ``item`` defines its name: not if shadowed or defined twice."""
        name = item.name.text
        if name not in self.defined:
            self.defined[name] = item.name.pos
            return True
        first = self.defined[name]
        if self.first_wins and first.file != file:
            return False  # shadowed by a file earlier on the search path
        self.errors.append(self.program.sources.error(
            f"'{name}' is defined twice", item.name.pos,
            f"first defined at {first.file}:{first.line}"))
        return False

    def _add(self, item: ast.GroupDef | ast.PoseDef | ast.GestureDef, is_root: bool) -> None:
        program, name = self.program, item.name.text
        match item:
            case ast.GestureDef():
                program.gestures[name] = item
                if is_root:
                    program.own.append(name)
            case ast.PoseDef():
                program.poses[name] = item
            case ast.GroupDef():
                program.groups[name] = item


def _key(file: str) -> str:
    """One spelling for one file, so that it is read once however it is named."""
    return os.path.normcase(os.path.abspath(file))


def _find_import(use: ast.Use, importer: str, search: Sequence[str], read: Reader,
                 sources: SourceMap) -> tuple[str, str]:
    """The file ``use`` names: relative to the importing file's directory, then to each
    directory of the search path (an absolute path as it is). It must be a gesture file,
    its name and (through any symlink) its target's name ending in .gest: so a gesture
    file from someone else cannot make the tools open, or quote a line of, anything else
    (docs/security.md)."""
    if not use.path.endswith(GEST_SUFFIX):
        raise GestError(sources.error(f"use takes a {GEST_SUFFIX} file, not '{use.path}'",
                                      use.pos, f'use "{Path(use.path).stem}{GEST_SUFFIX}"'))
    places = [os.path.join(os.path.dirname(importer), use.path)]
    places += [os.path.join(d, use.path) for d in search]
    for place in places:
        try:
            target = os.path.realpath(place)
            if not target.endswith(GEST_SUFFIX) and os.path.exists(place):
                raise ValueError(f"it links to '{target}', which is not a {GEST_SUFFIX} "
                                 f"file")
            return place, read(place)
        except FileNotFoundError:
            continue
        except (OSError, ValueError) as exc:  # a NUL in the path, not UTF-8, too large
            raise GestError(sources.error(f"cannot read '{place}': {exc}", use.pos)) from None
    raise GestError(sources.error(
        f"cannot find '{use.path}'", use.pos,
        "looked in " + ", ".join(os.path.dirname(p) or "." for p in places)))
