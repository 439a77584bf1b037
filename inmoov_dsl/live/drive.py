"""The drive loop (an edge): requests arrive while the hand moves, and each takes over.

One loop for every front end that drives a hand live (``gestplay repl``, the ROS node,
the service): it waits for a request only until the links need topping up, so a request
starts within a few milliseconds; a request (a typed line of .gest text, or steps already
resolved: a trajectory's points; its places solved from where the hand is going) takes
over the running move without a jump (``live.Session``). Each link's bytes go out as a
continuous run timed by the wire (``wire.pace``), written LIVE_HORIZON ahead; a take-over
or a stop drops what is queued and not yet on the wire. A ``Mirror`` keeps what each board holds as
its bytes arrive. What happens is told to the front end as ``Note``s.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal

from .. import clock
from ..compiling.actions import Action, Steps
from ..compiling.plan import Plan, Planner
from ..compiling.reaching import solved
from ..errors import Diagnostic, GestError, SourceMap
from ..hardware import Profile
from ..language.library import library_dirs, library_files, scan
from ..language.load import load
from ..language.program import Program
from ..wire.player import POLL, Link
from ..wire.ready import drain
from .orders import Control, Order, Rejoin, Request, Tracker
from .outbox import Outbox
from .session import LINE, Segment, Session, line_steps

#: what ``next_request`` gives: a request (an Order when it has an id or options, a
#: Control to stop or relax), None at the end, False if none came in time
Next = Request | Order | Control | Rejoin | None | Literal[False]


@dataclass(frozen=True)
class Note:
    """What the loop tells its front end.

    ``kind`` is "error" (a request could not be done), "warning" (a move was
    stretched), "start" (a request is being done; ``text`` is its name), "done" (the
    hand is still and nothing is queued) or "answered" (a request has been dealt
    with); for requests with an id (``Order``), also "started", "finished" and
    "stopped" (``orders.Tracker``); "stop" and "relax" when a Control was done.
    ``aside`` is set on warnings of queued steps, which come while the front end waits
    for its next request. ``id`` is the request's, where it has one."""

    kind: str
    diagnostics: tuple[Diagnostic, ...] = ()
    text: str = ""
    aside: bool = False
    id: str | None = None


Tell = Callable[[Note], None]
#: a check of what is about to move the robot (``model.guard.Guard.plan``): its warnings,
#: or a GestError that refuses it; (plan, its texts, whether contact is allowed: None,
#: the guard's own way)
Guard = Callable[[Plan, SourceMap | None, bool | None], tuple[Diagnostic, ...]]


def library_program(dirs: list[Path] | None = None) -> Program:
    """Every library gesture, pose and group, for names typed at the prompt: the first
    definition along the search path (files that do not parse left out: repl warned)."""
    dirs = library_dirs() if dirs is None else dirs
    broken = scan(dirs).broken
    uses = "".join(f'use "{f.resolve()}"\n' for f in library_files(dirs) if f not in broken)
    return load("<library>", uses, search=[str(d) for d in dirs], first_wins=True)


class Guarding:
    """The guard's part in the loop (``guard``: None, nothing is checked): a request's
    steps planned from where the hand is going and checked before they are queued, each
    segment again before it is sent; which requests allow contact."""

    def __init__(self, guard: Guard | None, profile: Profile):
        self.guard, self.profile = guard, profile
        self.allowing: dict[str | None, bool | None] = {}  #: request id -> allow_contact

    def request(self, order: Order, steps: list[Action], sources: SourceMap | None,
                final: tuple[int, ...], tags: set[str | None]) -> tuple[Diagnostic, ...]:
        """Its warnings, or a GestError (refused); ``final``: where the hand is going."""
        if self.guard is None or order.checked:
            return ()
        if order.allow_contact is not None:  # kept while its steps may still begin
            if len(self.allowing) > 64:
                self.allowing = {t: a for t, a in self.allowing.items() if t in tags}
            self.allowing[order.id] = order.allow_contact
        ahead = Planner(self.profile, sources).plan(steps, final)
        return self.guard(ahead, sources, order.allow_contact)

    def segment(self, segment: Segment) -> None:
        """A GestError if the guard refuses ``segment``: a take-over's own path (any
        other segment is planned from where it was checked to start)."""
        if self.guard is not None and segment.took_over:
            self.guard(segment.plan, None, self.allowing.get(segment.tag))


