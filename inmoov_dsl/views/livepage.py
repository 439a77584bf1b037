"""The live preview page of a gesture (an edge: viser's server on 127.0.0.1, the ``web``
extra): the robot of the gesture's profile in 3-D, posed by its plan; its timeline;
play, pause, loop, scrub and speed; the steps, the one under the editor's cursor
highlighted; a button that plays it on a robot.

Whoever follows the text (``gestc preview --live``, the language server) hands the page
a ``timeline.View`` for each version of the text or place of the cursor (``show``: it
returns at once); a thread of the page's own draws it and plays time forward, at most
FRAME apart, and sleeps while nothing changes; another looks for the contacts of each
new plan (``timeline.contacts``, slow on the whole robot) and draws them when found.
What a person does on the page comes back through hooks: ``on_pick`` (a step clicked:
put the editor's cursor there) and ``on_play`` (play the gesture on a robot: nothing
moves a robot but that click).
"""

from __future__ import annotations

import dataclasses
import sys
import threading
import time
from collections.abc import Callable
from typing import Any

from .liveclock import Clock
from .livepanel import Panel
from .lookout import Lookout
from .placemarks import PlaceMarks
from .scene import HOST, Robot, need_viser, robot_for, start_server, stop_server
from .timeline import Span, View

FRAME = 1 / 30  #: s between two pictures while playing, at most 30 a second
COMMAND = "gestc preview --live"


