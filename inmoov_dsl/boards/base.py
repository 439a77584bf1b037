"""What every kind of board provides (``Controller``), and what it is given (a plan).

A kind of board is one folder of ``boards/``: how a plan becomes its commands (timed
bytes: for a serial controller the bytes on its wire, for an I2C one its bus
transactions, framed), how those bytes are cut into commands, what the board holds
after reading them (its ``core``, a pure state machine: also its virtual twin's
heart), how to ask it for its pose and who it is, how it relaxes. Everything above
the boards (the player, the drive loop, the repl, the service, the ROS node) sees only
this interface.
"""

from __future__ import annotations

from collections.abc import Callable, Hashable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any, ClassVar, Protocol

import numpy as np

from ..hardware import Board, Profile, Servo
from ..protocol import byte_time
from .arduino import Bootloader
from .pulses import Widths, widths


class Track(Protocol):
    """A servo's planned motion."""

    def position(self, at: np.ndarray) -> np.ndarray:
        """Its value (command degrees, not rounded) at each of ``at`` (s)."""


class PlanLike(Protocol):
    """What a kind needs of a plan: the profile, a track per servo (the profile's
    order), the start pose and the duration (s)."""

    profile: Profile
    tracks: Sequence[Track]
    start: Sequence[float]
    duration: float
    #: the servos (indices) its steps name, moving or not: each is held at its target
    #: when the gesture ends (``frames.per_frame``)
    named: frozenset[int]


@dataclass(frozen=True)
class Write:
    """The board wrote ``value`` (a command value) to servo ``id``, at ``angle``
    (the servo angle: the firmware's; for a controller finer than a degree, the pulse
    width in us)."""

    id: int
    value: int
    angle: int


class PoseReader(Protocol):
    """Reads a board's answer to ``Controller.ask_pose``."""

    def feed(self, data: bytes) -> dict[int, int] | None:
        """Read ``data``: the pose (servo ID -> value) once the answer is whole."""

    def ask(self) -> bytes:
        """What to ask the board next, now that it answered what it was fed (most
        readers ask nothing more)."""