class Drive:
    """One hand driven live: its links, the motion it follows, what its boards hold."""

    def __init__(self, links: list[Link], profile: Profile, pose: dict[str, int],
                 program: Program, tell: Tell, take_over: bool = True,
                 now: clock.Clock | None = None, sleep: clock.Sleep | None = None,
                 file: str = LINE, speaker: Any = None, guard: Guard | None = None):
        self.links, self.profile, self.program = links, profile, program
        self.guarding = Guarding(guard, profile)
        self.file, self.lines = file, 0  #: typed lines are lines of ``file``; how many came
        self.take_over, self.told = take_over, tell
        self.speaker = speaker  #: where ``say`` steps are heard (``wire.audio.Speaker``)
        self.notes: list[Note] = []  #: told once the bytes due are out (``_flush``)
        self.tell: Tell = self.notes.append
        self.now, self.sleep = now or clock.now, sleep or clock.sleep
        start = [pose.get(s.name, s.rest) for s in profile.servos]
        self.out = Outbox(links, profile)
        self.mirror = self.out.mirror
        self.mirror.set(start)
        self.session = Session(profile, start, self.now(), program.sources)
        self.moving = False  #: a request has moved the hand since the last "done"
        self.tracker = Tracker(lambda kind, tag: self.tell(Note(kind, id=tag)))

    def run(self, next_request: Callable[[float], Next]) -> None:
        """Run until the input ends (``next_request`` gives None) and the hand is still.
        ``next_request(timeout)`` waits at most ``timeout`` s for a request."""
        ended = False
        while True:
            if self._still(self.now()) and ended:
                self._flush()
                return
            wait = self._wait(self.now(), ended)
            if ended:
                self.sleep(max(wait, 0))
                request: Next = False
            else:
                request = next_request(wait)
            if request is False:
                for link in self.links:
                    drain(link.port)  # WAITs answering filler; a pulled cable shows here
            t = self.now()
            segment = None
            if request is None:
                ended = True
            elif isinstance(request, Control):
                self._control(request, t)
            elif isinstance(request, Rejoin):
                self._rejoin(request, t)
            elif request is not False:
                segment = self._requested(request if isinstance(request, Order)
                                          else Order(request), t)
            queued = segment is None
            if queued:
                segment = self._queued(t)
            if request is not False:
                self.tell(Note("answered"))
            if segment is not None:
                self._begin(segment, aside=queued)
            self._send()
            self._flush()

    def settled(self) -> bool:
        """The requested steps are done: nothing to send or queued, nothing running."""
        return not self.out.sending() and not self.session.busy(self.now())

    def _still(self, t: float) -> bool:
        """Nothing to send and nothing to do; says "done" once after a move."""
        if self.out.sending() or self.session.busy(t):
            return False
        if self.moving:
            self.moving = False
            self.tracker.still()
            self.tell(Note("done"))
        return True

    def _wait(self, t: float, ended: bool) -> float:
        """How long to wait for a request: until a link needs topping up (a run's first
        byte: nearly due, then spin) or the next byte arrives (the Mirror reads it),
        until the running step ends if another is queued, never more than POLL."""
        if self.out.sending():
            return min(POLL, self.out.wake(t) - t)
        if self.session.queue or ended:
            return min(POLL, self.session.end - t)
        return POLL

    def _requested(self, order: Order, t: float) -> Segment | None:
        """Resolve and submit a request: the segment to send now, if any."""
        request = order.what
        if isinstance(request, Steps):
            steps, sources, name = list(request.actions), request.sources, request.name
        else:
            self.lines += 1
            name = request.strip()
            if not name or name.startswith("#"):
                return None
            try:
                steps, sources = line_steps(request, self.program, self.profile,
                                            self.file, self.lines)
            except GestError as exc:
                self.tell(Note("error", tuple(exc.diagnostics), name, id=order.id))
                return None
        if (steps := self._guarded(order, steps, sources, name)) is None:
            return None
        after = not self.take_over if order.after is None else order.after
        dropped = set() if after else {self.tracker.playing, *self.session.tags()}
        run = self.session.append if after else self.session.submit
        if not after and self.speaker is not None:
            self.speaker.stop()  # what it said is taken over too
        try:
            segment = run(steps, t, self.out.held(t), sources, order.id)
        except GestError as exc:  # the session has dropped what was queued with the step
            self.tell(Note("error", tuple(exc.diagnostics), name, id=order.id))
            return None
        self.tracker.ordered(order, steps, sources, dropped)
        self.tell(Note("start", text=name, id=order.id))
        return segment

    def _guarded(self, order: Order, steps: list[Action], sources: SourceMap | None,
                 name: str) -> list[Action] | None:
        """Its steps, places solved, if it may go on (``Guarding.request``); or None."""
        going = self.session.current.plan.final
        try:
            steps, noted = solved(steps, going, self.profile, sources)
            warnings = noted + self.guarding.request(order, steps, sources, going,
                                                     self.session.tags())
        except GestError as exc:
            self.tell(Note("error", tuple(exc.diagnostics), name, id=order.id))
            return None
        if warnings:
            self.tell(Note("warning", warnings, id=order.id))
        return steps

    def _begin(self, segment: Segment, aside: bool) -> None:
        """Send ``segment`` from now on; tell what began, and its warnings (``aside``:
        of a queued step, told while the front end waits). A segment the guard refuses
        (a take-over's path the request's check did not see) stops the hand instead."""
        try:
            self.guarding.segment(segment)
        except GestError as exc:
            self._control(Control("stop"), self.now())
            self.tell(Note("error", tuple(exc.diagnostics), aside=aside, id=segment.tag))
            return
        if not aside and self.out.sending():  # it takes over: what is queued is dropped
            self.out.discard(self.now())
        self.out.add(segment.origin, segment.streams)
        self.moving = True
        if self.speaker is not None:
            for start, speech in segment.plan.sounds:
                self.speaker.play(speech.sound, segment.origin + start)
        self.tracker.began(segment.tag, self.session.tags(), self._again)
        if segment.warnings:
            self.tell(Note("warning", segment.warnings, aside=aside, id=segment.tag))

    def _rejoin(self, rejoin: Rejoin, t: float) -> None:
        """A board is back, holding ``rejoin.values``: the hand goes on from what the
        boards hold."""
        self.out.discard(t, resync=False)
        for servo_id, value in rejoin.values.items():
            self.mirror.put(servo_id, value)
        self.tracker.halt(self.session.tags())
        self.session.stop(t, self.mirror.held())
        self.moving = False
        self.tell(Note("board-back", text=str(rejoin.board)))

    def _again(self, steps: list[Action], sources: SourceMap | None, tag: str) -> None:
        """Queue another pass of a request that loops."""
        self.session.append(steps, self.now(), self.mirror.held(), sources, tag)

    def _control(self, control: Control, t: float) -> None:
        """Stop the hand where it holds (CANCEL to every board) or relax it; nothing
        runs or is queued after."""
        self.out.discard(t)  # CANCEL, and what may have gone already, again
        if control.kind == "relax":
            self.out.relax(t)
        if self.speaker is not None:
            self.speaker.stop()
        self.tracker.halt(self.session.tags())
        self.session.stop(t, self.mirror.held())
        self.moving = False
        self.tell(Note(control.kind, id=control.id))

    def _queued(self, t: float) -> Segment | None:
        """The next queued step, once the running one has ended."""
        try:
            return self.session.next(t, self.mirror.held())
        except GestError as exc:
            self.tell(Note("error", tuple(exc.diagnostics), aside=True))
            return None

    def _flush(self) -> None:
        """Tell the front end what happened: after the bytes, so words never delay them."""
        notes, self.notes[:] = list(self.notes), []
        for note in notes:
            self.told(note)

    def _send(self) -> None:
        """Top the links up, and mirror what has arrived."""
        self.out.send(self.now())
