"""A virtual board's serial line in time: the host's bytes on their way to it
(``HostLine``), and what it says by itself every so often (``Beats``: MrlComm's board
info, every second)."""

from __future__ import annotations

import math
from collections import deque


class HostLine:
    """The host's side of a virtual board's serial line (``sim.VirtualBoard``): each
    byte written arrives a byte-time after the one before (``_inbox``: arrival, byte),
    until the board ``advance``s and reads it."""

    tau: float
    _inbox: deque[tuple[float, int]]
    _wire_free: float  # when the host -> board line is next free

    def advance(self, now: float) -> None:
        """Let the board run until ``now``."""
        raise NotImplementedError

    def write(self, data: bytes, now: float) -> list[float]:
        """The host sends ``data`` at ``now``: each byte starts on the wire when the one
        before has gone, and arrives a byte-time later. Returns when each starts."""
        self.advance(now)
        starts = []
        for b in data:
            starts.append(max(now, self._wire_free))
            self._wire_free = starts[-1] + self.tau
            self._inbox.append((self._wire_free, b))
        return starts

    def discard(self, now: float) -> int:
        """The host drops what it has written and the wire has not begun to send by
        ``now`` (a port's output buffer reset); returns how many bytes."""
        self.advance(now)
        kept = deque((t, b) for t, b in self._inbox if t - self.tau <= now)
        dropped = len(self._inbox) - len(kept)
        self._inbox = kept
        self._wire_free = kept[-1][0] if kept else min(self._wire_free, now)
        return dropped

    def sending_until(self) -> float:
        """When the last byte written so far has arrived."""
        return self._wire_free


class Beats:
    """When a core that speaks by itself every ``period`` s (MrlComm: its board info)
    says it again."""

    def __init__(self, period: float):
        self.period, self.next = period, math.inf

    def start(self, at: float) -> None:
        """It booted at ``at`` (inf: it is off)."""
        self.next = at + self.period

    def until(self, now: float) -> list[float]:
        """When it spoke up to ``now`` (of a board left alone for long, the last few)."""
        if not self.next <= now < math.inf:
            return []
        times = []
        self.next = max(self.next, now - 3 * self.period)
        while self.next <= now:
            times.append(self.next)
            self.next += self.period
        return times
