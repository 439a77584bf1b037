"""The live preview page's panel (an edge: viser's GUI): what the gesture is, the
file's errors, play, pause, loop, speed and the time, the timeline, the pose, the steps
as buttons, the button that plays the gesture on a robot. It draws what ``LivePage``
hands it (livepage.py) and tells it what a person does (``Handlers``)."""

from __future__ import annotations

import html
import threading
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any, Protocol

from . import livedraw
from .liveclock import SPEEDS
from .timeline import Span, View

MAX_STEPS = 100  #: step buttons at most: a window of the gesture's steps round the cursor
WIDTH = 620  #: px of the panel (docked on the right; the robot has the rest)
SLIDER = 0.25  #: s of the gesture the time slider may lag behind while playing


class Handlers(Protocol):
    """What the panel tells the page."""

    def toggle(self) -> None:
        """Play, or pause."""

    def scrub(self, t: float) -> None:
        """The time slider was moved to ``t``."""

    def set_speed(self, speed: float) -> None:
        """The speed was chosen."""

    def set_loop(self, loop: bool) -> None:
        """Loop was ticked or not."""

    def pick(self, index: int) -> None:
        """The step of span ``index`` was clicked."""

    def play_on_robot(self) -> None:
        """"Play on the robot" was clicked."""


def speed_label(speed: float) -> str:
    """``0.25x``, ``1x``."""
    return f"{speed:g}x"


