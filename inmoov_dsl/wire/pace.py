"""A continuous stream: timing set by the wire's clock, not the operating system's.

A UART sends the bytes it holds exactly one byte-time apart, by its own crystal. So a
link is kept busy from a stream's first byte to its last: every command (the CANCEL,
each pair) sits at its place on the link's byte grid, the gaps between commands are
filled with CANCEL (a board waiting for a servo ID drops it: the original firmware and
ours alike), and each byte's time is fixed by its place in the run. The ``Pacer``
writes the run a short ``HORIZON`` ahead of the wire, so the player may wake late by
up to that much without any byte arriving late; should the wire run dry (the computer
stalled longer), the pacer leaves out filler until the run is on schedule again.

Why the horizon is 15 ms when a gesture plays: the pacer tops the port up every
``WAKE`` (3 ms), and on a two-core machine kept busy by other programs the player
slept past its time by up to 11.6 ms (benchmarks/timing.py, 2026-11-24), now and then
longer; a horizon of 10 ms ran dry in one run of three there (docs/benchmarks.md), 15 ms
in none. A longer stall costs a late byte, never a broken command. And the horizon
bounds what a stop cannot take back: a stop first drops what the port holds
(``discard_output``), but a USB adapter's chip, and a pseudo-terminal's other end, keep
what they have taken, at most the horizon; so a CANCEL still reaches the board within
a servo frame (20 ms) of Ctrl-C. Live control (the repl, the ROS node, the service)
writes ``LIVE_HORIZON`` (10 ms) ahead: a take-over goes out behind at most that much,
so a new request takes over within half a frame, and a stall there costs a late byte.

Filler never goes inside a command: a pair's value follows its ID at once.

A kind of board with no filler (a Maestro, a PCA9685, MrlComm: ``Controller.fill`` is
None) gets its commands from a ``Timed`` sender instead (``flow``): each written, whole,
when it is due, and no faster than the board reads them.
"""

from __future__ import annotations

import contextlib
import math
from collections.abc import Sequence

from ..boards.rig import commands
from ..protocol import Signal
from .flow import Timed

FILL = Signal.CANCEL  #: what fills the gaps: a board waiting for a servo ID drops it
HORIZON = 0.015  #: s; how far ahead of the wire a gesture is written (see above)
LIVE_HORIZON = 0.010  #: s; the same for live control
WAKE = 0.003  #: s; how often the pacer tops the port up


def place(offset: float, end: int, tau: float) -> int:
    """The place of a command due ``offset`` s after a run's first byte: the nearest
    grid point, but not before ``end`` (the place after the command before)."""
    return max(end, round(offset / tau))


def places(times: Sequence[float], data: bytes, tau: float, speed: float = 1.0) -> list[int]:
    """Each byte's place on the byte grid, counted in byte-times from the first: a
    command's first byte at its ``place`` (its time ``/ speed``); the rest of a command
    right after its first byte."""
    out: list[int] = []
    end = 0
    for first, stop in commands(data):
        at = place((times[first] - times[0]) / speed, end, tau)
        out += range(at, at + stop - first)
        end = at + stop - first
    return out


def padded(times: Sequence[float], data: bytes, tau: float, speed: float = 1.0) -> bytes:
    """The stream as one continuous run from its first byte: each byte at its place
    (``places``), FILL everywhere else."""
    where = places(times, data, tau, speed)
    run = bytearray([FILL]) * (where[-1] + 1 if where else 0)
    for at, byte in zip(where, data, strict=True):
        run[at] = byte
    return bytes(run)


