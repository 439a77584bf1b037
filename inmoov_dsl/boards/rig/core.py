"""The rig board's rules, byte for byte as the original firmware reads them
(docs/protocol.md).

A pure state machine fed one byte at a time: ``feed(byte)`` returns what the board
does with it (servo writes, reply bytes). It reads the bytes with the protocol reader
(``decode.Reader`` with the ``BOARD`` policy) and acts on its events. No clock and no
I/O: the virtual board (``sim.py``) paces it, the repl mirrors the hand with it, and
the firmware's host tests check the C++ core against the same rules.

- CANCEL (255) drops a half-read command; the board then expects a servo ID.
- DUMP (253) is answered ``START BOARD_ID N (id value)*N END`` wherever it arrives, and
  drops a half-read command.
- RELAX (248, ours) stops the pulses wherever it arrives and drops a half-read command;
  the next servo write drives every servo again, from the pose the board holds.
- Any other byte is a servo ID where an ID is expected (a foreign one, if the board has
  no such servo: its value is read and the pair ignored) and a value where a value is
  expected, clamped to 180: WAIT (254) arriving as a value sets 180.
- A pair for PLAY (247) asks for a stored gesture (its value is the gesture's number,
  or CATALOG for the list): ``asked`` says which, for the board to play (``sim.py``).
- A value is mapped onto the servo's calibration (reversed servos map 180..0 onto it)
  with the Arduino's integer ``map()``, and the angle onto a pulse of 544..2400 us.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from ...decode import BOARD, Pair, Reader
from ...hardware import Board, Profile
from ...protocol import MAX_VALUE, PLAY, Signal, reply
from ..base import Write
from ..pulses import angle, pulse_us


@dataclass(frozen=True)
class BoardServo:
    """One servo as its board knows it: ID, calibration (angles for 0 and 180), whether
    it is reversed, and the value it starts at without a stored pose."""

    id: int
    calibration: tuple[int, int] = (0, MAX_VALUE)
    reversed: bool = False
    default: int = 0

    def angle(self, value: int) -> int:
        """The servo angle for a command value, as the original firmware computes it:
        ``map(v, 0, 180, lo, hi)``, or ``map(v, 180, 0, lo, hi)`` when reversed."""
        return angle(value, self.calibration, self.reversed)

    def pulse(self, value: int) -> int:
        """The pulse width (us) on this servo's pin for a command value."""
        return pulse_us(self.angle(value))


class BoardCore:
    """The protocol as one board reads it."""

    def __init__(self, board_id: int, servos: Sequence[BoardServo]):
        self.board_id = board_id
        self.servos = tuple(servos)
        self._index = {s.id: i for i, s in enumerate(self.servos)}
        self._reader = Reader(BOARD)
        self.values: list[int] = []  #: last value written, unscaled
        self.relaxed = False  #: RELAX came: no pulses until the next servo write
        self.asked: int | None = None  #: the number after PLAY the last byte completed
        self.restore(None)

    @classmethod
    def from_profile(cls, profile: Profile, board: Board) -> BoardCore:
        """The core of ``board`` of ``profile``: its servos, each resting at its rest."""
        servos = [profile.servos[profile.index(name)] for name in board.servos]
        return cls(board.id, [BoardServo(s.id, s.calibration, s.reversed, s.rest)
                              for s in servos])

    @property
    def pending(self) -> int | None:
        """A servo ID waiting for its value, if any."""
        return self._reader.pending

    def feed(self, byte: int) -> tuple[Write | None, bytes]:
        """Read one byte: the servo write it completes, if any, and the bytes to reply."""
        self.asked = None
        for event in self._reader.feed(byte):
            match event:
                case Signal.DUMP:
                    return None, self.dump()
                case Signal.RELAX:
                    self.relaxed = True
                case Pair(id=sid, value=value) if sid in self._index:
                    return self.command(self._index[sid], value), b""
                case Pair(id=sid, value=value) if sid == PLAY:
                    self.asked = value
        return None, b""

    def command(self, index: int, value: int) -> Write:
        """Servo ``index`` to ``value``, as a servo command or a stored gesture does: it
        drives every servo again after RELAX."""
        self.values[index] = value
        self.relaxed = False
        return Write(self.servos[index].id, value, self.servos[index].angle(value))

    def restore(self, values: Sequence[int] | None) -> None:
        """Reset: every servo at ``values`` (the pose kept in EEPROM) or, if None, at
        its rest value; nothing pending."""
        self.values = list(values) if values is not None else [s.default for s in
                                                                self.servos]
        self._reader.reset()
        self.relaxed = False

    def dump(self) -> bytes:
        """The reply to DUMP: START BOARD_ID N (id value)*N END."""
        return reply(self.board_id, [(s.id, v) for s, v in zip(self.servos, self.values,
                                                                 strict=True)])
