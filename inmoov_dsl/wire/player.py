"""Playing compiled streams to boards (the only stage with a clock and ports).

Time is data until the last moment: every byte has a planned time, and the player
puts it at ``start + time / speed`` on one absolute clock, as a place in a continuous
run the UART's crystal times (``pace``), so neither lateness nor the operating
system's wake-ups reach the board. The clock, the sleep and the ports are passed in,
so tests can drive the player as a timeline.
"""

from __future__ import annotations

import contextlib
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, Protocol

from .. import clock
from ..clock import Clock, Sleep
from ..compiling.compiled import Compiled
from ..decode import Replies
from ..protocol import ASK_POSE, CANCEL_PENDING, RELAX_BOARD, Signal
from .pace import HORIZON, Pacer, commands, discard_output

READY_TIMEOUT = 2.0  #: s; the longest we wait for a board to boot (its first WAIT)
PROBE = 0.1  #: s; while waiting for a board, send it a CANCEL this often
#: s; the longest we wait for a DUMP reply: a board answers within milliseconds, one in
#: a simulator on a machine kept busy by other programs took over half a second
DUMP_TIMEOUT = 1.0
SPIN = 0.0005  #: s; sleep until this close to a deadline, then spin on the clock
AUDIO_AHEAD = 0.05  #: s; a gesture with sounds starts this late: its first sound on time
POLL = 0.2  #: s; in a long pause, look at the links this often (a pulled cable)


class Port(Protocol):
    """What the player needs of a serial port (pyserial's, or a virtual board's)."""

    def write(self, data: bytes) -> int | None:
        """Send ``data``."""

    def read(self, size: int = 1) -> bytes:
        """Up to ``size`` bytes that have come (a port that never blocks: maybe none)."""


@dataclass
class Link:
    """One board's connection."""

    board: int
    port: Port
    name: str = ""


def drain(port: Port) -> bytes:
    """Whatever the board has sent (WAIT bytes, mostly); raises if the link is gone."""
    return port.read(4096)


def wait_ready(port: Port, now: Clock | None = None, sleep: Sleep | None = None,
               timeout: float = READY_TIMEOUT) -> bool:
    """Wait until the board is ready: the WAIT it sends when it has booted (opening the
    port reset it) or the WAIT it answers a CANCEL with (the port kept DTR up, so it did
    not reset). A CANCEL goes out every PROBE s; a bootloader still running swallows it.
    False after ``timeout``."""
    now, sleep = now or clock.now, sleep or clock.sleep
    deadline = now() + timeout
    probe = now()
    while now() < deadline:
        if now() >= probe:
            port.write(CANCEL_PENDING)
            probe = now() + PROBE
        if Signal.WAIT in drain(port):
            return True
        sleep(0.01)
    return False


def ask_dump(port: Port, board: int, now: Clock | None = None, sleep: Sleep | None = None,
             timeout: float = DUMP_TIMEOUT) -> dict[int, int] | None:
    """CANCEL, then DUMP: the board's servo values (ID -> value), or None if no reply."""
    now, sleep = now or clock.now, sleep or clock.sleep
    drain(port)
    port.write(ASK_POSE)
    replies = Replies(board)
    deadline = now() + timeout
    while now() < deadline:
        found = replies.feed(drain(port))
        if found is not None:
            return found[1]
        sleep(0.005)
    return None


def wait_until(deadline: float, links: Sequence[Link], now: Clock, sleep: Sleep,
               spin: float = SPIN) -> None:
    """Sleep until ``deadline`` (spinning for the last ``spin`` s); in long pauses drain
    the links now and then, so a pulled cable is noticed within a second."""
    while True:
        left = deadline - now()
        if left > POLL + spin:
            sleep(POLL)
            for link in links:
                drain(link.port)
        elif left > spin:
            sleep(left - spin)
        elif left > 0:
            sleep(0)  # spin: give the thread away, look at the clock again
        else:
            return


