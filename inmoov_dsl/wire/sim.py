"""The virtual board: BoardCore on a simulated serial link, with the firmware's memory.

Bytes written by the host reach the board one byte-time apart at the board's baud;
bytes the bootloader would swallow (after a reset) are lost; the board answers DUMP and
sends WAIT whenever it is about to read a command and nothing is left to read, as the
firmware does. Every servo write is recorded with the time it happened. Like the
firmware, it keeps its pose once the pose has settled (no servo write for
POSE_SETTLE s: the EEPROM record) and starts from that pose after a reset. Time is
passed in, so the same board runs in real time behind ``sim://`` or on a test's clock.

With gestures stored in its flash (``flash``, the same bytes a build puts in the
image: ``stored.py``), it plays them as the firmware does: on PLAY N, at power-up, when
idle, when a button is pressed (``press``); any byte from the host stops them, and it
sends WAIT when one ends by itself (``stored_play.py``).
"""

from __future__ import annotations

import copy
import math
from collections import deque
from dataclasses import dataclass, field

from ..boards.base import Write
from ..boards.rig.core import BoardCore
from ..protocol import CATALOG, DEFAULT_BAUD, POSE_SETTLE, Signal, byte_time
from .line import Beats, HostLine
from .stored import BOOT_QUIET, DEBOUNCE, StoredSet, catalog_reply
from .stored_play import Playback

TX_BUFFER = 64  #: bytes the firmware's serial port holds: a catalog cut short still sends them
#: s; what the host side of a UART holds beyond its computer's buffer (the chip's FIFO,
#: a USB adapter's): a pty's reader takes bytes only this far ahead of the wire
UART_AHEAD = 0.005


@dataclass
class VirtualBoard(HostLine):
    """A board on a simulated link: ``write`` and ``read`` take the time they happen."""

    core: BoardCore
    baud: int = DEFAULT_BAUD
    ready_at: float = 0.0  #: s; when the bootloader hands over to the sketch
    log: list[tuple[float, Write]] = field(default_factory=list)  #: (time, write)
    swallowed: int = 0  #: bytes lost while the board was booting
    stored: list[int] | None = None  #: the pose kept in EEPROM (None: never written)
    records: int = 0  #: poses stored (EEPROM records written)
    resets: int = 0
    flash: StoredSet | None = None  #: the gestures stored in its flash
    chatty: bool = True  #: it sends WAIT when booted and idle (a rig; not a Maestro)
    hello: bytes = b""  #: what one not chatty sends as it boots (MrlComm: its banner)
    #: s of silence a bootloader waits for once a byte came while it ran (a Mega's
    #: STK500v2: a byte keeps it in its command loop); 0: it swallows the byte, no more
    trap: float = 0.0

    def __post_init__(self) -> None:
        self.tau = byte_time(self.baud)
        self._inbox: deque[tuple[float, int]] = deque()  # (arrival, byte)
        self._outbox: deque[tuple[float, int]] = deque()  # (ready, byte)
        self._wire_free = 0.0  # when the host -> board line is next free
        self._out_free = 0.0  # when the board -> host line is next free
        self._booted = False
        self._last_write: float | None = None  # a servo write not yet stored
        self.playing: Playback | None = None  #: the stored gesture it is playing
        self._own: list[tuple[float, int]] = []  # (when, gesture): buttons pressed
        self._boot_at: float | None = None  # when the boot gesture starts
        self._quiet = 0.0  # the last host byte, press or gesture's end
        self._catalog: list[float] = []  # when each catalog byte is ready (to cut it)
        self._triggers = True  # boot, idle and buttons may start gestures
        self._beats = Beats(getattr(self.core, "BEAT", math.inf))  # MrlComm's board info
        self._ring = getattr(self.core, "ring", None)  # a receive buffer read in its time
        if self.stored is not None:
            self.core.restore(self.stored)

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
        self.playing, self._own, self._catalog, self._boot_at = None, [], [], None
        self._beats.start(math.inf)
        self.core.restore(self.stored)
        self.ready_at = now + boot
        self._booted = False
        self.resets += 1

    def advance(self, now: float) -> None:
        """Let the board run until ``now``."""
        while not self._booted and self._inbox and self._inbox[0][0] <= now and \
                self._inbox[0][0] < self.ready_at:
            self._read()  # the bootloader has it (and one that a byte traps stays)
        if not self._booted and now >= self.ready_at:
            self._booted = True
            self._quiet = self.ready_at
            self._send(self.ready_at, bytes([Signal.WAIT]) if self.chatty else self.hello)
            if self.flash is not None and self.flash.boot is not None:
                self._boot_at = self.ready_at + BOOT_QUIET
            self._beats.start(self.ready_at)
        while True:
            arrival = self._inbox[0][0] if self._inbox else math.inf
            reading = self._ring.next_read() if self._ring is not None else math.inf
            due, start = self._due()
            first = min(arrival, reading, due)
            if first > now or first == math.inf:
                break
            if reading == first:
                self._take(*self._ring.take())
            elif arrival <= due:
                self._read()
            elif start is not None:
                self._play(due, start)
            else:
                self._step(due)
        for t in self._beats.until(now):
            self._send(t, self.core.beat())
            if self._ring is not None:  # it waits its board info out too
                self._ring.busy(self._out_free)
        self._settle(now)

    def _read(self) -> None:
        """The next byte on the wire reaches the board (or its receive ring, where it
        waits for the board's loop to read it)."""
        arrival, byte = self._inbox.popleft()
        if arrival < self.ready_at:
            self.swallowed += 1
            if self.trap:
                self.ready_at = arrival + self.trap
            return
        if self._ring is not None:
            self._ring.arrive(arrival, byte)
            return
        self._take(arrival, byte)

    def _take(self, arrival: float, byte: int) -> None:
        """The board reads ``byte`` at ``arrival`` (or when its loop takes it from its
        receive ring)."""
        self._settle(arrival)
        self._quiet = arrival
        self.playing = self._boot_at = None  # any byte stops what the board does itself
        _cut_catalog(self, arrival)
        write, reply = self.core.feed(byte)
        for one in write if isinstance(write, tuple) else (write,) if write else ():
            self._wrote(arrival, one)  # a command may set several servos
        self._send(arrival, reply)
        if self._ring is not None and self.core.pending is None:  # it waits its reply out
            self._ring.busy(max(arrival, self._out_free) + self._ring.read)
        asked = self.core.asked if self.flash is not None else None
        if asked is not None and asked < len(self.flash.gestures):
            self._play(arrival, asked)
        idle = not self._inbox or self._inbox[0][0] > arrival
        if idle and self.chatty and self.core.pending is None and self.playing is None:
            self._send(arrival, bytes([Signal.WAIT]))
        if asked == CATALOG:
            self._catalog = [self._send(arrival, catalog_reply(self.core.board_id,
                                                               self.flash.to_bytes()))]

    def _due(self) -> tuple[float, int | None]:
        """When the board next acts by itself, and the gesture it then starts (None: a
        step of the one it plays)."""
        if not self._booted or self.flash is None:
            return math.inf, None
        if self.playing is not None:
            return self.playing.due(), None
        if not self._triggers:
            return math.inf, None
        starts = list(self._own)
        if self._boot_at is not None:
            starts.append((self._boot_at, self.flash.boot))
        if self.flash.idle is not None and self._boot_at is None:
            starts.append((self._quiet + self.flash.idle_after, self.flash.idle))
        return min(starts, default=(math.inf, None))

    def _play(self, now: float, number: int) -> None:
        """Start stored gesture ``number`` at ``now``."""
        self._own = [o for o in self._own if o[0] > now]
        if self._boot_at is not None and self._boot_at <= now:
            self._boot_at = None
        if self.core.relaxed:
            self._wrote(now, self.core.command(0, self.core.values[0]))
        self.playing = Playback(self.flash, number, self.core.values, now)

    def _step(self, now: float) -> None:
        """What the stored gesture does at ``now``: writes, or its end (then WAIT)."""
        writes, over = self.playing.run()
        for index, value in writes:
            self._wrote(now, self.core.command(index, value))
        if over:
            self.playing, self._quiet = None, now
            if self.core.pending is None:
                self._send(now, bytes([Signal.WAIT]))

    def _wrote(self, now: float, write: Write) -> None:
        self.log.append((now, write))
        self._last_write = now

    def press(self, pin: int, now: float) -> None:
        """A button on ``pin`` is pressed at ``now`` (and held): its gesture starts once
        the press has lasted DEBOUNCE."""
        self.advance(now)
        for button, number in self.flash.buttons if self.flash is not None else ():
            if button == pin:
                self._own.append((now + DEBOUNCE, number))

    def _settle(self, now: float) -> None:
        """Store the pose if it has settled by ``now`` and differs from the stored one."""
        if self._last_write is None or now - self._last_write < POSE_SETTLE:
            return
        self._last_write = None
        if self.core.values != self.stored:
            self.stored = list(self.core.values)
            self.records += 1

    def _send(self, at: float, data: bytes) -> float:
        for b in data:
            self._out_free = max(at, self._out_free) + self.tau
            self._outbox.append((self._out_free, b))
        return self._out_free

    def positions(self) -> dict[int, int]:
        """Servo ID -> the value the board last wrote (its DUMP values)."""
        return {s.id: v for s, v in zip(self.core.servos, self.core.values, strict=True)}



