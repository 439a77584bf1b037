"""A program: a .gest file with everything it imports, and the names they define (the
loader, ``load``, makes one)."""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from ..errors import Diagnostic, Pos, SourceMap
from . import syntax as ast
from .catalog import Catalog
from .library import comments_above


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
    #: file -> its robot line (files without one are not here)
    robots: dict[str, ast.Robot] = field(default_factory=dict)
    #: the library along the search path the loader knows (``catalog.Catalog``): the
    #: file (its name) that defines a gesture, or None; every gesture's name. An
    #: unknown name's hint asks it
    in_library: Catalog | None = field(default=None, repr=False, compare=False)
    #: the sound of ``say "text"`` in a file (``voice.hearing.Hearing``): the loader
    #: knows where files are; (text, file, voice, speed, pitch) -> sound
    hear: Callable[..., Any] | None = field(default=None, repr=False, compare=False)
    #: one resolve.Resolver per profile (see ``resolve.resolver``), and the SHA-256 of
    #: every text
    resolvers: dict[int, Any] = field(default_factory=dict, repr=False)
    #: the root file's syntax errors, when it was loaded with what of it parses, and the
    #: names its blocks that do not parse would define (``*``: a robot or use line)
    syntax: tuple[Diagnostic, ...] = ()
    broken: frozenset[str] = frozenset()
    #: the names of the root file's blocks that parse with errors (a value, a unit, a
    #: step's line): read for their names, never planned
    flawed: frozenset[str] = frozenset()
    digests: dict[str, str] = field(default_factory=dict, repr=False)
    places: dict[str, ast.PlaceDef] = field(default_factory=dict)
    _unplayable: frozenset[str] | None = field(default=None, repr=False, compare=False)

    def names(self) -> dict[str, Pos]:
        """Every group, pose, place and gesture the program defines -> where it is
        defined."""
        found: dict[str, Pos] = {}
        for table in (self.groups, self.poses, self.places, self.gestures):
            for name, node in table.items():
                found[name] = node.name.pos
        return found

    def writes(self, name: str) -> set[str]:
        """The names the definition of ``name`` writes (none for a name it does not
        define)."""
        node = self.gestures.get(name) or self.poses.get(name) or self.groups.get(name)
        return set(_written(node)) if node is not None else set()

    def unplayable(self) -> frozenset[str]:
        """The flawed names and their users (``users``): what cannot be planned."""
        if self._unplayable is None:
            self._unplayable = self.flawed | frozenset(self.users(set(self.flawed)))
        return self._unplayable

    def users(self, names: set[str]) -> set[str]:
        """The group, pose and gesture names whose definitions write one of ``names``,
        or the name of one that does, and so on."""
        written: dict[str, set[str]] = {}
        for table in (self.groups, self.poses, self.gestures):
            for defined in table:
                for word in self.writes(defined):
                    written.setdefault(word, set()).add(defined)
        found, todo = set(), list(names)
        while todo:
            for user in written.get(todo.pop(), ()):
                if user not in found:
                    found.add(user)
                    todo.append(user)
        return found

    def source(self, name: str) -> tuple[Pos, list[str]] | None:
        """The lines that define the group, pose or gesture ``name``: the comment block
        right above it (what it does), then its own lines to the last one it writes on;
        and where the first of them is. None for a name it does not define, or whose
        file's text it does not keep."""
        node = self.gestures.get(name) or self.poses.get(name) or self.groups.get(name)
        text = self.texts.get(node.name.pos.file) if node else None
        if node is None or text is None:
            return None
        lines = [row.rstrip("\r") for row in text.split("\n")]  # as the parser counts
        top = comments_above(lines, node.name.pos.line)
        return Pos(node.name.pos.file, top, 1), lines[top - 1:_last_line(node)]


def _last_line(node: object) -> int:
    """The last line a syntax node (or a tuple of them) has a position on."""
    if isinstance(node, Pos):
        return node.line
    if isinstance(node, tuple):
        return max(map(_last_line, node), default=0)
    if dataclasses.is_dataclass(node):
        return max((_last_line(getattr(node, f.name)) for f in dataclasses.fields(node)),
                   default=0)
    return 0


def _written(node: object) -> tuple[str, ...]:
    """``_names`` of a definition, kept on the node: a block is parsed into one node for
    as long as its text stays the same (``incremental``), so an edit elsewhere in a long
    file walks none of the others again."""
    names = node.__dict__.get("_written")
    if names is None:
        names = node.__dict__["_written"] = tuple(_names(node))  # (frozen: its own)
    return names


def _names(node: object) -> list[str]:
    """The names a syntax node (or a tuple of them) writes."""
    if isinstance(node, ast.Name):
        return [node.text]
    if isinstance(node, tuple):
        return [n for item in node for n in _names(item)]
    if dataclasses.is_dataclass(node) and not isinstance(node, Pos):
        return [n for f in dataclasses.fields(node) for n in _names(getattr(node, f.name))]
    return []
