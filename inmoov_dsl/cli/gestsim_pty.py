"""gestsim's side of the pseudo-terminal (an edge): the bytes a program writes reach
the virtual board as a UART takes them, the board's replies go back, and the board
resets as the program raises DTR."""

from __future__ import annotations

import _thread
import contextlib
import gc
import os
import select
import threading
from collections.abc import Callable
from typing import TextIO

from .. import clock
from ..wire.dtr import DtrLine
from ..wire.glove import VirtualGlove
from ..wire.sim import VirtualBoard, room_at
from ..wire.sim import room as uart_room


class Pty:
    """The board's side of the pseudo-terminal: bytes in, replies out, resets as the
    program on the other side raises DTR."""

    def __init__(self, master: int, boot: float, glove: list[tuple[float, bytes]] | None,
                 views: list, log: TextIO | None,
                 new_board: Callable[[float], VirtualBoard]):
        self.master, self.boot, self.glove, self.views, self.log = master, boot, glove, views, log
        self.new_board = new_board
        self.board: VirtualBoard | VirtualGlove | None = None
        self.line = DtrLine()  # no program has the port open yet
        self._left = False  # the last read filled the UART: bytes may wait in the pty
        self._turn = 0.0  # when the last turn was
        self.drawing: threading.Lock | None = None  #: held while drawing, among boards

    def serve(self) -> None:
        """The board on the desk, drawn; then forever: wait up to 5 ms for bytes (while
        the UART has room for them: what it has no room for stays in the computer's
        buffer, where the program may still discard it), then let the board read and
        answer."""
        self.start(clock.now())
        poller = select.poll()
        poller.register(self.master, select.POLLIN)
        while True:
            now = clock.now()
            full = self._room_at(now) - now
            if full > 0:  # the UART is full: the pty is not looked at
                clock.sleep(min(full, 0.005))
                self.tick(0, clock.now(), looked=False)
            else:
                self.tick(dict(poller.poll(5)).get(self.master, 0), clock.now())

    def _room_at(self, now: float) -> float:
        """When the board's UART takes the next byte from the pty."""
        board = self.board
        return room_at(board, now) if isinstance(board, VirtualBoard) else now

    def start(self, now: float) -> None:
        """A board is powered before any program opens its port: it is there, in its
        rest pose, and drawn at once (the first open resets it, as DTR rises). A glove
        starts its gesture when the port opens."""
        if self.glove is None:
            self.board = self.new_board(now + self.boot)
            self._draw(now)

    def tick(self, flags: int, now: float, looked: bool = True) -> None:
        """One turn: read what came (``looked``: the pty was polled), notice a close or
        an open, let the board answer."""
        data = b""
        board = self.board
        room = uart_room(board, now) if isinstance(board, VirtualBoard) else 4096
        if flags & select.POLLIN and room:  # first: the last bytes may come with a hang-up
            try:
                data = os.read(self.master, room)
            except OSError:  # EIO: the other side has closed
                data = b""
        if flags & select.POLLHUP and not data and not (flags & select.POLLIN and not room):
            self.line.closed()  # the bytes already on the wire still arrive
            self._left = False
            if self.board is not None:
                self.board.read(now)
                self._draw(now)
            clock.sleep(0.01)
            return
        if not self.line.is_open:  # a program opened the port: if DTR rises, a reset
            self._opened(now)
        self.line.hupcl = _hupcl(self.master)
        if data:
            # bytes left in the pty at the last turn have waited since then: the UART
            # took each as soon as it had room, however late this turn came round
            starts = self.board.write(data, self._turn if self._left else now)
            if self.log is not None:
                self.log.write("".join(f"{t:.6f} {b}\n" for t, b in zip(starts or
                                       [now] * len(data), data, strict=True)))
                self.log.flush()
        if looked:  # bytes are left in the pty if the read took all the UART had room for
            self._left = bool(data) and len(data) == room
        self._turn = now
        out = self.board.read(now)
        if out:
            try:
                os.write(self.master, out)
            except OSError:  # the other side closed meanwhile
                self.line.closed()
        self._draw(now)

    def _opened(self, now: float) -> None:
        self._left = False
        rose = self.line.opened()
        if self.glove is not None:
            self.board = VirtualGlove(self.glove, now + self.boot)
        elif self.board is None:
            self.board = self.new_board(now + self.boot)
        elif rose:
            self.board.reset(now, self.boot)

    def _draw(self, now: float) -> None:
        if self.drawing is None:
            for view in self.views:
                view.draw(self.board, now)
            return
        with self.drawing:  # the views are shared with other boards' threads
            for view in self.views:
                view.draw(self.board, now)


def serve(ptys: list[Pty]) -> None:
    """Each board on its pseudo-terminal, until stopped: one board in this thread; with
    several, each but the first in a thread of its own (its loop as a lone board's:
    one board's hung-up port or pause never holds another's reads), drawing into the
    views one at a time. A thread that fails stops gestsim with its error."""
    gc.freeze()  # what is loaded stays: the collector's pauses stay short
    _as_on_a_chip_of_its_own()
    if len(ptys) == 1:
        ptys[0].serve()
        return
    lock, stopped = threading.Lock(), threading.Event()
    failed: list[BaseException] = []
    for pty in ptys:
        pty.drawing = lock

    def run(pty: Pty) -> None:
        try:
            pty.serve()
        except BaseException as exc:  # noqa: BLE001 (told by the main thread)
            if not stopped.is_set():  # (not the ports closed as gestsim stops)
                failed.append(exc)
                _thread.interrupt_main()

    for pty in ptys[1:]:
        threading.Thread(target=run, args=(pty,), name="gestsim-board", daemon=True).start()
    try:
        ptys[0].serve()
    except KeyboardInterrupt:
        if failed:
            raise failed[0] from None
        raise
    finally:
        stopped.set()


BOARD_NICE = -10  #: the boards' priority, where they may have it (as root)


def _as_on_a_chip_of_its_own() -> None:
    """A real board runs on a chip of its own, whatever the computer's load: the boards
    served here (this thread and those it starts) ask for the CPU before the programs
    beside them where allowed (as root); elsewhere they keep the priority they have. A
    board starved by a busy machine stops reading its port, and a player's write times
    out as if it had been unplugged. They take only what real time needs: idle, they wait."""
    with contextlib.suppress(OSError, AttributeError):  # not allowed; not on this system
        os.setpriority(os.PRIO_PROCESS, 0, BOARD_NICE)


def _as_a_serial_device(slave: int) -> None:
    """Give the pty a serial device's default: HUPCL set (the last close drops DTR), so
    a program that reads it right after opening the port knows the open reset the
    board, as it knows of a real one (``ports.dtr_rose``)."""
    import termios

    attrs = termios.tcgetattr(slave)
    attrs[2] |= termios.HUPCL
    termios.tcsetattr(slave, termios.TCSANOW, attrs)


def open_pty(masters: list[int]) -> str:
    """A new pseudo-terminal set up as a serial port: its master kept in ``masters``,
    its path returned."""
    import tty

    master, slave = os.openpty()
    masters.append(master)
    path = os.ttyname(slave)
    tty.setraw(slave)
    _as_a_serial_device(slave)
    os.close(slave)
    return path


def _hupcl(master: int) -> bool:
    """Does the program that has the pty open leave HUPCL set (DTR drops when it
    closes)? A pty's settings are the ones the program set on its side."""
    import termios  # POSIX only, as gestsim is

    try:
        return bool(termios.tcgetattr(master)[2] & termios.HUPCL)
    except termios.error:
        return True