class Panel:
    """The controls, in the main panel docked on the right of the page."""

    def __init__(self, server: Any, handlers: Handlers):
        gui, self.handlers = server.gui, handlers
        gui.set_panel_label("gestc preview")
        gui.main_panel.dock_right()
        gui.main_panel.set_width(WIDTH)
        self.head = gui.add_markdown("waiting for a gesture")
        self.problems = gui.add_html("")
        self.play = gui.add_button("Play", icon="player-play")
        self.loop = gui.add_checkbox("Loop", False)
        self.speed = gui.add_dropdown("Speed", [speed_label(s) for s in SPEEDS],
                                      initial_value=speed_label(1.0))
        self.time = gui.add_slider("Time (s)", min=0.0, max=1.0, step=0.01, initial_value=0.0)
        self.timeline = gui.add_html("")
        self.now_shown = gui.add_html("")  #: one element: one update a frame while playing
        self.audio = gui.add_html("")
        self.gui = gui
        self.steps_box = gui.add_folder("Steps")
        with self.steps_box:
            self.more = gui.add_markdown("")
        with gui.add_folder("Robot"):
            self.robot = gui.add_button("Play on the robot", icon="robot", disabled=True,
                                        hint="plays the gesture on a running gestplay serve")
            self.robot_said = gui.add_html("")
        self.buttons: list[Any] = []
        self.first = 0  #: the span of the first button
        self._labels: list[tuple[str, str | None]] = []
        self._playing = False
        self._sound: tuple[int, int] | None = None  #: (session, sound) on the page
        self._wire()

    def _wire(self) -> None:
        h = self.handlers
        self.play.on_click(lambda _: h.toggle())
        self.robot.on_click(lambda _: h.play_on_robot())
        # a value set by the page itself (client None) is not a person's doing
        self.loop.on_update(lambda e: e.client is not None and h.set_loop(self.loop.value))
        self.speed.on_update(lambda e: e.client is not None and h.set_speed(
            float(self.speed.value.rstrip("x"))))
        self.time.on_update(lambda e: e.client is not None and h.scrub(float(self.time.value)))

    def show(self, view: View, revision: int, unchecked: bool, robot: str = "") -> None:
        """A new view: its head, its problems, its timeline (the time and the pose
        follow with ``now``); ``unchecked``: its contacts cannot be looked for;
        ``robot``: why the robot is not drawn, if it is not."""
        name = Path(view.path).name
        if view.plan is None:
            self.head.content = (f"**{view.gesture or 'no gesture'}** in `{name}`: "
                                 + ("does not compile yet" if view.gesture else
                                    "the file defines no gesture"))
        else:
            stale = " (the last that compiled)" if view.stale else ""
            self.head.content = (f"**{view.gesture}**{stale} in `{name}` on "
                                 f"`{view.profile.name}`: {view.duration:.2f} s, "
                                 f"{len(view.spans)} step{'s' * (len(view.spans) != 1)}. "
                                 f"{livedraw.contacts_note(view, unchecked)}"
                                 + (f" No 3-D model: {robot}" if robot else ""))
        self.problems.content = livedraw.diagnostics(view)
        self.time.max = max(view.duration, 0.01)
        self.timeline.content = (f'{livedraw.PAD}<div id="gl-view" data-rev="{revision}" '
                                 f'data-gesture="{view.gesture or ""}" '
                                 f'data-stale="{int(view.stale)}">'
                                 f"{livedraw.timeline(view)}</div></div>")
        self.steps(view.spans, view.cursor)

    def steps(self, spans: Sequence[Span], cursor: Sequence[int]) -> None:
        """A button per step (a window of MAX_STEPS round the cursor), the cursor's
        coloured; buttons are kept and relabelled, not made again."""
        first = max(0, min((cursor[0] if cursor else 0) - 10, len(spans) - MAX_STEPS))
        shown = spans[first:first + MAX_STEPS]
        while len(self.buttons) < len(shown):
            k = len(self.buttons)
            with self.steps_box:
                button = self.gui.add_button("")
            button.on_click(lambda _, k=k: self.handlers.pick(self.first + k))
            self.buttons.append(button)
            self._labels.append(("", None))
        self.first = first
        for k, button in enumerate(self.buttons):
            if k >= len(shown):
                if button.visible:
                    button.visible = False
                continue
            s = shown[k]
            label = f"{s.number}. {s.start:.2f}–{s.end:.2f} s · {s.label}"
            colour = "yellow" if first + k in cursor else None
            if self._labels[k] != (label, colour):
                button.label, button.color = label, colour
                self._labels[k] = (label, colour)
            if not button.visible:
                button.visible = True
        hidden = len(spans) - len(shown)
        self.more.content = (f"steps {first + 1} to {first + len(shown)} of {len(spans)} "
                             "(the timeline has them all)" if hidden else "")

    def now(self, view: View, t: float, values: Sequence[float], cursor: Sequence[int],
            playing: bool) -> None:
        """The time, the pose and the playhead (and the time slider, every SLIDER while
        playing)."""
        self.now_shown.content = (livedraw.clock(view, t) + livedraw.state(view, t, cursor)
                                  + livedraw.pose(view, values))
        if playing != self._playing:
            self.play.label = "Pause" if playing else "Play"
            self.play.icon = "player-pause" if playing else "player-play"
            self._playing = playing
        if playing and abs(t - self.time.value) < SLIDER:
            return  # the slider follows the time a few times a second (the page is busy)
        self.time.value = round(min(max(t, 0.0), self.time.max), 3)

    def sound(self, view: View, t: float, session: int | None) -> None:
        """A ``say``'s sound from where the page is in it, while playing at 1x
        (``session``; None: not) since a browser plays sound at its own rate: put on the
        page as it starts, taken off when the page pauses, seeks or changes speed."""
        sounds = view.motion.sounds if view.motion is not None and session is not None \
            else ()
        now = next((k for k, s in enumerate(sounds) if s.start <= t < s.start + s.duration),
                   None)
        wanted = (session, now) if now is not None else None
        if wanted == self._sound:
            return
        self._sound = wanted
        self.audio.content = "" if now is None else \
            livedraw.audio(sounds[now], t - sounds[now].start)

    def controls(self, speed: float, loop: bool) -> None:
        """The speed and loop as the page has them."""
        self.speed.value = speed_label(speed)
        self.loop.value = loop

    def can_play_on_robot(self, able: bool, hint: str | None) -> None:
        """Enable the robot's button or not, and say why."""
        self.robot.disabled = not able
        self.robot.hint = hint or ("plays the gesture on a running gestplay serve" if able
                                   else "give the address of a gestplay serve to play on it")

    def send(self, view: View | None, play: Callable[[View], str] | None) -> None:
        """Play ``view`` on the robot (``play``, on a thread of its own), unless it does
        not compile; show what ``play`` says."""
        if play is None or view is None:
            return
        if view.plan is None or view.stale:
            self.robot_says("the gesture does not compile: nothing was sent")
            return

        def run() -> None:
            try:
                said = play(view)
            except Exception as exc:  # noqa: BLE001 (a person reads it on the page)
                said = f"{type(exc).__name__}: {exc}"
            self.robot_says(html.escape(said))

        self.robot_says("sending...")
        threading.Thread(target=run, name="live-robot", daemon=True).start()

    def robot_says(self, text: str) -> None:
        """What the robot's service answered."""
        self.robot_said.content = f'<div id="gl-robot" style="font-size:12px">{text}</div>'