class LivePage:
    """A page on ``http://127.0.0.1:PORT/`` (``url``) showing the views it is given.
    ``port`` 0 takes any free one; a busy one, the next free."""

    def __init__(self, port: int = 0, now: Callable[[], float] = time.monotonic):
        viser, _, _ = need_viser(COMMAND)
        self.server = start_server(viser, port)
        self.port: int = self.server.get_port()
        self.url = f"http://{HOST}:{self.port}/"
        #: a step clicked: the editor's cursor to its ``file``, ``line``, ``character``
        self.on_pick: Callable[[Span], None] | None = None  # (0-based; viser's thread)
        self._on_play: Callable[[View], str] | None = None
        self.view: View | None = None  #: the view shown (with its contacts when found)
        self.clock = Clock()
        self.cursor: tuple[int, ...] = ()  #: the spans highlighted
        self.revision = 0  #: views drawn
        self.frames = 0  #: times the pose and the time were drawn
        self._now = now
        self._lock = threading.RLock()
        self._pending: View | None = None
        self._robot: Robot | None = None
        self._drawn: tuple | None = None  #: what was drawn last: time, cursor, view...
        self._restep = False  #: the cursor moved: the steps' buttons to colour again
        self._picked: int | None = None  #: the span clicked, while the cursor is on its line
        self._wake, self._closing = threading.Event(), threading.Event()
        self.panel = Panel(self.server, self)
        self.marks = PlaceMarks(self.server)  #: the plan's places, the hand's path, the gaze
        self.lookout = Lookout(self._found)
        self._thread = threading.Thread(target=self._run, name="live-page", daemon=True)
        self._thread.start()

    # --- what the editor's side calls

    def show(self, view: View) -> None:
        """Show ``view`` at once (the page's thread draws it): its cursor's steps lit,
        and while paused, the pose the last of them ends in."""
        with self._lock:
            self._pending = self.lookout.filled(view)
        self._wake.set()

    def point(self, index: int | None) -> None:
        """Highlight the step of span ``index`` (None: none), pause, hold its end pose."""
        with self._lock:
            spans = (self._pending or self.view).spans if self._pending or self.view else ()
            self.cursor = (index,) if index is not None and 0 <= index < len(spans) else ()
            self.clock.pause(self._now())
            if self.cursor:
                self.clock.seek(spans[index].end, self._now())
            self._restep = True
        self._wake.set()

    @property
    def on_play(self) -> Callable[[View], str] | None:
        """"Play on the robot": called with the view shown, on a thread of its own;
        what it returns is shown. None: the button is disabled."""
        return self._on_play

    @on_play.setter
    def on_play(self, play: Callable[[View], str] | None) -> None:
        """Set the hook (its ``hint``, if it has one, is the button's)."""
        self._on_play = play
        self.panel.can_play_on_robot(play is not None, getattr(play, "hint", None))

    def seek(self, t: float) -> None:
        """Go to time ``t`` of the gesture."""
        self._change(lambda clock, now: clock.seek(t, now))

    def play(self) -> None:
        """Play from where the page is."""
        self._change(Clock.play)

    def pause(self) -> None:
        """Hold where the page is."""
        self._change(Clock.pause)

    def _change(self, change: Callable[[Clock, float], object]) -> None:
        """Change the clock (now), and draw."""
        with self._lock:
            change(self.clock, self._now())
        self._wake.set()

    def close(self) -> None:
        """Stop the threads and the server (the page then shows it is disconnected)."""
        self._closing.set()
        self._wake.set()
        self._thread.join(timeout=2)
        self.lookout.close()
        stop_server(self.server)

    # --- what the panel tells (a person on the page)

    def toggle(self) -> None:
        """Play, or pause."""
        self._change(lambda clock, now: (clock.pause if clock.playing else clock.play)(now))

    def scrub(self, t: float) -> None:
        """The time slider moved: pause there."""
        self._change(lambda clock, now: (clock.pause(now), clock.seek(t, now)))

    def set_speed(self, speed: float) -> None:
        """Play at ``speed`` from now on."""
        self._change(lambda clock, now: clock.set_speed(speed, now))

    def set_loop(self, loop: bool) -> None:
        """Loop or not."""
        self._change(lambda clock, _now: setattr(clock, "loop", loop))

    def pick(self, index: int) -> None:
        """A step's button: highlight it, hold the pose it ends in, tell ``on_pick``."""
        if (view := self.view) is None or not 0 <= index < len(view.spans):
            return
        self.point(index)
        self._picked = index
        if self.on_pick is not None:
            self.on_pick(view.spans[index])

    def play_on_robot(self) -> None:
        """Hand the view to ``on_play`` (the panel: on a thread of its own)."""
        self.panel.send(self.view, self._on_play)

    # --- the page's threads

    def _run(self) -> None:
        """Until closed: draw each new view, and the time, the pose and the playhead
        when they change; a frame apart while playing."""
        due = 0.0  # when the next frame is, while playing
        while True:
            self._wake.wait(max(0.0, due - time.monotonic()) if self.clock.playing else None)
            self._wake.clear()
            if self._closing.is_set():
                return
            due = time.monotonic() + FRAME
            try:
                self._turn()
            except Exception as exc:  # noqa: BLE001 (the page goes on; the editor's log says)
                print(f"{COMMAND}: the page could not draw: {type(exc).__name__}: {exc}",
                      file=sys.stderr)

    def _turn(self) -> None:
        """Draw what changed: a new view, the cursor's steps, the time."""
        with self._lock:
            view, self._pending = self._pending, None
            if view is not None:
                self._take(view)
            restep, self._restep = self._restep and view is None, False
        if view is not None:
            self._draw(view)
        elif restep and self.view is not None:
            self.panel.steps(self.view.spans, self.cursor)
        self._draw_now()

    def _take(self, view: View) -> None:
        """The new view's time and cursor (within the lock): while paused at the
        cursor's step, the pose its last step ends in now."""
        now = self._now()
        self.clock.set_duration(view.duration, now)
        self.cursor = view.holding(self._picked)
        self._picked = self._picked if self.cursor == (self._picked,) else None
        if self.cursor and not self.clock.playing:
            self.clock.seek(view.spans[self.cursor[-1]].end, now)
        self.view = view
        self.revision += 1

    def _draw(self, view: View) -> None:
        """A new view on the page: the robot (a new one when the profile changed), the
        panel; its contacts asked for."""
        note = ""
        if view.profile is not None:
            self._robot, note = robot_for(self.server, self._robot, view.profile, COMMAND)
        known, marks = self.lookout.known(view.plan) if view.plan else (False, None)
        self.panel.show(view, self.revision, known and marks is None, note)
        self.marks.show(view.plan)
        if view.plan is not None and view.contacts is None:
            self.lookout.ask(view.plan)
        self._drawn = None

    def _found(self, plan: Any, marks: tuple | None) -> None:
        """The lookout found ``plan``'s contacts: its view shown again with them."""
        with self._lock:
            view = self._pending or self.view
            if view and view.plan and view.plan.tracks is plan.tracks and view.contacts is None:
                self._pending = dataclasses.replace(view, contacts=marks or ())
        self._wake.set()

    def _draw_now(self) -> None:
        """The time, the pose and the playhead, if they changed; a sound playing."""
        with self._lock:
            view, t = self.view, self.clock.time(self._now())
            state = (t, self.cursor, self.revision, self.clock.playing)
            if view is None or state == self._drawn:
                return
            self._drawn, cursor = state, self.cursor
            playing, speed, session = self.clock.playing, self.clock.speed, self.clock.session
        values = view.pose(t)
        if self._robot is not None and view.profile is not None:
            self._robot.pose(values)
            self.marks.pose(values)
        self.panel.now(view, t, values, cursor, playing)
        self.panel.sound(view, t, session if playing and speed == 1.0 else None)
        self.frames += 1
