"""What a name means in a program compiled for one profile: a servo, a group, a pose
or a gesture; one table, checked once for names that clash."""

from __future__ import annotations

import functools
from collections.abc import Callable, Sequence
from dataclasses import dataclass

from ..errors import Diagnostic, GestError, Pos, closest, did_you_mean
from ..hardware import Profile
from ..language import syntax as ast
from ..language.program import Program

ANYTHING = "servo, group, pose or gesture"  #: what an unknown name could have been


@dataclass(frozen=True)
class Servo:
    """A servo of the profile."""

    name: str
    index: int


@dataclass(frozen=True)
class Group:
    """A group of servos, of the program or of the profile."""

    name: str
    members: tuple[str, ...]


@dataclass(frozen=True)
class Pose:
    """A pose of the program."""

    node: ast.PoseDef


@dataclass(frozen=True)
class Gesture:
    """A gesture of the program."""

    node: ast.GestureDef


@dataclass(frozen=True)
class Place:
    """A place, of the program (``place cup (350, -200, 300) mm``) or of the profile
    (``[place.cup]``): metres in the robot's base frame, and where it is written."""

    name: str
    xyz: tuple[float, float, float] | None  #: None: written wrong (told by the parser)
    pos: Pos | None = None  #: None: the profile's


Entity = Servo | Group | Pose | Gesture | Place


class NameTable:
    """Every name the program and the profile define -> what it is."""

    def __init__(self, program: Program, profile: Profile,
                 elsewhere: Callable[[str], Sequence[str]]):
        """Build the table; names that clash are GestErrors, all reported at once.
        ``elsewhere(name)``: the built-in profiles that have a servo or group ``name``
        (``profiles.profile.profiles_with``, asked only to word a hint)."""
        self.profile, self.elsewhere = profile, elsewhere
        self.in_library = program.in_library
        self._table = _table(program, profile)

    def get(self, name: str) -> Entity | None:
        """What ``name`` is, or None."""
        return self._table.get(name)

    def entries(self) -> dict[str, Entity]:
        """Every name -> what it is (an editor's completions)."""
        return dict(self._table)

    def hint(self, name: str) -> str | None:
        """A hint for an unknown ``name``: the built-in profile that has it, the library
        file that defines it (a file's names come in with ``use``), or the closest name,
        the library's gestures' too. Every command that resolves a name words it here."""
        others = [p for p in self.elsewhere(name) if p != self.profile.name]
        if others:
            return (f"'{name}' is in profile '{others[0]}': a file for that robot starts "
                    f"with the line  robot {others[0]}")
        library = self.in_library.entries() if self.in_library is not None else {}
        if name in library:
            found = library[name].path.name
            return (f"'{name}' is a library gesture, defined in {found}: add the line  "
                    f"use \"{found}\"  to this file")
        meant = closest(name, [*self._table, *library])
        if meant is None:
            return None
        if meant in self._table:
            return f"did you mean '{meant}'?"
        found = library[meant].path.name
        return (f"did you mean '{meant}'? It is a library gesture, defined in {found}: "
                f"add the line  use \"{found}\"  to this file")


def _table(program: Program, profile: Profile) -> dict[str, Entity]:
    """Every name -> what it is. A program's name may not be a servo's, nor a profile
    group's unless it is a group itself; a group's members must be servos."""
    servos = {n: Servo(n, i) for i, n in enumerate(profile.names)}
    table: dict[str, Entity] = {**servos, **{n: Group(n, tuple(m)) for n, m in
                                             profile.groups.items()}}
    errors: list[Diagnostic] = []
    for name, pos in program.names().items():
        if name in servos:
            errors.append(program.sources.error(f"'{name}' is the name of a servo of "
                                                f"profile '{profile.name}'", pos))
        elif name in profile.groups and name not in program.groups:
            errors.append(program.sources.error(f"'{name}' is the name of a group of "
                                                f"profile '{profile.name}'", pos))
    for group in program.groups.values():
        for member in group.members:
            if member.text not in servos:
                errors.append(program.sources.error(
                    f"unknown servo '{member.text}' in group '{group.name.text}'",
                    member.pos, did_you_mean(member.text, servos)))
        table[group.name.text] = Group(group.name.text, tuple(m.text for m in group.members))
    if errors:
        raise GestError(errors)
    table.update({n: Place(n, xyz) for n, xyz in profile.places.items()
                  if n not in table})  # a file's own place of the name wins
    table.update({n: Place(n, node.point.xyz, node.name.pos)
                  for n, node in program.places.items()})
    table.update({n: Pose(node) for n, node in program.poses.items()})
    table.update({n: Gesture(node) for n, node in program.gestures.items()})
    return table


MAX_WHERE = 120  #: characters of a step's call chain; a longer one is abbreviated


@functools.lru_cache(maxsize=4096)
def call_chain(where: str, callee: str) -> str:
    """The call chain shown for a step, ``where > callee``; a chain longer than
    MAX_WHERE keeps its first and last names."""
    text = f"{where} > {callee}"
    if len(text) > MAX_WHERE:
        root = where.split(" > ", 1)[0]
        half = (MAX_WHERE - 9) // 2
        text = f"{_cut(root, half)} > ... > {_cut(callee, half)}"
    return text


def _cut(name: str, most: int) -> str:
    return name if len(name) <= most else name[:most - 3] + "..."