class Pacer:
    """One link's continuous run: commands placed on its byte grid from the run's first
    byte (``epoch``, a clock time), FILL between them, written ``horizon`` ahead of the
    wire by ``pump``. It keeps the wire's account (a byte written to an idle wire goes
    at once, the next a byte-time after the one before): the first byte is written when
    it is due, and if the wire fell behind (the computer slept too long), filler is left
    out until the run is on schedule again. When the last byte has gone the run ends;
    the next command starts a new one."""

    def __init__(self, port, tau: float, horizon: float = HORIZON):
        self.port, self.tau, self.horizon = port, tau, horizon
        self.epoch: float | None = None  #: clock time of the run's place 0
        self._run = bytearray()  # the run's bytes from place self._base
        self._real = bytearray()  # 0: FILL; 1: a command's first byte; 2: the rest of it
        self._base = 0  # the place of _run[0]
        self.written = 0  #: places of the run given to the port (or left out)
        self._free = -math.inf  # when the wire has sent everything written
        self.late = 0.0  #: s; the most a command's byte has started late

    @property
    def end(self) -> int:
        """The place after the run's last byte."""
        return self._base + len(self._run)

    def pending(self) -> bool:
        """Has the run bytes not yet given to the port?"""
        return self.epoch is not None and self.written < self.end

    def add(self, t: float, command: bytes) -> None:
        """``command`` (a CANCEL, a pair, a signal) is due at clock time ``t``: at the
        grid point nearest ``t``, after what is already placed."""
        if self.epoch is None:  # a new run: after what the wire may still be sending
            self.epoch, self._base, self.written = max(t, self._free), 0, 0
            self._run.clear()
            self._real.clear()
        at = place(t - self.epoch, self.end, self.tau)
        gap = at - self.end
        self._run += bytes([FILL]) * gap + command
        self._real += bytes(gap) + (b"\x01" + b"\x02" * (len(command) - 1) if command else b"")

    def shift(self, dt: float) -> None:
        """The run starts ``dt`` s later (it was laid out from clock time 0)."""
        if self.epoch is not None:
            self.epoch += dt

    def pump(self, now: float) -> None:
        """Write what the wire will need until ``now + horizon``."""
        if self.epoch is None:
            return
        start = max(now, self._free)  # when the next byte written would start
        due = self.epoch + self.written * self.tau
        if start < due - 1e-9 and self._free <= now:
            return  # the wire is idle and the next byte is not due yet
        while start - due >= self.tau and self.written < self.end and \
                not self._real[self.written - self._base]:
            self.written += 1  # filler the wire had no time for
            due += self.tau
        ahead = math.ceil((now + self.horizon - start) / self.tau)
        target = min(self.end, self.written + max(0, ahead))
        while target < self.end and self._real[target - self._base] == 2:
            target += 1  # a command goes whole: its bytes back to back on the wire
        if target > self.written:
            chunk = slice(self.written - self._base, target - self._base)
            if any(self._real[chunk]):  # its commands start this much after their places
                self.late = max(self.late, start - due)
            self.port.write(bytes(self._run[chunk]))
            self._free = start + (target - self.written) * self.tau
            self.written = target
        drop = self.written - self._base
        if drop > 4096:  # what is written is not needed again
            del self._run[:drop]
            del self._real[:drop]
            self._base = self.written
        if self.written >= self.end and now >= self._free:
            self.epoch = None  # the run is over: the wire is idle

    def busy(self, now: float) -> bool:
        """Is the wire still sending what was written?"""
        return self._free > now

    def heard(self, data: bytes) -> None:
        """What the board sent (a run waits for no answer)."""

    def awaiting(self) -> int:
        """Commands written whose answer is awaited: a run awaits none."""
        return 0

    def unanswered(self) -> int:
        """Commands written whose answer has not come: a run awaits none."""
        return 0

    def next_wake(self, now: float) -> float:
        """When ``pump`` is next needed (a clock time; inf: nothing waits)."""
        if self.epoch is None:
            return math.inf
        if self._free <= now:  # idle: the run's next byte is due then
            return max(now, self.epoch + self.written * self.tau)
        return now + WAKE

    def discard(self) -> None:
        """Stop the run at once: drop what is not yet written and what the port still
        holds (``discard_output``). What a port keeps (a USB adapter's chip) cannot be
        known, so the wire's account stays as it was: the next run is placed after it
        (at most the horizon later), and its bytes are written at once, so they reach
        the board then or sooner, never behind bytes the account does not know of."""
        self.epoch = None
        self._run.clear()
        self._real.clear()
        self._base = self.written = 0
        discard_output(self.port)


def discard_output(port) -> None:
    """Drop what ``port`` holds unsent, where it can (pyserial's
    ``reset_output_buffer``; a port that cannot has sent it already)."""
    reset = getattr(port, "reset_output_buffer", None)
    if reset is not None:
        # a port that cannot discard (gone, or a termios error) leaves its bytes to go
        with contextlib.suppress(Exception):
            reset()


def pacer(port, controller, horizon: float = HORIZON, answered: bool = False
          ) -> Pacer | Timed:
    """The pacer for ``controller``'s board on ``port``: a continuous run with the
    kind's filler (the rig), else commands written when due, no faster than the board
    reads them (``flow``; ``answered``: the player passes on what the board sends)."""
    if controller.fill is None:
        return Timed(port, controller.tau, controller=controller, answered=answered)
    return Pacer(port, controller.tau, horizon)
