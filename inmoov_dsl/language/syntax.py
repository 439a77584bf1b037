"""The syntax tree of a .gest file: plain frozen dataclasses, each with its position."""

from __future__ import annotations

from dataclasses import dataclass

from ..errors import Diagnostic, Pos

#: the language's keywords: never a gesture, pose, group or servo name
KEYWORDS = frozenset({"robot", "use", "group", "pose", "wait", "hold", "repeat", "over", "stagger",
                      "through", "left", "right", "say", "place", "look"})


@dataclass(frozen=True)
class Name:
    """A name as written, and where."""

    text: str
    pos: Pos


@dataclass(frozen=True)
class Target:
    """``index 180`` (servo or group with a value) or ``fist`` (a pose or gesture name)."""

    name: Name
    value: int | None  #: None: none written, or one refused (``value_pos`` is set)
    value_pos: Pos | None

    @property
    def valued(self) -> bool:
        """Was a value written (one the parser refused too)?"""
        return self.value_pos is not None


@dataclass(frozen=True)
class Point:
    """``(350, -200, 300) mm``: a place in the robot's base frame (x forward, y to its
    left, z up, from ``base_link``), or ``cup``: a place's name."""

    xyz: tuple[float, float, float] | None  #: metres; None: a name (``name``), or refused
    pos: Pos  #: the whole of it, from ``(`` to the unit, or the name
    name: Name | None = None
    numbers: tuple[str, ...] = ()  #: as written
    unit: str = "mm"


@dataclass(frozen=True)
class Reach:
    """``right hand to P`` (``what``: ``right``, ``left``) or ``look at P`` (``look``):
    an item of a step that a solve turns into servo values."""

    what: str
    to: Point
    pos: Pos  #: from the first word to the end of the place


@dataclass(frozen=True)
class Duration:
    """A duration (``over``, ``stagger``, ``wait``) in seconds, as written."""

    seconds: float
    pos: Pos
    number: str = ""  #: as written, e.g. ``.5``
    unit: str = "s"  #: ``s`` or ``ms``


@dataclass(frozen=True)
class Move:
    """A step that sets targets (or calls a gesture: a gesture's name alone)."""

    targets: tuple[Target, ...]
    over: Duration | None
    stagger: Duration | None
    pos: Pos
    through: Pos | None = None  #: ``through``: the servos cross the keyframe moving
    side: Name | None = None  #: ``left peace``: the call played on that side
    reaches: tuple[Reach, ...] = ()  #: ``right hand to cup``, ``look at cup``
    #: every item in the order written (targets and reaches), for what prints the step
    items: tuple[Target | Reach, ...] = ()


@dataclass(frozen=True)
class Wait:
    """A step that holds the pose: ``wait`` or ``hold``."""

    duration: Duration
    pos: Pos
    keyword: str = "wait"  #: ``wait`` or ``hold`` (the same thing)


@dataclass(frozen=True)
class Repeat:
    """``repeat N:`` and the steps it repeats."""

    count: int
    body: tuple[Step, ...]
    pos: Pos


@dataclass(frozen=True)
class Say:
    """``say "hello.wav"`` or ``say "Hello"``: a sound (a WAV file, or text spoken by
    espeak-ng) and the mouth moving with it."""

    text: str
    pos: Pos  #: the keyword
    text_pos: Pos  #: the string, quotes included

    @property
    def is_file(self) -> bool:
        """Is it a WAV file's name (else text to speak)?"""
        return self.text.lower().endswith(".wav")


@dataclass(frozen=True)
class Together:
    """``a & b``: moves, calls, poses or sounds that run at the same time, on their own
    servos."""

    parts: tuple[Move | Say, ...]
    pos: Pos


Step = Move | Wait | Repeat | Together | Say


@dataclass(frozen=True)
class Robot:
    """``robot inmoov`` or ``robot "my_hand.toml"``: the robot (its profile) the file's
    gestures are written for; a file has at most one, before anything else."""

    name: str  #: a built-in profile's name, or a .toml file's path as written
    pos: Pos  #: the name (or the string, quotes included)
    is_file: bool = False  #: given as a quoted .toml path (relative to the file)


@dataclass(frozen=True)
class Use:
    """``use "other.gest"``: the file's definitions are imported."""

    path: str
    pos: Pos


@dataclass(frozen=True)
class GroupDef:
    """``group NAME: servo, servo, ...``"""

    name: Name
    members: tuple[Name, ...]


@dataclass(frozen=True)
class PoseDef:
    """``pose NAME: targets``"""

    name: Name
    targets: tuple[Target, ...]


@dataclass(frozen=True)
class PlaceDef:
    """``place NAME (x, y, z) mm``: a named place of the robot's base frame."""

    name: Name
    point: Point


@dataclass(frozen=True)
class GestureDef:
    """``NAME: step`` or ``NAME:`` and an indented block of steps."""

    name: Name
    steps: tuple[Step, ...]


Item = Robot | Use | GroupDef | PoseDef | PlaceDef | GestureDef


@dataclass(frozen=True)
class Module:
    """One parsed file."""

    file: str
    items: tuple[Item, ...]
    #: the errors of steps whose shape is known (a value, a unit, a line that does not
    #: parse in a block that does): their definitions are read, for their names, but
    #: cannot be played
    flaws: tuple[Diagnostic, ...] = ()

    @property
    def robot(self) -> Robot | None:
        """The file's robot line, if it has one."""
        first = self.items[0] if self.items else None
        return first if isinstance(first, Robot) else None
