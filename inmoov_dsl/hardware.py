"""What a robot is made of, as its profile says once read: frozen dataclasses.
``profiles`` reads a TOML file into them; the rest of the package, the kinds of board
among it, imports them from here."""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

from .errors import Pos


@dataclass(frozen=True)
class Servo:
    """One servo, in command degrees (0..180 as sent on the wire)."""

    name: str
    id: int
    board: int
    lo: int  #: smallest value a gesture may command
    hi: int  #: largest value a gesture may command
    rest: int
    max_velocity: float  #: command degrees / s
    max_acceleration: float  #: command degrees / s^2
    max_jerk: float  #: command degrees / s^3
    calibration: tuple[int, int]  #: board side: 0..180 is mapped onto these servo angles
    reversed: bool  #: board side: 180..0 is mapped onto the calibration instead
    pin: int | None  #: its pin; on a Maestro or a PCA9685, its channel
    joint: str = ""  #: the model's joint this servo turns (urdf.py); the servo's name if ""
    #: where its ``joint`` key is (its table's header when it has none), and that line
    joint_at: tuple[Pos, str] | None = field(default=None, compare=False)
    #: ``pulse``: the widths (us) of values 0 and 180, instead of the calibration's
    pulse: tuple[int, int] | None = None


@dataclass(frozen=True)
class Board:
    """One servo board: its ID on the wire, its link's speed and its servos in order."""

    id: int
    name: str
    baud: int
    servos: tuple[str, ...]
    pos: Pos | None = field(default=None, compare=False)  #: its ``id`` in the profile
    kind: str = "rig"  #: what drives its servos: ``rig``, ``maestro``, ``pca9685``, ``mrlcomm``
    #: what its kind needs to know of it (a Maestro's model and device number, a
    #: PCA9685's address, oscillator and bus speed), as its kind's table declares them
    options: tuple[tuple[str, int], ...] = ()

    def option(self, key: str, default: int) -> int:
        """Its kind's option ``key``."""
        return dict(self.options).get(key, default)


@dataclass(frozen=True)
class Sensor:
    """One flex sensor of a glove: the servo it commands and how it reads."""

    servo: str
    pin: int  #: analog pin (14 is A0 on an Uno or Nano)
    calibration: tuple[int, int]  #: readings (0..1023) that map to 0 and 180
    reversed: bool = False  #: the low reading maps to 180 instead


@dataclass(frozen=True)
class Glove:
    """A flex-sensor glove: it reads its sensors and commands a servo board."""

    id: int
    name: str
    board: int  #: the servo board it sends to, on its software serial command port
    baud: int  #: USB, to the computer
    command_pins: tuple[int, int]  #: rx, tx of the command port
    deadband: int  #: command degrees a value must move before it is sent again
    frame_ms: int  #: ms between readings
    sensors: tuple[Sensor, ...]


@dataclass(frozen=True)
class Voice:
    """``[voice]``: the servo that is the mouth, its closed and open values, and how
    espeak-ng speaks the profile's text (its voice, words per minute and pitch)."""

    mouth: str
    closed: int
    opened: int
    voice: str = "en"
    speed: int = 160
    pitch: int = 50
    pos: Pos | None = field(default=None, compare=False)  #: the ``[voice]`` table


CLEARANCE_MM = 10.0  #: mm; two of a robot's parts closer than this touch (by default)


@dataclass(frozen=True)
class Profile:
    """A robot: its boards, its servos board by board, its groups and its gloves."""

    name: str
    description: str
    boards: tuple[Board, ...]
    servos: tuple[Servo, ...]  #: board by board, in each board's order
    groups: dict[str, tuple[str, ...]]
    path: str = ""
    sha256: str = ""  #: of the TOML text it was read from
    gloves: tuple[Glove, ...] = ()
    #: ``[sides]``: "right" and "left", each a list of servos, the k-th of one side the
    #: mirror image of the k-th of the other (empty: the profile has one side)
    sides: dict[str, tuple[str, ...]] = field(default_factory=dict)
    voice: Voice | None = None  #: ``[voice]``: the mouth that moves with ``say``
    #: ``[collision]``: closer than this (mm), two of the robot's parts touch
    clearance_mm: float = CLEARANCE_MM
    #: ``[place.NAME]``: the robot's own places (metres, its base frame), by name
    places: dict[str, tuple[float, float, float]] = field(default_factory=dict)

    def index(self, name: str) -> int:
        """The position of servo ``name`` in ``servos``; KeyError if there is none."""
        return self._indices[name]

    @cached_property
    def _indices(self) -> dict[str, int]:
        return {servo.name: i for i, servo in enumerate(self.servos)}

    @cached_property
    def names(self) -> tuple[str, ...]:
        """The servos' names, in the order of ``servos``."""
        return tuple(s.name for s in self.servos)

    @property
    def rest_pose(self) -> dict[str, int]:
        """Each servo's rest value, by name."""
        return {s.name: s.rest for s in self.servos}