def play(compiled: Compiled, links: Sequence[Link], speed: float = 1.0,
         now: Clock | None = None, sleep: Sleep | None = None,
         progress: Callable[[float], None] | None = None, speaker: Any = None,
         horizon: float = HORIZON) -> float:
    """Send each board's stream as one continuous run (``pace``): every byte at its
    place on the link's byte grid, CANCEL between commands, written ``horizon`` ahead
    of the wire, so the UART's clock times the bytes. Returns the worst lateness in
    seconds (a command that started late because the computer slept past the
    horizon). With a ``speaker`` (``audio.Speaker``), the gesture's sounds play from
    the same clock (their cues hold them), the whole gesture a moment later
    (AUDIO_AHEAD) so that the first sound can be placed on time; an interruption
    silences them. ``now`` and ``sleep``: the clock (default ``clock.now``, read when
    called, so a test's virtual clock drives every tool)."""
    now, sleep = now or clock.now, sleep or clock.sleep
    sounds = compiled.sounds if speaker is not None else ()
    pacers = runs(compiled, links, 0.0, speed, horizon)
    start = now() + (AUDIO_AHEAD if sounds else 0.0)  # once the runs are laid out
    for pacer in pacers:
        pacer.shift(start)
    for cue in sounds:
        speaker.play(cue.sound, start + cue.start)
    try:
        wait_until(start, links, now, sleep)
        shown = -1.0
        while any(p.pending() for p in pacers):
            t = now()
            for pacer in pacers:
                pacer.pump(t)
            for link in links:
                drain(link.port)  # the board answers filler with WAIT; a pulled cable shows
            if progress is not None and (t - start) * speed - shown >= 0.1:
                shown = (t - start) * speed
                progress(min(shown, compiled.duration))
            t = now()
            wake = min(p.next_wake(t) for p in pacers)
            # a run's first byte goes when it is due (spin for it); the rest are timed
            # by the wire, and the player only tops the ports up
            starting = any(p.next_wake(t) == wake and not p.busy(t) for p in pacers)
            wait_until(wake, links, now, sleep, SPIN if starting else 0.0)
        wait_until(start + compiled.duration / speed, links, now, sleep)
    except BaseException:
        if sounds:
            speaker.stop()
        raise
    if progress is not None:
        progress(compiled.duration)
    return max((p.late for p in pacers), default=0.0)


def runs(compiled: Compiled, links: Sequence[Link], start: float, speed: float = 1.0,
         horizon: float = HORIZON) -> list[Pacer]:
    """A pacer for each link, holding its board's stream from clock time ``start``."""
    by_board = {s.board: s for s in compiled.streams}
    pacers = []
    for link in links:
        stream = by_board.get(link.board)
        pacer = Pacer(link.port, stream.byte_time if stream else 0.0, horizon)
        if stream is not None:
            times = stream.times.tolist()
            for first, stop in commands(stream.data):
                pacer.add(start + times[first] / speed, stream.data[first:stop])
        pacers.append(pacer)
    return pacers


def cancel_all(links: Sequence[Link]) -> None:
    """Send CANCEL everywhere we still can, at once: what the ports still hold of a
    stream is dropped first (``pace.discard_output``), and no half command is left
    pending."""
    _send_all(links, CANCEL_PENDING)


def relax_all(links: Sequence[Link]) -> None:
    """Every board we can reach stops driving its servos (they go limp) until its next
    command: ``protocol.RELAX_BOARD`` (CANCEL RELAX CANCEL, which the original firmware
    reads as a servo it does not have, and ignores), at once: what the ports still hold
    is dropped first."""
    _send_all(links, RELAX_BOARD)


def _send_all(links: Sequence[Link], data: bytes) -> None:
    for link in links:
        with contextlib.suppress(OSError):  # a dead link cannot be reached; go on
            discard_output(link.port)
            link.port.write(data)
