"""A gesture's timeline, as the live preview draws it (pure): each servo it moves with
its planned curve, the values its board receives and its limits; its steps as spans at
their planned times; where a move was stretched, a link was full or two parts touch;
each ``say``'s sound. ``View`` is one state of the page: the gesture, its plan, its
timeline, the file's diagnostics and the steps under the editor's cursor
(``editor/preview_view.py`` makes it from an editor's text; ``livepage.py`` shows it).

What a plan's tracks draw (``Motion``: samples, the bytes' values, full links, sounds)
is the costly part; it is made once per plan (``motion``) and kept while the plan's
tracks stay the same (an edit elsewhere in the file leaves them).
"""

from __future__ import annotations

import bisect
import functools
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import protocol
from ..compiling.compiled import Stream
from ..compiling.plan import Plan
from ..errors import Diagnostic, GestError
from ..hardware import Profile

SAMPLES = 400  #: points of a servo's planned curve, at most (the drawing is 520 wide)
BINS = 400  #: columns of a sound's waveform
FULL = 0.9  #: a servo frame this busy has no room left (``gestc show`` says so too)


@dataclass(frozen=True)
class Span:
    """One planned step, numbered as ``gestc show`` numbers it; ``file``, ``line`` and
    ``character`` (0-based) are where picking it puts the editor's cursor: its own line,
    or the line of the gesture's step that calls the gesture it is in."""

    number: int
    label: str  #: the step's code, as written
    where: str  #: the gesture it is written in
    kind: str  #: "move", "hold" or "say"
    start: float
    end: float
    asked: float | None
    stretched: bool
    servos: tuple[int, ...]  #: the servos it moves (profile indices)
    file: str | None
    line: int | None
    character: int | None


@dataclass(frozen=True)
class Mark:
    """Something to see at a time: ``kind`` "stretched" (a move its limits made
    longer), "full link" (a board's link busy in every frame of it) or "contact" (two
    parts of the robot closer than their clearance, from ``start`` on)."""

    kind: str
    start: float
    end: float
    text: str


@dataclass(frozen=True, eq=False)
class Series:
    """A servo on the timeline: its planned position (command degrees) sampled at
    ``times``, the values its board receives (``sent_times``: when each arrives), and
    its range."""

    servo: int
    name: str
    lo: int
    hi: int
    times: np.ndarray = field(repr=False)
    planned: np.ndarray = field(repr=False)
    sent_times: np.ndarray = field(repr=False)
    sent: np.ndarray = field(repr=False)


@dataclass(frozen=True, eq=False)
class Sound:
    """A ``say``'s sound on the timeline: its waveform (each column's lowest and highest
    sample, -1..1), its loudness every HOP (0..1), and the mouth that follows it."""

    start: float
    duration: float
    source: str
    servo: int
    low: np.ndarray = field(repr=False)
    high: np.ndarray = field(repr=False)
    levels: np.ndarray = field(repr=False)
    hop: float
    samples: np.ndarray = field(repr=False)  #: -1..1 (for playing it)
    rate: float


@dataclass(frozen=True, eq=False)
class Motion:
    """What a plan's tracks draw: a series per servo the gesture moves (profile order),
    its sounds, and where a board's link is full."""

    duration: float
    series: tuple[Series, ...]
    sounds: tuple[Sound, ...]
    links: tuple[Mark, ...]


def motion(plan: Plan) -> Motion:
    """The timeline's curves of ``plan``: its tracks sampled, its streams encoded and
    read back as the boards read them (``metrics.values_sent``)."""
    from ..compiling.encode import encode
    from ..compiling.metrics import values_sent
    from .plot import moving_servos

    streams = encode(plan)
    sent = values_sent(plan.profile, streams)
    end = max(plan.duration, 1e-3)
    times = np.linspace(0.0, end, int(min(SAMPLES, max(50, end / 0.005))))
    empty = (np.empty(0), np.empty(0, dtype=np.int64))
    series = tuple(
        Series(i, (s := plan.profile.servos[i]).name, s.lo, s.hi, times,
               np.asarray(plan.tracks[i].position(times), dtype=float), *sent.get(i, empty))
        for i in moving_servos(plan, sent))
    return Motion(plan.duration, series, tuple(_sound(t, s) for t, s in plan.sounds),
                  full_links(plan, streams))