class Controller:
    """One board of a profile, as its kind drives it."""

    kind: ClassVar[str] = ""
    #: the byte that fills the gaps of a continuous run (None: the link is idle between
    #: commands, and each command is written when it is due)
    fill: ClassVar[int | None] = None
    #: it runs our firmware (or the original): it sends WAIT when booted and idle, maps
    #: values to angles itself, has a sketch and may store gestures
    ours: ClassVar[bool] = False
    #: it is on a serial port (a PCA9685 is on an I2C bus: ``open``)
    serial: ClassVar[bool] = True
    #: what one place of ``addressed`` is called in messages ("channel")
    address: ClassVar[str] = "channel"
    #: its answer to ``ask_pose`` in its own words, as a message misses it ("no DUMP
    #: reply"), and what to check then
    pose_reply: ClassVar[str] = "answer to its pose question"
    unheard: ClassVar[str] = "is the board powered, and at this baud?"

    def __init__(self, profile: Profile, board: Board):
        self.profile, self.board = profile, board
        self.servos: tuple[Servo, ...] = tuple(profile.servos[profile.index(n)]
                                               for n in board.servos)
        self.widths: tuple[Widths, ...] = tuple(widths(s) for s in self.servos)

    @property
    def tau(self) -> float:
        """Seconds one byte of its stream takes on the link: on a serial link, 8N1 at
        the board's baud."""
        return byte_time(self.board.baud)

    def commands(self, data: bytes) -> list[tuple[int, int]]:
        """(first, end) index of each command of ``data``: what goes whole."""
        raise NotImplementedError

    def addresses(self) -> set[int]:
        """What its commands address its servos by: their channels (a pin each)."""
        return {s.pin for s in self.servos}

    def addressed(self, data: bytes) -> set[int]:
        """What the commands of ``data`` address (``addresses``' kind of number)."""
        raise NotImplementedError

    def open(self, spec: str):
        """The board's port ``spec`` opened by the kind itself, or None: a serial port,
        which the link edge opens."""
        return None

    @classmethod
    def claims(cls, spec: str) -> str | None:
        """What ``spec`` is when it names a port of this kind's own, which no other kind
        opens (a PCA9685's I2C bus), said to a board of another kind given it; None."""
        return None

    def unanswered(self) -> str:
        """What to try when nothing answers on its port."""
        return "try another port ('gestplay ports' asks each one who it is), or --blind " \
               "to play anyway on a link that cannot answer"

    def moves(self, data: bytes) -> list[tuple[int, int]]:
        """(servo ID, its value in the board's unit) of each servo command of ``data``."""
        raise NotImplementedError

    def encode(self, plan: PlanLike) -> tuple[np.ndarray, bytes]:
        """The plan's motion of this board's servos: each byte's time (s) and the bytes."""
        raise NotImplementedError

    def core(self) -> Any:
        """What the board holds after the bytes it reads (``feed``, ``values``,
        ``restore``, ``command``): a new one, at the servos' rests."""
        raise NotImplementedError

    def twin(self) -> Any:
        """The board's virtual twin's core: as ``core``, but as the board powers up
        (a PCA9685 asleep, before a connect sets it up)."""
        return self.core()

    def hello(self) -> bytes:
        """What the board sends as it starts (a rig's WAIT aside): MrlComm's banner."""
        return b""

    def set_values(self, values: Mapping[int, int]) -> bytes:
        """Commands that leave servo ID -> value as given (a stop sends them again)."""
        raise NotImplementedError

    def cancel(self) -> bytes:
        """What drops a half-sent command (empty: the kind needs nothing)."""
        return b""

    def relax(self) -> bytes:
        """What makes the board stop driving its servos."""
        raise NotImplementedError

    def ask_pose(self) -> bytes:
        """The question whose answer is the pose it holds."""
        raise NotImplementedError

    def pose_reader(self) -> PoseReader:
        """A reader of the answer to ``ask_pose``."""
        raise NotImplementedError

    def watch(self) -> Callable[[bytes], str | None]:
        """A reader of what the board sends while it plays: what in it says the board
        cannot go on (an MrlComm that started again), or None."""
        return lambda data: None

    #: bytes the board's serial receive buffer holds, for a board whose own loop, not
    #: the wire, bounds how fast it reads (MrlComm); None: it keeps up with the wire.
    #: What is written and not yet read (``cost``) is kept within it (``wire.flow``)
    receive_buffer: ClassVar[int | None] = None

    def cost(self, command: bytes) -> float:
        """Seconds of the board's own time that reading ``command`` and doing what it
        says take, by the host's account (0: the wire's time is all it takes)."""
        return 0.0

    def key(self, command: bytes) -> Hashable | None:
        """What ``command`` sets, such that a newer command of the same key makes it
        needless when both wait to be sent (a move: its servo); None: always sent."""
        return None

    def answer(self, command: bytes) -> Hashable | None:
        """What the board says once it has read ``command`` (as ``answers`` reads it),
        or None: nothing that says so."""
        return None

    def answers(self) -> Callable[[bytes], list[Hashable]]:
        """A reader of what the board sends: the ``answer`` of each command it has read,
        in order."""
        return lambda data: []

    def bootloader(self) -> Bootloader | None:
        """What runs on the board after a reset, when opening its port resets it (an
        Arduino's DTR), or None: opening its port does not reset it."""
        return None

    def probe(self) -> bytes:
        """What a board answers once it is ready (rig: CANCEL, answered WAIT)."""
        raise NotImplementedError

    def ready(self, answer: bytes) -> bool:
        """Does ``answer`` (all that came since the first probe) say it is ready?"""
        raise NotImplementedError

    def greeting(self, answer: bytes) -> str | None:
        """What to tell a person about the board's answer to ``probe`` (its errors), or
        None."""
        return None

    def refusal(self, answer: bytes) -> str | None:
        """Why a board that answered ``answer`` to its ``probe`` cannot be driven (a
        firmware of another version), or None."""
        return None

    def answered_late(self) -> str:
        """What to say of a board that did not answer ``probe`` in time but answered
        ``ask_pose`` (after "board N on PORT"), in its kind's words."""
        return "was not ready in time, but then told its pose"

    def stop_sent(self) -> str:
        """What a stop (Ctrl-C: ``cancel``) sent it, in words: a kind whose commands go
        whole needs nothing more."""
        return "nothing more sent"

    def stop_held(self) -> str:
        """What its servos do after a stop, in words."""
        return "each servo holds its last target"

    def setup(self, answer: bytes = b"", pose: Mapping[int, int] | None = None) -> bytes:
        """What goes to the board once it is ready (``answer``: what it answered the
        probe; ``pose``: servo ID -> the value it holds), before anything moves."""
        return b""

    #: us per step of the board's unit (None: the rig's whole command degrees)
    unit_us: ClassVar[float | None] = None

    def units(self, index: int, values) -> np.ndarray:
        """Servo ``index``'s plan ``values`` (kept in its range) in the board's unit."""
        raise NotImplementedError

    def degrees(self, index: int, units) -> np.ndarray:
        """Widths in the board's unit as degrees of servo ``index``'s span: linear in the
        width, 0 and 180 at the widths of values 0 and 180 (for measuring)."""
        table = self.widths[index].table
        us = np.asarray(units, dtype=float) * self.unit_us
        return (us - table[0]) / (table[-1] - table[0]) * 180

    def limit(self, values: np.ndarray, index: int) -> np.ndarray:
        """``values`` (a plan's) of servo ``index`` kept in its range."""
        s = self.servos[index]
        return np.clip(values, s.lo, s.hi)