def _cut_catalog(board: VirtualBoard, now: float) -> None:
    """A host byte cuts a catalog being sent short: what is not yet in the serial port's
    buffer is never sent."""
    if not board._catalog:
        return
    keep = now + TX_BUFFER * board.tau
    board._outbox = deque((t, b) for t, b in board._outbox if t <= keep)
    board._out_free = min(board._out_free, max((t for t, _ in board._outbox), default=now))
    board._catalog = []


def settled(board: VirtualBoard) -> list[int] | None:
    """The pose ``board`` will have stored once what is on the wire has arrived and
    settled (None: never any): what it starts from at its next reset. The board itself
    does not move on."""
    log, board.log = board.log, []
    try:
        twin = copy.deepcopy(board)
    finally:
        board.log = log
    twin._triggers = False  # a gesture playing ends; no other starts by itself
    twin.advance(math.inf)
    return twin.stored

def _fifo(board: VirtualBoard, ahead: float) -> int:
    """How many bytes ``ahead`` s of ``board``'s wire holds (at least one)."""
    return max(1, round(ahead / board.tau))


def room(board: VirtualBoard, now: float, ahead: float = UART_AHEAD) -> int:
    """How many bytes ``board``'s link takes from its computer at ``now``: the host's
    UART holds ``ahead`` s of bytes not yet on the wire (at least one)."""
    queued = max(0.0, board.sending_until() - now) / board.tau
    return max(0, _fifo(board, ahead) - math.ceil(queued - 1e-9))


def room_at(board: VirtualBoard, now: float, ahead: float = UART_AHEAD) -> float:
    """When ``board``'s link next takes a byte from its computer (``now`` if it can)."""
    if room(board, now, ahead):
        return now
    return board.sending_until() - (_fifo(board, ahead) - 1) * board.tau + 1e-6
