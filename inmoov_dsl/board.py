"""A servo board's rules, exactly as the protocol states them (docs/protocol.md).

A pure state machine fed one byte at a time: ``feed(byte)`` returns what the board
does with it (servo writes, reply bytes). No clock and no I/O: the virtual board
(``sim.py``) paces it, the metrics decode streams with it, and the firmware's host
tests check the C++ core against the same rules.

- CANCEL (255) drops a half-read command; the board then expects a servo ID.
- DUMP (253) is answered ``START BOARD_ID N (id value)*N END`` and changes nothing else.
- Other signals (249..254) are not commands and are skipped wherever they arrive.
- A command is (servo ID, value). A value above 180 is clamped to 180. A pair for an
  ID the board does not own is read (to stay in step) and ignored.
- A value is mapped onto the servo's calibration (reversed servos map 180..0 onto
  it) with the Arduino's integer ``map()`` before it is written to the servo.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from .profile import Board, Profile
from .protocol import MAX_VALUE, Signal


@dataclass(frozen=True)
class BoardServo:
    id: int
    calibration: tuple[int, int] = (0, MAX_VALUE)
    reversed: bool = False
    default: int = 0

    def angle(self, value: int) -> int:
        """The servo angle for a command value, as Arduino's integer map() computes it."""
        lo, hi = self.calibration
        step = value * (hi - lo) // MAX_VALUE
        return hi - step if self.reversed else lo + step


@dataclass(frozen=True)
class Write:
    """The board wrote ``value`` (unscaled) to servo ``id``, at ``angle``."""

    id: int
    value: int
    angle: int


class BoardCore:
    """The protocol as one board reads it."""

    def __init__(self, board_id: int, servos: Sequence[BoardServo]):
        self.board_id = board_id
        self.servos = tuple(servos)
        self._index = {s.id: i for i, s in enumerate(self.servos)}
        self.values = [s.default for s in self.servos]  #: last value written, unscaled
        self.pending: int | None = None  #: a servo ID waiting for its value

    @classmethod
    def from_profile(cls, profile: Profile, board: Board) -> BoardCore:
        servos = [profile.servos[profile.index(name)] for name in board.servos]
        return cls(board.id, [BoardServo(s.id, s.calibration, s.reversed, s.rest)
                              for s in servos])

    def feed(self, byte: int) -> tuple[Write | None, bytes]:
        """Read one byte: the servo write it completes, if any, and the bytes to reply."""
        if byte == Signal.CANCEL:
            self.pending = None
        elif byte == Signal.DUMP:
            return None, self.dump()
        elif byte >= min(Signal):
            pass  # a signal this board does not act on
        elif self.pending is None:
            self.pending = byte
        else:
            sid, self.pending = self.pending, None
            index = self._index.get(sid)
            if index is not None:
                value = min(byte, MAX_VALUE)
                self.values[index] = value
                return Write(sid, value, self.servos[index].angle(value)), b""
        return None, b""

    def dump(self) -> bytes:
        body = [b for s, v in zip(self.servos, self.values, strict=True) for b in (s.id, v)]
        return bytes([Signal.START, self.board_id, len(self.servos), *body, Signal.END])


def parse_dump(data: bytes, board_id: int | None = None
               ) -> tuple[int, dict[int, int]] | None:
    """Find a DUMP reply in bytes from a board (WAIT bytes and noise around it are
    skipped), from board ``board_id`` if given: (board ID, servo ID -> value), or None
    if no complete reply is there."""
    start = 0
    while True:
        start = data.find(bytes([Signal.START]), start)
        if start < 0 or start + 2 >= len(data):
            return None
        board, count = data[start + 1], data[start + 2]
        end = start + 3 + 2 * count
        if end < len(data) and data[end] == Signal.END:
            body = data[start + 3:end]
            pairs = dict(zip(body[0::2], body[1::2], strict=True))
            if all(v <= MAX_VALUE for v in pairs.values()) and len(pairs) == count \
                    and board_id in (None, board):
                return board, pairs
        start += 1
