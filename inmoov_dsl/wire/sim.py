"""The virtual board: BoardCore on a simulated serial link, with the firmware's memory.

Bytes written by the host reach the board one byte-time apart at the board's baud;
bytes the bootloader would swallow (after a reset) are lost; the board answers DUMP and
sends WAIT whenever it is about to read a command and nothing is left to read, as the
firmware does. Every servo write is recorded with the time it happened. Like the
firmware, it keeps its pose once the pose has settled (no servo write for
POSE_SETTLE s: the EEPROM record) and starts from that pose after a reset. Time is
passed in, so the same board runs in real time behind ``sim://`` or on a test's clock.
"""

from __future__ import annotations

import copy
import math
from collections import deque
from dataclasses import dataclass, field

from ..protocol import DEFAULT_BAUD, POSE_SETTLE, Signal, byte_time
from .board import BoardCore, Write


@dataclass
class DtrLine:
    """The DTR line from a host's port to a board: an Uno or a Nano resets when it
    rises. Opening the port raises it unless it is up already; closing drops it unless
    the program cleared HUPCL (``hupcl``, what the program with the port open asks)."""

    up: bool = False
    is_open: bool = False  #: a program has the port open
    hupcl: bool = True

    def opened(self) -> bool:
        """A program opened the port: True if DTR rose (the board resets)."""
        rose = not self.up
        self.up = self.is_open = True
        return rose

    def closed(self) -> None:
        """The program closed the port (once is enough; again changes nothing)."""
        if self.is_open:
            self.up = not self.hupcl
        self.is_open = False


@dataclass
class VirtualBoard:
    """A board on a simulated link: ``write`` and ``read`` take the time they happen."""

    core: BoardCore
    baud: int = DEFAULT_BAUD
    ready_at: float = 0.0  #: s; when the bootloader hands over to the sketch
    log: list[tuple[float, Write]] = field(default_factory=list)  #: (time, write)
    swallowed: int = 0  #: bytes lost while the board was booting
    stored: list[int] | None = None  #: the pose kept in EEPROM (None: never written)
    records: int = 0  #: poses stored (EEPROM records written)
    resets: int = 0

    def __post_init__(self) -> None:
        self.tau = byte_time(self.baud)
        self._inbox: deque[tuple[float, int]] = deque()  # (arrival, byte)
        self._outbox: deque[tuple[float, int]] = deque()  # (ready, byte)
        self._wire_free = 0.0  # when the host -> board line is next free
        self._out_free = 0.0  # when the board -> host line is next free
        self._clock = 0.0
        self._booted = False
        self._last_write: float | None = None  # a servo write not yet stored
        if self.stored is not None:
            self.core.restore(self.stored)

    def write(self, data: bytes, now: float) -> None:
        """The host sends ``data`` at ``now``; each byte arrives a byte-time later."""
        self.advance(now)
        for b in data:
            arrival = max(now, self._wire_free) + self.tau
            self._wire_free = arrival
            self._inbox.append((arrival, b))

    def read(self, now: float) -> bytes:
        """Everything the board has sent by ``now``."""
        self.advance(now)
        out = bytearray()
        while self._outbox and self._outbox[0][0] <= now:
            out.append(self._outbox.popleft()[1])
        return bytes(out)

    def reset(self, now: float, boot: float) -> None:
        """DTR rose: the board restarts at ``now`` from its stored pose (its rest pose if
        none), the bootloader swallowing bytes for ``boot`` s; what is on the wire is
        lost, and so is a pose that had not settled yet."""
        self.advance(now)
        self._inbox.clear()
        self._outbox.clear()
        self._last_write = None
        self.core.restore(self.stored)
        self.ready_at = now + boot
        self._booted = False
        self.resets += 1

    def advance(self, now: float) -> None:
        """Let the board run until ``now``."""
        if not self._booted and now >= self.ready_at:
            self._booted = True
            self._clock = self.ready_at
            self._send(self.ready_at, bytes([Signal.WAIT]))
        while self._inbox and self._inbox[0][0] <= now:
            arrival, byte = self._inbox.popleft()
            if arrival < self.ready_at:
                self.swallowed += 1
                continue
            self._settle(arrival)
            self._clock = arrival
            write, reply = self.core.feed(byte)
            if write is not None:
                self.log.append((arrival, write))
                self._last_write = arrival
            self._send(arrival, reply)
            idle = not self._inbox or self._inbox[0][0] > arrival
            if idle and self.core.pending is None:
                self._send(arrival, bytes([Signal.WAIT]))
        self._settle(now)

    def _settle(self, now: float) -> None:
        """Store the pose if it has settled by ``now`` and differs from the stored one."""
        if self._last_write is None or now - self._last_write < POSE_SETTLE:
            return
        self._last_write = None
        if self.core.values != self.stored:
            self.stored = list(self.core.values)
            self.records += 1

    def _send(self, at: float, data: bytes) -> None:
        for b in data:
            ready = max(at, self._out_free) + self.tau
            self._out_free = ready
            self._outbox.append((ready, b))

    def settled(self) -> list[int] | None:
        """The pose this board will have stored once what is on the wire has arrived and
        settled (None: never any): what it starts from at its next reset. The board
        itself does not move on."""
        log, self.log = self.log, []
        try:
            twin = copy.deepcopy(self)
        finally:
            self.log = log
        twin.advance(math.inf)
        return twin.stored

    def positions(self) -> dict[int, int]:
        """Servo ID -> the value the board last wrote (its DUMP values)."""
        return {s.id: v for s, v in zip(self.core.servos, self.core.values, strict=True)}