def _sound(start: float, speech) -> Sound:
    from ..compiling.speech import HOP

    samples = speech.sound.samples
    bins = max(1, len(samples) // BINS)
    count = max(1, len(samples) // bins)
    cut = np.resize(samples, count * bins).reshape(count, bins) if len(samples) else \
        np.zeros((1, 1))
    return Sound(start, speech.sound.duration, speech.sound.source, speech.servo,
                 cut.min(axis=1), cut.max(axis=1), np.asarray(speech.levels), HOP, samples,
                 speech.sound.rate)


def full_links(plan: Plan, streams: Sequence[Stream]) -> tuple[Mark, ...]:
    """Each run of servo frames in which a board's link is at least FULL busy."""
    from ..boards import controller

    boards = {b.id: b for b in plan.profile.boards}
    found = []
    for stream in streams:
        if not len(stream.times):
            continue
        tau = controller(plan.profile, boards[stream.board]).tau
        frame = protocol.SERVO_FRAME
        busy = np.bincount((stream.times / frame).astype(int)) * tau / frame
        full = np.flatnonzero(busy >= FULL)
        for run in np.split(full, np.flatnonzero(np.diff(full) > 1) + 1) if len(full) else ():
            top = float(busy[run].max())
            found.append(Mark("full link", float(run[0] * frame), float((run[-1] + 1) * frame),
                              f"board {stream.board}'s link full ({100 * top:.0f}% of a "
                              "frame): values may arrive late"))
    return tuple(sorted(found, key=lambda m: m.start))


def stretched(spans: tuple[Span, ...]) -> tuple[Mark, ...]:
    """A mark on each stretched move: what it asked, what it takes."""
    return tuple(Mark("stretched", s.start, s.end, f"step {s.number} stretched: asked "
                      f"{s.asked:.2f} s, needs {s.end - s.start:.2f} s")
                 for s in spans if s.stretched and s.asked is not None)


def contacts(plan: Plan) -> tuple[Mark, ...] | None:
    """Where two parts of the robot first touch, worded as every tool words it
    (``guard.marks``): a mark each; None when they cannot be looked for (python-fcl is
    not installed, or the profile's model has no two parts that can meet). Costly (a
    tenth of a second and more on the whole robot): a page looks for them aside."""
    try:
        from ..model.guard import marks

        found = marks(plan)
    except (ImportError, GestError):
        return None
    if found is None:
        return None
    return tuple(Mark("contact", float(t), float(t), what) for t, what in found)


@dataclass(frozen=True, eq=False)
class View:
    """One state of the live preview: the gesture shown, its plan and timeline, the
    file's diagnostics, the spans under the editor's cursor. ``stale``: the text has
    errors where the gesture is, and this is the last plan that compiled; ``contacts``
    None: not looked for yet."""

    path: str
    gesture: str | None
    profile: Profile | None
    plan: Plan | None = None
    motion: Motion | None = None
    spans: tuple[Span, ...] = ()
    cursor: tuple[int, ...] = ()  #: indices in ``spans``
    diagnostics: tuple[Diagnostic, ...] = ()
    stale: bool = False
    gestures: tuple[str, ...] = ()  #: the file's own, in its order
    contacts: tuple[Mark, ...] | None = None
    program: Any = None  #: the program the plan is of (its texts: what a robot is sent)

    @property
    def duration(self) -> float:
        """s; 0 without a plan."""
        return self.plan.duration if self.plan is not None else 0.0

    @property
    def errors(self) -> tuple[Diagnostic, ...]:
        """The diagnostics that are errors."""
        return tuple(d for d in self.diagnostics if d.severity == "error")

    @property
    def marks(self) -> tuple[Mark, ...]:
        """Stretched moves, full links and contacts, by time."""
        found = stretched(self.spans) + (self.motion.links if self.motion else ()) + \
            (self.contacts or ())
        return tuple(sorted(found, key=lambda m: m.start))

    @property
    def cursor_end(self) -> float | None:
        """When the steps under the cursor end: the pose the robot holds while paused."""
        return self.spans[self.cursor[-1]].end if self.cursor else None

    def holding(self, picked: int | None) -> tuple[int, ...]:
        """The spans under the cursor; or ``picked`` (a step clicked on the page), while
        the cursor is on its line (the line of its first time, in a ``repeat``)."""
        if picked is not None and self.cursor and picked < len(self.spans):
            first, mine = self.spans[self.cursor[0]], self.spans[picked]
            if (first.file, first.line) == (mine.file, mine.line):
                return (picked,)
        return self.cursor

    def pose(self, t: float) -> list[float]:
        """Each servo's planned value at ``t`` (profile order; its rest without a plan)."""
        if self.plan is None:
            return [float(s.rest) for s in self.profile.servos] if self.profile else []
        t = min(max(t, 0.0), self.plan.duration)
        return [float(track.position(t)) for track in self.plan.tracks]

    def span_at(self, t: float) -> int | None:
        """The index of the span playing at ``t``: the last one begun before it (at a
        step's end, that step, not the next one)."""
        if not self.spans:
            return None
        return max(bisect.bisect_left(self._starts, t - 1e-9) - 1, 0)

    @functools.cached_property
    def _starts(self) -> list[float]:
        return [s.start for s in self.spans]
