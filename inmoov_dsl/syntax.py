"""The syntax tree of a .gest file: plain frozen dataclasses, each with its position."""

from __future__ import annotations

from dataclasses import dataclass

from .errors import Pos

#: the language's keywords: never a gesture, pose, group or servo name
KEYWORDS = frozenset({"use", "group", "pose", "wait", "hold", "repeat", "over", "stagger"})


@dataclass(frozen=True)
class Name:
    text: str
    pos: Pos


@dataclass(frozen=True)
class Target:
    """``index 180`` (servo or group with a value) or ``fist`` (a pose or gesture name)."""

    name: Name
    value: int | None
    value_pos: Pos | None


@dataclass(frozen=True)
class Duration:
    seconds: float
    pos: Pos
    number: str = ""  #: as written, e.g. ``.5``
    unit: str = "s"  #: ``s`` or ``ms``


@dataclass(frozen=True)
class Move:
    targets: tuple[Target, ...]
    over: Duration | None
    stagger: Duration | None
    pos: Pos


@dataclass(frozen=True)
class Wait:
    duration: Duration
    pos: Pos
    keyword: str = "wait"  #: ``wait`` or ``hold`` (the same thing)


@dataclass(frozen=True)
class Repeat:
    count: int
    body: tuple[Step, ...]
    pos: Pos


Step = Move | Wait | Repeat


@dataclass(frozen=True)
class Use:
    path: str
    pos: Pos


@dataclass(frozen=True)
class GroupDef:
    name: Name
    members: tuple[Name, ...]


@dataclass(frozen=True)
class PoseDef:
    name: Name
    targets: tuple[Target, ...]


@dataclass(frozen=True)
class GestureDef:
    name: Name
    steps: tuple[Step, ...]


Item = Use | GroupDef | PoseDef | GestureDef


@dataclass(frozen=True)
class Module:
    """One parsed file."""

    file: str
    items: tuple[Item, ...]
