"""Playing compiled streams to boards (the only stage with a clock and ports).

Time is data until the last moment: every byte has a planned time, and the player
sends it at ``start + time / speed`` on one absolute clock, so lateness never
accumulates. The clock, the sleep and the ports are passed in, so tests can drive the
player as a timeline.
"""

from __future__ import annotations

import contextlib
import heapq
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, Protocol

from .. import clock
from ..clock import Clock, Sleep
from ..compiling.compiled import Compiled
from ..decode import Replies
from ..protocol import ASK_POSE, CANCEL_PENDING, RELAX_BOARD, SERVO_FRAME, Signal

READY_TIMEOUT = 2.0  #: s; the longest we wait for a board to boot (its first WAIT)
PROBE = 0.1  #: s; while waiting for a board, send it a CANCEL this often
DUMP_TIMEOUT = 0.5  #: s; the longest we wait for a DUMP reply
SPIN = 0.0005  #: s; sleep until this close to a deadline, then spin on the clock
#: s; the same for runs of bytes: about 50 wake-ups a second can afford to wake this
#: early, which keeps them on time when other programs keep every core busy
RUN_SPIN = 0.003
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


def wait_ready(port: Port, now: Clock = clock.now, sleep: Sleep = clock.sleep,
               timeout: float = READY_TIMEOUT) -> bool:
    """Wait until the board is ready: the WAIT it sends when it has booted (opening the
    port reset it) or the WAIT it answers a CANCEL with (the port kept DTR up, so it did
    not reset). A CANCEL goes out every PROBE s; a bootloader still running swallows it.
    False after ``timeout``."""
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


def ask_dump(port: Port, board: int, now: Clock = clock.now, sleep: Sleep = clock.sleep,
             timeout: float = DUMP_TIMEOUT) -> dict[int, int] | None:
    """CANCEL, then DUMP: the board's servo values (ID -> value), or None if no reply."""
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


def schedule(compiled: Compiled, links: Sequence[Link]) -> list[tuple[float, int, int]]:
    """Every byte of every board, in time order: (seconds, link index, byte)."""
    by_board = {link.board: k for k, link in enumerate(links)}
    streams = [[(t, by_board[s.board], b) for t, b in zip(s.times.tolist(), s.data,
                                                            strict=True)]
               for s in compiled.streams if s.board in by_board]
    return list(heapq.merge(*streams))


def bursts(compiled: Compiled, links: Sequence[Link]) -> list[tuple[float, int, bytes]]:
    """The bytes of every board as writes, in time order: (seconds, link index, bytes).

    A write is a run of one board's bytes each due one byte-time after the one before
    (the pairs packed at a frame's end), no longer than a servo frame: written when its
    first byte is due, the wire spaces the rest exactly as planned. A playing hand then
    needs about 50 wake-ups a second instead of one per byte."""
    by_board = {link.board: k for k, link in enumerate(links)}
    runs = []
    for s in compiled.streams:
        if s.board not in by_board:
            continue
        k, tau = by_board[s.board], s.byte_time
        times = s.times.tolist()
        first = 0
        for i in range(1, len(times) + 1):
            if i == len(times) or times[i] - times[i - 1] > tau * (1 + 1e-6) \
                    or times[i] - times[first] >= SERVO_FRAME:
                runs.append((times[first], k, s.data[first:i]))
                first = i
    return sorted(runs, key=lambda r: (r[0], r[1]))


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
         now: Clock = clock.now, sleep: Sleep = clock.sleep,
         progress: Callable[[float], None] | None = None, speaker: Any = None) -> float:
    """Send every byte at its planned time; returns the worst lateness in seconds. With
    a ``speaker`` (``audio.Speaker``), the gesture's sounds play from the same clock
    (their cues hold them), the whole gesture a moment later (AUDIO_AHEAD) so that the
    first sound can be placed on time; an interruption silences them.

    At full speed a run of bytes due one byte-time apart goes in one write, which the
    wire spaces as planned (``bursts``), and the player wakes RUN_SPIN before each;
    slower, each byte is written on its own, SPIN after waking."""
    runs = speed == 1
    events = bursts(compiled, links) if runs else \
        [(t, k, bytes([b])) for t, k, b in schedule(compiled, links)]
    spin = RUN_SPIN if runs else SPIN
    sounds = compiled.sounds if speaker is not None else ()
    start = now() + (AUDIO_AHEAD if sounds else 0.0)
    for cue in sounds:
        speaker.play(cue.sound, start + cue.start)
    try:
        return _send(compiled, links, events, start, speed, now, sleep, spin, progress)
    except BaseException:
        if sounds:
            speaker.stop()
        raise


def _send(compiled: Compiled, links: Sequence[Link], events, start: float, speed: float,
          now: Clock, sleep: Sleep, spin: float,
          progress: Callable[[float], None] | None) -> float:
    """``play``'s loop: each byte at its time from ``start``; the worst lateness."""
    worst, shown = 0.0, -1.0
    for t, k, data in events:
        due = start + t / speed
        wait_until(due, links, now, sleep, spin)
        links[k].port.write(data)
        worst = max(worst, now() - due)
        if progress is not None and t - shown >= 0.1:
            progress(t)
            shown = t
    wait_until(start + compiled.duration / speed, links, now, sleep)
    if progress is not None:
        progress(compiled.duration)
    return worst


def cancel_all(links: Sequence[Link]) -> None:
    """Send CANCEL everywhere we still can: no half command is left pending."""
    _send_all(links, CANCEL_PENDING)


def relax_all(links: Sequence[Link]) -> None:
    """Every board we can reach stops driving its servos (they go limp) until its next
    command: ``protocol.RELAX_BOARD`` (CANCEL RELAX CANCEL, which the original firmware
    reads as a servo it does not have, and ignores)."""
    _send_all(links, RELAX_BOARD)


def _send_all(links: Sequence[Link], data: bytes) -> None:
    for link in links:
        with contextlib.suppress(OSError):  # a dead link cannot be reached; go on
            link.port.write(data)
