"""Load a program: a .gest file and every file it ``use``s, parsed, with its names.

File access goes through an injected ``read`` function, so loading stays testable;
what a ``use`` may open is decided here (docs/security.md).
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from ..errors import Diagnostic, GestError, Pos, SourceMap, decode_utf8
from ..resources import FolderGiven, files_in, read_regular
from ..voice.hearing import Hearing
from . import syntax as ast
from .catalog import Catalog
from .library import library_dirs
from .parse import MAX_SOURCE, parse
from .program import Program

if TYPE_CHECKING:
    from .incremental import Partial

GEST_SUFFIX = ".gest"

Reader = Callable[[str], str]  #: path -> its text
Parser = Callable[[str, str], ast.Module]  #: (text, file) -> its syntax tree
#: (text, file) -> what of it parses and what does not (``incremental.Partial``)
Partly = Callable[[str, str], "Partial"]


def read_text(path: str) -> str:
    """The default reader for ``use``: a UTF-8 file (GestError where it is not UTF-8).
    A file too large to hold at most MAX_SOURCE characters (four bytes each) is a
    GestError before it is read; one that is not a regular file is a ValueError, like a
    NUL in the path."""
    data = read_regular(path, 4 * MAX_SOURCE)
    if len(data) > 4 * MAX_SOURCE:
        raise GestError(Diagnostic(
            "error", f"the file is longer than {MAX_SOURCE:,} characters: it is not read",
            Pos(path, 1, 1), "split it into several files joined with 'use'"))
    return decode_utf8(data, path)


def folder_given(path: str) -> Diagnostic:
    """The error of a folder given where a gesture file was, and the files in it to give
    instead (or a library gesture)."""
    files = files_in(path, GEST_SUFFIX)
    hint = (f"give a {GEST_SUFFIX} file in it: {', '.join(files)}" if files else
            f"give a {GEST_SUFFIX} file, or a library gesture's name (gestc list)")
    return Diagnostic("error", f"'{path}' is a folder, not a gesture file", hint=hint)


def load(path: str, text: str | None = None, read: Reader = read_text,
         search: Sequence[str] | None = None, first_wins: bool = False,
         parser: Parser = parse, partly: Partly | None = None) -> Program:
    """Parse a .gest file (or ``text`` under that name) with its imports
    (``first_wins``: a name defined again by a later file is shadowed, not an error;
    ``parser``: ``parse``, or one that remembers the blocks it has seen; ``partly``: the
    file itself is loaded with what of it parses, its syntax errors kept in the program,
    ``incremental.BlockParser.parse_partly``)."""
    dirs = [str(d) for d in library_dirs()] if search is None else list(search)
    try:
        return load_program(path, read, dirs, text, first_wins, parser, partly)
    except FileNotFoundError:
        raise GestError(Diagnostic("error", f"cannot find '{path}'")) from None
    except FolderGiven:
        raise GestError(folder_given(path)) from None
    except (OSError, ValueError) as exc:  # not UTF-8, too large, a NUL in the name
        raise GestError(Diagnostic("error", f"cannot read '{path}': {exc}",
                                   Pos(path, 1, 1))) from None


def load_program(path: str, read: Reader, search: Sequence[str] = (),
                 text: str | None = None, first_wins: bool = False,
                 parser: Parser = parse, partly: Partly | None = None) -> Program:
    """Parse ``path`` (or ``text`` under that name) and every file it ``use``s.

    Imports are looked up beside the importing file, then in ``search``; each file is
    read once. Duplicate definitions are errors naming both places, unless
    ``first_wins`` (a library along its search path): then a name already defined by
    another file is shadowed, and only one file defining it twice is an error. Loaded
    ``partly`` (to tell every error: ``gestc check``, the editor), a name defined twice
    is an error among the program's syntax errors, its first definition kept, so the
    rest of the file is checked too.
    """
    program = Program(path, in_library=Catalog(tuple(search)), hear=Hearing(search))
    loader = _Loader(program, read, search, first_wins, parser, partly)
    loader.visit(path, read(path) if text is None else text, True)
    if loader.errors and partly is None:
        raise GestError(loader.errors)
    program.syntax = (*program.syntax, *loader.errors)
    return loader.program


class _Loader:
    """What loading one program keeps track of: the files seen, the names defined."""

    def __init__(self, program: Program, read: Reader, search: Sequence[str],
                 first_wins: bool, parser: Parser = parse, partly: Partly | None = None):
        self.program, self.parse, self.partly = program, parser, partly
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
        if is_root and self.partly is not None:
            module, error, program.broken, program.flawed = self.partly(source, file)
            program.syntax = () if error is None else error.diagnostics
        else:
            module = self.parse(source, file)
        if module.robot is not None:
            program.robots[file] = module.robot
        for item in module.items:
            match item:
                case ast.Use():
                    found, text = _find_import(item, file, self.search, self.read,
                                               program.sources)
                    if _key(found) not in self.seen:
                        self.visit(found, text, False)
                case ast.Robot():
                    pass
                case _ if self._defines(item, file):
                    self._add(item, is_root)

    def _defines(self, item: Definition, file: str) -> bool:
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

    def _add(self, item: Definition, is_root: bool) -> None:
        program, name = self.program, item.name.text
        match item:
            case ast.GestureDef():
                program.gestures[name] = item
                if is_root:
                    program.own.append(name)
            case ast.PoseDef():
                program.poses[name] = item
            case ast.PlaceDef():
                program.places[name] = item
            case ast.GroupDef():
                program.groups[name] = item


Definition = ast.GroupDef | ast.PoseDef | ast.PlaceDef | ast.GestureDef


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
