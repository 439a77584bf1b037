"""The servo boards' byte protocol: every constant defined once, here.

Raw 8-bit bytes. A servo command is a pair ``(servo ID, value)`` with a value in
0..180; signals are numbered down from 255 and may arrive at any position.
The firmware core declares the same numbers; a test checks the two against each other.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterable, Sequence
from enum import IntEnum


class Signal(IntEnum):
    """Bytes above 180 that are not values."""

    CANCEL = 255  #: host -> board: drop any half-read command, expect a servo ID
    WAIT = 254  #: board -> host: nothing left to read
    DUMP = 253  #: host -> board: answer START BOARD_ID N (id value)*N END
    START = 252  #: board -> host: a reply begins
    END = 251  #: board -> host: a reply ends
    MIN = 250  #: host -> glove: capture the lower calibration bound
    MAX = 249  #: host -> glove: capture the upper calibration bound
    RELAX = 248  #: host -> servo board: stop driving the servos until the next command


MAX_VALUE = 180  #: largest servo value; a board clamps larger non-signal values to it
MAX_SERVO_ID = 180  #: servo IDs are values too: 0..180 (181 of them)
FIRST_BOARD_ID = 181  #: board IDs start here (right hand 181, right glove 182)
LAST_BOARD_ID = min(Signal) - 1  #: and end below the signals
DEFAULT_BAUD = 9600  #: a board's or glove's link, unless its profile says otherwise
MAX_BAUD = 2_000_000  #: the fastest link a board or glove may declare
POSE_SETTLE = 1.0  #: s without a servo command before a board stores its pose (EEPROM)
#: host -> servo board, where a servo ID is expected, followed by a number: play the
#: stored gesture of that number (or, for ``CATALOG``, say which ones it holds). The
#: original firmware reads the two bytes as a pair for a servo it does not have. Not a
#: ``Signal``: it acts only as an ID does (in value position it is a value), and board
#: IDs may still be 247.
PLAY = 247
CATALOG = 180  #: the number after PLAY that asks a board for its stored gestures
MAX_STORED = CATALOG  #: stored gestures are numbered 0..MAX_STORED - 1

BITS_PER_BYTE = 10  #: 8N1: start bit, 8 data bits, stop bit
SERVO_FRAME = 0.020  #: s; a hobby servo takes one new position per 20 ms PWM frame
PAIR_BYTES = 2  #: a servo command is (ID, value)


def byte_time(baud: int) -> float:
    """Seconds one byte occupies on the wire at ``baud`` (8N1)."""
    return BITS_PER_BYTE / baud


def pairs_per_frame(baud: int) -> int:
    """How many (ID, value) pairs fit in one servo frame after the stream's CANCEL byte."""
    tau = byte_time(baud)
    return max(0, math.floor((SERVO_FRAME - tau) / (PAIR_BYTES * tau) + 1e-9))


def usable_baud(baud: int) -> bool:
    """Can a link at ``baud`` carry a servo command in every servo frame, within
    MAX_BAUD?"""
    return 0 < baud <= MAX_BAUD and pairs_per_frame(baud) >= 1


def clamp(value: int) -> int:
    """``value`` within 0..MAX_VALUE: the nearest value a servo command can carry."""
    return max(0, min(MAX_VALUE, value))


def frame(pairs: Iterable[tuple[int, int]]) -> bytes:
    """A stream's bytes: CANCEL (a board may be mid-command), then each (servo ID,
    value) pair, the ID first. ``frame(())`` is CANCEL alone."""
    return bytes([Signal.CANCEL, *itertools.chain.from_iterable(pairs)])


def pairs(data: bytes) -> list[tuple[int, int]]:
    """The (servo ID, value) pairs of bytes ``frame`` made: the byte after CANCEL and
    every second one after it are IDs, each followed by its value (a last ID without
    its value is left out)."""
    return list(zip(data[1::2], data[2::2], strict=False))


def timed_pairs(times: Sequence[float], data: bytes) -> list[tuple[float, int, int]]:
    """(time its value byte goes out, servo ID, value) of each pair of the bytes
    ``frame`` made, each byte sent at its time in ``times``: the board has the whole
    command a byte-time after that time."""
    return [(float(t), sid, value) for (sid, value), t in
            zip(pairs(data), list(times[2::2]), strict=False)]


def frame_fault(data: bytes) -> tuple[int, str] | None:
    """Where ``data`` breaks a stream's layout, or None if it keeps it (CANCEL, then
    whole pairs of a servo ID and a value, each 0..MAX_VALUE): the index of the byte
    at fault and what it is, "CANCEL" (the first byte is not), "pair" (the last pair
    is cut short), or "servo ID" or "value" (the first byte above MAX_VALUE)."""
    if not data or data[0] != Signal.CANCEL:
        return 0, "CANCEL"
    if (len(data) - 1) % PAIR_BYTES:
        return len(data) - 1, "pair"
    if len(data) > 1 and max(data[1:]) > MAX_VALUE:
        n = next(n for n, byte in enumerate(data) if n and byte > MAX_VALUE)
        return n, ("servo ID", "value")[(n - 1) % PAIR_BYTES]
    return None


def reply(board_id: int, pairs: Iterable[tuple[int, int]]) -> bytes:
    """A board's answer to DUMP: START BOARD_ID N (servo ID, value)*N END."""
    body = list(itertools.chain.from_iterable(pairs))
    return bytes([Signal.START, board_id, len(body) // PAIR_BYTES, *body, Signal.END])


CANCEL_PENDING = frame(())  #: a board drops a half-read command (and answers WAIT)
ASK_POSE = bytes([Signal.CANCEL, Signal.DUMP])  #: a board answers ``reply`` with its pose
#: a board's servos go limp until its next command (the original firmware reads RELAX
#: as the ID of a servo it does not have, and the CANCEL after it drops that ID)
RELAX_BOARD = bytes([Signal.CANCEL, Signal.RELAX, Signal.CANCEL])
