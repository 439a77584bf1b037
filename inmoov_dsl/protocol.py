"""The servo boards' byte protocol: every constant defined once, here.

Raw 8-bit bytes. A servo command is a pair ``(servo ID, value)`` with a value in
0..180; signals are numbered down from 255 and may arrive at any position.
The firmware core declares the same numbers; a test checks the two against each other.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
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


def frame(pairs: Iterable[tuple[int, int]]) -> bytes:
    """A stream's bytes: CANCEL (a board may be mid-command), then each (servo ID,
    value) pair."""
    return bytes([Signal.CANCEL, *(b for pair in pairs for b in pair)])


def pairs(data: bytes) -> list[tuple[int, int]]:
    """The (servo ID, value) pairs of a stream ``frame`` made: IDs at [1::2], values at
    [2::2]."""
    return list(zip(data[1::2], data[2::2], strict=False))


ASK_POSE = bytes([Signal.CANCEL, Signal.DUMP])  #: a board answers with the pose it holds
RELAX_BOARD = bytes([Signal.CANCEL, Signal.RELAX, Signal.CANCEL])  #: its servos go limp
