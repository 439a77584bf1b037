"""The robot in 3-D in a browser, live: the page of ``gestsim --web`` (an edge: HTTP and
a websocket on 127.0.0.1, through viser, an optional extra).

viser serves its own client (a page built into its wheel: nothing is fetched from the
network) and draws the profile's URDF model (``urdf.model``) through yourdfpy. One page
shows every board gestsim serves: each board's loop hands over its values (``update``,
cheap: a copy when they changed); a thread of its own turns them into joint positions
(``joints.positions``) and moves the model, at most FRAME apart, and sleeps while
nothing changes.
"""

from __future__ import annotations

import threading
from collections.abc import Sequence
from typing import Any

from ..hardware import Board, Profile
from .scene import HOST, Robot, need_viser, start_server, stop_server

FRAME = 1 / 30  #: s between two updates of the page, at most 30 a second


class WebView:
    """A page on ``http://127.0.0.1:PORT/`` where the profile's model takes the pose of
    its ``boards`` (one, or several), live. ``port`` 0 takes any free one; a busy one,
    the next free."""

    def __init__(self, profile: Profile, boards: Board | Sequence[Board], port: int):
        viser, _, _ = need_viser()
        self.profile = profile
        self.boards = [boards] if isinstance(boards, Board) else list(boards)
        self.slots = {b.id: [profile.index(name) for name in b.servos] for b in self.boards}
        self.values = [s.rest for s in profile.servos]  #: the whole robot, profile order
        self.server = start_server(viser, port)
        try:
            self._furnish(self.boards)
        except BaseException:
            self.close()
            raise
        self.port: int = self.server.get_port()
        self.url = f"http://{HOST}:{self.port}/"
        self.shown: list[int] | None = None  #: the whole robot's, as ``pose`` gave them
        self._seen: dict[int, list[int]] = {}  #: each board's values, as last handed over
        self._pending: dict[int, list[int]] = {}
        self._lock = threading.Lock()
        self._whole = False  #: ``pose`` gave the whole robot's values
        self._wake, self._closing = threading.Event(), threading.Event()
        self._thread = threading.Thread(target=self._run, name="gestsim-web", daemon=True)
        self._thread.start()

    def _furnish(self, boards: list[Board]) -> None:
        """The scene: the model at rest on a floor, the camera on what the boards move
        (the whole robot, for all its boards)."""
        server = self.server
        named = ", ".join(f"{b.id} ({b.name})" for b in boards)
        server.gui.set_panel_label(f"gestsim: {self.profile.name}, board"
                                   f"{'s' if len(boards) > 1 else ''} {named}")
        server.gui.main_panel.minimize()  # the robot has the page; the panel is a click away
        self.robot = Robot(server, self.profile, [n for b in boards for n in b.servos])
        self.actuated: list[str] = self.robot.actuated  # every servo's joint

    def configuration(self, values: Sequence[float]) -> Any:
        """The model's actuated joints' positions (radians, its order) for the values
        of the profile's servos (profile order); a joint no servo turns stays at 0."""
        return self.robot.configuration(values)

    def draw(self, board: Any, now: float) -> None:
        """Called by the loop of the (first) board on every turn: ``update``."""
        self.update(self.boards[0].id, board.core.values, now)

    def update(self, board: int, values: Sequence[int], now: float) -> None:
        """Board ``board`` holds ``values`` (its servos' order): hand them over if they
        changed (the page is moved by the view's own thread)."""
        if values == self._seen.get(board):
            return
        self._seen[board] = list(values)
        with self._lock:
            self._pending[board] = self._seen[board]
        self._wake.set()

    def pose(self, values: Sequence[int]) -> None:
        """Hand over the whole robot's values (profile order), if they changed: for a
        page that shows every board (``gestplay serve``)."""
        values = list(values)
        if values == self.shown:
            return
        self.shown = values
        with self._lock:
            self._pending.clear()
            self.values = list(values)
            self._whole = True
        self._wake.set()

    def _run(self) -> None:
        """Until closed: wait for new values, move the model, pause a frame."""
        while True:
            self._wake.wait()
            if self._closing.is_set():
                return
            self._wake.clear()
            with self._lock:
                boards, self._pending = self._pending, {}
                whole, self._whole = self._whole, False
                for board, held in boards.items():
                    for slot, value in zip(self.slots[board], held, strict=True):
                        self.values[slot] = value
                values = list(self.values)
            if boards or whole:
                self.robot.pose(values)
            if self._closing.wait(FRAME):
                return

    def close(self) -> None:
        """Stop the thread and the server (the page then shows it is disconnected)."""
        if hasattr(self, "_closing"):
            self._closing.set()
            self._wake.set()
            self._thread.join(timeout=2)
        stop_server(self.server)

