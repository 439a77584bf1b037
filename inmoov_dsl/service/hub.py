"""What the HTTP thread and the drive loop share (an edge): requests one way, the
loop's notes the other, as events to every WebSocket; the pose as the boards hold it."""

from __future__ import annotations

import asyncio
import dataclasses
import queue
from collections.abc import Callable
from typing import Any

from ..compiling.plan import Planner
from ..compiling.reaching import solved
from ..errors import Diagnostic
from ..live.drive import Drive, Next, Note
from ..live.orders import Control, Order
from . import core
from .allowance import Allowance
from .work import Work

QUEUE = 1000  #: events kept for a WebSocket that reads slowly; older ones are dropped


class Lost(Exception):  # noqa: N818 (not an error of the request: of a cable)
    """A request needs boards whose link is down (HTTP 503)."""

    def __init__(self, boards: set[int]):
        super().__init__(boards)
        self.boards = boards


class Service:
    """What the HTTP thread and the drive loop share: requests one way, notes the other."""

    def __init__(self, program, profile, listing: Callable[[], list[dict[str, Any]]]):
        self.program, self.profile, self.listing = program, profile, listing
        self.requests: queue.Queue = queue.Queue()
        self.drive: Drive | None = None
        self.loop: asyncio.AbstractEventLoop | None = None
        self.listeners: set[asyncio.Queue] = set()
        self.lost: set[int] = set()  #: boards whose link is down
        self.view = None  #: the hand in 3-D (``views.webview.WebView``), when it can be
        #: makes the view, the first time the page asks where it is (None: tried)
        self.make_view: Callable[[], Any] | None = None
        #: refuses what drives the robot into itself (``model.guard.Guard``), or None
        self.collisions = None
        self.work = Work()  #: the requests' checks, off the event loop

    def prepare(self, doc: dict[str, Any], id: str) -> tuple[Order, tuple[Diagnostic, ...]]:
        """A play request made an Order and checked (a check's thread: ``work``): its
        warnings; a BadRequest (400), a GestError (422: it does not compile, says too
        much, ``Allowance``, or drives the robot into itself) or Lost (503)."""
        program = self.program
        if program.hear is not None:  # what the request may say, counted
            program = dataclasses.replace(program, hear=Allowance(program.hear))
        order = core.play_order(doc, program, self.profile, id)
        needed = core.boards_of(order.what.actions, self.profile) & self.lost
        if needed:
            raise Lost(needed)
        return dataclasses.replace(order, checked=True), self.check(order)

    def check(self, order: Order) -> tuple[Diagnostic, ...]:
        """A play request's steps planned from where the hand is going, as one gesture
        (its limits hold: a gesture lasts at most an hour, each pass of a loop), and
        checked against the guard (a 422 before anything moves; the drive loop plans
        each step again as it takes it): its warnings, or a GestError."""
        drive, what = self.drive, order.what
        if drive is None or not what.actions:
            return ()
        start = drive.session.current.plan.final
        steps, noted = solved(what.actions, start, self.profile, what.sources)
        planned = Planner(self.profile, what.sources).plan(steps, start)
        if self.collisions is None:
            return noted
        return noted + self.collisions.plan(planned, what.sources, order.allow_contact)

    def next_request(self, timeout: float) -> Next:
        """The drive loop's ``next_request``."""
        try:
            return self.requests.get(timeout=timeout) if timeout > 0 else \
                self.requests.get_nowait()
        except queue.Empty:
            return False

    def told(self, note: Note) -> None:
        """The drive loop's ``tell`` (its thread): the note as an event, if it is one."""
        if note.kind == "board-back":
            self.lost.discard(int(note.text))
            self.publish({"event": "board-back", "id": None, "board": int(note.text)})
            return
        event = core.note_event(note.kind, note.id, note.diagnostics)
        if event is not None:
            self.publish(event)

    def board_lost(self, board: int) -> None:
        """A board's link went away (the drive loop's thread): an event, and the other
        boards stop where they are."""
        if board not in self.lost:
            self.lost.add(board)
            self.publish({"event": "board-lost", "id": None, "board": board})
            self.requests.put(Control("stop", f"board-{board}-lost"))

    def publish(self, event: dict[str, Any]) -> None:
        """Send ``event`` to every WebSocket (from any thread)."""
        if self.loop is not None:
            self.loop.call_soon_threadsafe(self._fan_out, event)

    def _fan_out(self, event: dict[str, Any]) -> None:
        for listener in self.listeners:
            if listener.full():
                listener.get_nowait()
            listener.put_nowait(event)

    def view_url(self) -> str | None:
        """Where the page finds the hand in 3-D: made when first asked."""
        if self.view is None and self.make_view is not None:
            make, self.make_view = self.make_view, None
            self.view = make()
        return self.view.url if self.view is not None else None

    def pose(self) -> dict[str, Any]:
        """The pose as ``GET /api/pose`` gives it."""
        drive = self.drive
        now = drive.now()
        velocity = drive.session.state(now).velocity if drive.session.busy(now) else \
            (0.0,) * len(self.profile.servos)
        return core.pose(self.profile, drive.mirror.held(), velocity, drive.tracker.playing)

    def moving(self) -> bool:
        """Does the hand move (or wait in a gesture)?"""
        drive = self.drive
        return drive is not None and (drive.out.sending() or drive.session.busy(drive.now()))
