"""Playing compiled streams to boards (the only stage with a clock and ports).

Time is data until the last moment: every byte has a planned time, and the player
puts it at ``start + time / speed`` on one absolute clock, as a place in a continuous
run the UART's crystal times (``pace``), so neither lateness nor the operating
system's wake-ups reach the board. The clock, the sleep and the ports are passed in,
so tests can drive the player as a timeline.
"""

from __future__ import annotations

import contextlib
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any, Protocol

from .. import clock
from ..boards.base import Controller
from ..boards.rig import DumpReader, commands
from ..clock import Clock, Sleep
from ..compiling.compiled import Compiled
from ..errors import Diagnostic
from ..protocol import ASK_POSE, CANCEL_PENDING, RELAX_BOARD, Signal
from .pace import HORIZON, Pacer, Timed, discard_output
from .pace import pacer as pacer_for

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


class BoardTrouble(OSError):
    """A board said, while it played, that it cannot go on (``Controller.watch``)."""

    def __init__(self, diagnostic: Diagnostic):
        super().__init__(diagnostic.message)
        self.diagnostic = diagnostic


@dataclass
class Link:
    """One board's connection, and the board as its kind drives it (None: a rig)."""

    board: int
    port: Port
    name: str = ""
    controller: Controller | None = None
    _watch: Callable[[bytes], str | None] | None = field(default=None, repr=False,
                                                          compare=False)

    def listen(self) -> bytes:
        """What the board has sent (``drain``); what its kind reads in it (or in its
        silence) as a board that cannot go on (an MrlComm that started again, or
        stopped) raises ``BoardTrouble``."""
        data = drain(self.port)
        if self.controller is not None:
            if self._watch is None:
                self._watch = self.controller.watch()
            if trouble := self._watch(data):
                raise BoardTrouble(Diagnostic(
                    "error", f"{trouble} (on {self.name})",
                    hint="play again: it is connected anew, its servos from where they are"))
        return data


def drain(port: Port) -> bytes:
    """Whatever the board has sent (WAIT bytes, mostly); raises if the link is gone."""
    return port.read(4096)


def wait_ready(port: Port, now: Clock | None = None, sleep: Sleep | None = None,
               timeout: float = READY_TIMEOUT, controller: Controller | None = None,
               heard: bytearray | None = None) -> bool:
    """Wait until the board is ready. A rig (``controller`` None or a rig's): the WAIT
    it sends when it has booted (opening the port reset it) or the WAIT it answers a
    CANCEL with (the port kept DTR up, so it did not reset); another kind: its answer
    to its ``probe``. The probe goes out every PROBE s; a bootloader still running
    swallows it. False after ``timeout``. ``heard``: gets what the board answered."""
    now, sleep = now or clock.now, sleep or clock.sleep
    question = controller.probe() if controller else CANCEL_PENDING
    answered = controller.ready if controller else (lambda a: Signal.WAIT in a)
    answer = bytearray()
    deadline = now() + timeout
    probe = now()
    while now() < deadline:
        if now() >= probe:
            answer.clear()
            port.write(question)
            probe = now() + PROBE
        answer += drain(port)
        if answered(bytes(answer)):
            if heard is not None:
                heard += answer
            return True
        sleep(0.01)
    return False


def ask_dump(port: Port, board: int, now: Clock | None = None, sleep: Sleep | None = None,
             timeout: float = DUMP_TIMEOUT, controller: Controller | None = None
             ) -> dict[int, int] | None:
    """The board's servo values (ID -> value), or None if no reply: a rig's answer to
    CANCEL DUMP, another kind's to its ``ask_pose``."""
    now, sleep = now or clock.now, sleep or clock.sleep
    drain(port)
    port.write(controller.ask_pose() if controller else ASK_POSE)
    reader = controller.pose_reader() if controller else DumpReader(board)
    deadline = now() + timeout
    while now() < deadline:
        found = reader.feed(drain(port))
        if found is not None:
            return found
        more = getattr(reader, "ask", None)
        if more is not None and (question := more()):
            port.write(question)
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
                link.listen()
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
                link.listen()  # the board answers filler with WAIT; a pulled cable shows
            if progress is not None and (t - start) * speed - shown >= 0.1:
                shown = (t - start) * speed
                progress(min(shown, compiled.duration))
            t = now()
            wake = min(p.next_wake(t) for p in pacers)
            # a run's first byte goes when it is due (spin for it); the rest are timed
            # by the wire, and the player only tops the ports up
            starting = any(p.next_wake(t) == wake and not p.busy(t) for p in pacers)
            if wake < math.inf:  # (inf: the last commands were just written)
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
         horizon: float = HORIZON) -> list[Pacer | Timed]:
    """A pacer for each link, holding its board's stream from clock time ``start``."""
    by_board = {s.board: s for s in compiled.streams}
    pacers = []
    for link in links:
        stream = by_board.get(link.board)
        c = link.controller
        out = pacer_for(link.port, c, horizon) if c else \
            Pacer(link.port, stream.byte_time if stream else 0.0, horizon)
        if stream is not None:
            times = stream.times.tolist()
            for first, stop in (c.commands if c else commands)(stream.data):
                out.add(start + times[first] / speed, stream.data[first:stop])
        pacers.append(out)
    return pacers


def cancel_all(links: Sequence[Link]) -> None:
    """Stop every board we still can, at once: a rig's port drops what it still holds
    of a stream (``pace.discard_output``) and a CANCEL follows, so no half command is
    left pending; a kind with no filler was written whole commands only, and is left
    holding the last."""
    for link in links:
        c = link.controller
        _send(link, c.cancel() if c else CANCEL_PENDING, c is None or c.fill is not None)


def relax_all(links: Sequence[Link]) -> None:
    """Every board we can reach stops driving its servos (they go limp) until its next
    command, at once: a rig's ``protocol.RELAX_BOARD`` (CANCEL RELAX CANCEL, which the
    original firmware reads as a servo it does not have, and ignores), after what its
    port still holds is dropped; another kind's ``relax``."""
    for link in links:
        c = link.controller
        _send(link, c.relax() if c else RELAX_BOARD, c is None or c.fill is not None)


def _send(link: Link, data: bytes, discard: bool) -> None:
    with contextlib.suppress(OSError):  # a dead link cannot be reached; go on
        if discard:
            discard_output(link.port)
        if data:
            link.port.write(data)
