"""Boards that may be unplugged while the service runs (an edge): a lost link is an
event, its bytes go nowhere until it comes back, and a watcher opens it again, asks the
board its pose and hands the board back to the drive loop, which goes on from there."""

from __future__ import annotations

import contextlib
import threading
from collections.abc import Callable

import serial

from ..boards import controller
from ..errors import GestError
from ..hardware import Profile
from ..live.orders import Rejoin
from ..wire.link import open_board
from ..wire.pace import discard_output
from ..wire.player import Link
from ..wire.ready import ask_dump, wait_ready

RETRY = 0.5  #: s between attempts to open a lost board's port again


class Resilient:
    """A board's port that does not raise when the board goes away: writes are dropped
    and reads are empty until ``back`` gives it a new port. A board that says it cannot
    go on (an MrlComm that started again, its servos gone: ``Controller.watch``) is
    taken as gone, and joins again as one that came back."""

    def __init__(self, link: Link, lost: Callable[[int], None]):
        self.board, self.name, self.port = link.board, link.name, link.port
        self.lost, self.down = lost, False
        self.lock = threading.Lock()
        self.controller = link.controller
        self.watch = link.controller.watch() if link.controller else None

    def write(self, data: bytes) -> int:
        """Send ``data`` (dropped while the board is away)."""
        with self.lock:
            if not self.down:
                try:
                    return self.port.write(data)
                except (serial.SerialException, OSError):
                    self._lose()
            return len(data)

    def read(self, size: int = 1) -> bytes:
        """What the board has sent (nothing while it is away)."""
        with self.lock:
            if not self.down:
                try:
                    data = self.port.read(size)
                except (serial.SerialException, OSError):
                    self._lose()
                    return b""
                if self.watch is not None and self.watch(data):  # silence too
                    self._lose()
                    return b""
                return data
            return b""

    def reset_output_buffer(self) -> None:
        """Drop what the port holds unsent (a stop or a take-over goes at once)."""
        with self.lock:
            if not self.down:
                discard_output(self.port)

    def _lose(self) -> None:
        self.down = True
        with contextlib.suppress(serial.SerialException, OSError):
            self.port.close()
        self.lost(self.board)

    def back(self, port) -> None:
        """The board is there again, on ``port``."""
        with self.lock:
            self.port, self.down = port, False
            self.watch = self.controller.watch() if self.controller else None

    def close(self) -> None:
        """Close the port."""
        with self.lock:
            if not self.down:
                self.port.close()


class Watcher:
    """Opens lost boards' ports again, every RETRY s, until the service stops."""

    def __init__(self, ports: list[Resilient], profile: Profile,
                 request: Callable[[object], None]):
        self.ports, self.profile, self.request = ports, profile, request
        self.stopping = threading.Event()
        self.thread = threading.Thread(target=self._run, name="board-watcher", daemon=True)

    def start(self) -> None:
        """Watch."""
        self.thread.start()

    def stop(self) -> None:
        """Stop watching."""
        self.stopping.set()
        self.thread.join(timeout=5)

    def _run(self) -> None:
        while not self.stopping.wait(RETRY):
            for port in self.ports:
                if port.down and not self.stopping.is_set():
                    self._try(port)

    def _try(self, lost: Resilient) -> None:
        try:
            board = next(b for b in self.profile.boards if b.id == lost.board)
            port = open_board(lost.name, self.profile, board)
        except GestError:
            return
        kind, heard = controller(self.profile, board), bytearray()
        ready = wait_ready(port, controller=kind, heard=heard)
        values = ask_dump(port, lost.board, controller=kind) if ready else None
        if values is None:
            port.close()
            return
        if setup := kind.setup(bytes(heard), values):
            port.write(setup)
        lost.back(port)
        self.request(Rejoin(lost.board, values))
