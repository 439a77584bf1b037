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
from typing import Any

from .. import clock
from ..boards.base import Controller
from ..boards.rig import commands
from ..clock import Clock, Sleep
from ..compiling.compiled import Compiled
from ..errors import Diagnostic
from ..protocol import CANCEL_PENDING, RELAX_BOARD
from .flow import awaited
from .pace import HORIZON, Pacer, Timed, discard_output
from .pace import pacer as pacer_for
from .ready import Port, drain

SPIN = 0.0005  #: s; sleep until this close to a deadline, then spin on the clock
AUDIO_AHEAD = 0.05  #: s; a gesture with sounds starts this late: its first sound on time
POLL = 0.2  #: s; in a long pause, look at the links this often (a pulled cable)


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
    hear: Callable[[bytes], None] | None = field(default=None, repr=False, compare=False)

    def listen(self) -> bytes:
        """What the board has sent (``drain``), passed on to ``hear`` (a sender awaiting
        its answers: ``flow``); what its kind reads in it (or in its silence) as a board
        that cannot go on (an MrlComm that restarted, stopped, or lost bytes) raises
        ``BoardTrouble``."""
        data = drain(self.port)
        if self.controller is not None:
            if self._watch is None:
                self._watch = self.controller.watch()
            if trouble := self._watch(data):
                raise BoardTrouble(Diagnostic(
                    "error", f"{trouble} (on {self.name})",
                    hint="play again: it is connected anew, its servos from where they are"))
        if self.hear is not None:
            self.hear(data)
        return data


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
    """Send each board's stream, on time: a rig's as one continuous run on the link's
    byte grid written ``horizon`` ahead (``pace``: the UART's clock times it), another
    kind's commands when due and no faster than its board reads them, each answer
    awaited (``flow``). Returns the worst lateness (s). With a ``speaker``, the sounds
    play from the same clock (their cues hold them), the gesture AUDIO_AHEAD later so
    that the first is on time; an interruption silences them. ``now``, ``sleep``: the
    clock (default ``clock.now``, read when called: a test's virtual clock drives all)."""
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
        for link, pacer in zip(links, pacers, strict=True):  # it read all, nothing lost
            if left := awaited(pacer, link.listen, now, sleep):
                raise BoardTrouble(Diagnostic(
                    "error", f"board {link.board} did not say it read {left} of the commands "
                    f"it was sent: they may be lost (on {link.name})",
                    hint="play again; if it happens again, check the board's cable and power"))
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
        out = pacer_for(link.port, c, horizon, answered=True) if c else \
            Pacer(link.port, stream.byte_time if stream else 0.0, horizon)
        link.hear = out.heard  # its board's answers free room for more (``flow``)
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
