"""The virtual board: BoardCore on a simulated serial link.

Bytes written by the host reach the board one byte-time apart at the board's baud;
bytes the bootloader would swallow (the board resets when its port is opened) are
lost; the board answers DUMP and sends WAIT whenever it is about to read a command
and nothing is left to read, as the firmware does. Every servo write is recorded with
the time it happened. Time is passed in, so the same board runs in real time behind
``sim://`` or on a test's fake clock.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass, field

from .board import BoardCore, Write
from .protocol import Signal, byte_time


@dataclass
class VirtualBoard:
    core: BoardCore
    baud: int = 9600
    ready_at: float = 0.0  #: s; when the bootloader hands over to the sketch
    log: list[tuple[float, Write]] = field(default_factory=list)  #: (time, write)
    swallowed: int = 0  #: bytes lost while the board was booting

    def __post_init__(self) -> None:
        self.tau = byte_time(self.baud)
        self._inbox: deque[tuple[float, int]] = deque()  # (arrival, byte)
        self._outbox: deque[tuple[float, int]] = deque()  # (ready, byte)
        self._wire_free = 0.0  # when the host -> board line is next free
        self._out_free = 0.0  # when the board -> host line is next free
        self._clock = 0.0
        self._booted = False

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
            self._clock = arrival
            write, reply = self.core.feed(byte)
            if write is not None:
                self.log.append((arrival, write))
            self._send(arrival, reply)
            idle = not self._inbox or self._inbox[0][0] > arrival
            if idle and self.core.pending is None:
                self._send(arrival, bytes([Signal.WAIT]))

    def _send(self, at: float, data: bytes) -> None:
        for b in data:
            ready = max(at, self._out_free) + self.tau
            self._out_free = ready
            self._outbox.append((ready, b))

    def positions(self) -> dict[int, int]:
        """Servo ID -> the value the board last wrote (its DUMP values)."""
        return {s.id: v for s, v in zip(self.core.servos, self.core.values, strict=True)}
