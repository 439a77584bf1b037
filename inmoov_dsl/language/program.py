"""A program: a .gest file with everything it imports, and the names they define (the
loader, ``load``, makes one)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from ..errors import Pos, SourceMap
from . import syntax as ast


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
    #: the library file (its name) that defines a gesture, pose or group, or None; the
    #: loader knows the search path (``load.in_library``), and an error's hint asks
    in_library: Callable[[str], str | None] | None = field(default=None, repr=False,
                                                           compare=False)
    #: the sound of ``say "text"`` in a file (``voice.hearing.Hearing``): the loader
    #: knows where files are; (text, file, voice, speed, pitch) -> sound
    hear: Callable[..., Any] | None = field(default=None, repr=False, compare=False)
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
