"""Live motion (pure): steps arrive while the hand moves, and each takes over at once.

A Session holds the plan the hand is following and the steps queued after it. A
move submitted while the hand is still moving is planned by ruckig from the hand's
planned position, velocity and acceleration at that moment, so the motion carries
on without a jump and without stopping first; servos the new step does not name
carry on to where they were going. Each new plan is encoded like a compiled
gesture (CANCEL first, so a half-sent pair is dropped), against the values the
board already holds. Times are the caller's clock, in seconds; this module has none.
"""

from __future__ import annotations

import contextlib
import functools
from collections import deque
from collections.abc import Sequence
from dataclasses import dataclass, replace

from ..compiling.actions import Action
from ..compiling.compiled import Stream
from ..compiling.encode import encode
from ..compiling.plan import MotionState, Plan, Planner
from ..compiling.resolve import Resolver
from ..compiling.valuehint import fitting
from ..errors import Diagnostic, GestError, Pos, SourceMap, did_you_mean
from ..hardware import Profile
from ..language import snippet
from ..language.load import load_program
from ..language.parse import parse
from ..language.program import Program
from ..language.syntax import GestureDef, Robot, Use

LINE = "<repl>"  #: the file name diagnostics give for lines typed at a terminal
STDIN = "<stdin>"  #: and for lines read from a pipe or a file
_NAME = "_"  #: the typed line becomes this gesture
#: s; a takeover that ruckig cannot plan from the hand's state (a rare numerical edge of
#: its solver) is planned from where the running move has the hand this much later
RETRY_LATER = (0.001, 0.002, 0.005, 0.010, 0.020)
_PREFIX = f"{_NAME}: "


@dataclass(frozen=True)
class Segment:
    """A stretch of motion to send from ``origin`` on: its plan and its streams."""

    origin: float
    plan: Plan
    streams: tuple[Stream, ...]
    step: Action
    warnings: tuple[Diagnostic, ...] = ()
    tag: str | None = None  #: the request the step came from (its id), if it has one
    took_over: bool = False  #: planned from the hand's motion, not from where it stood


class Session:
    """The motion of one hand, one step after another, new steps taking over."""

    def __init__(self, profile: Profile, pose: Sequence[int], now: float,
                 sources: SourceMap | None = None):
        self.profile = profile
        self.planner = Planner(profile, sources)
        hold = Action((), hold=0.0)
        self.current = Segment(now, self.planner.plan([hold], pose), (), hold)
        #: (step, the text its diagnostics point into, the request's tag)
        self.queue: deque[tuple[Action, SourceMap | None, str | None]] = deque()

    def state(self, now: float) -> MotionState:
        """Where the current plan has the hand at ``now``."""
        return MotionState.at(self.current.plan, now - self.current.origin)

    def busy(self, now: float) -> bool:
        """Still moving or holding, or steps queued."""
        return now < self.end or bool(self.queue)

    @property
    def end(self) -> float:
        """When the current segment ends (the caller's clock, s)."""
        return self.current.origin + self.current.plan.duration

    def submit(self, steps: Sequence[Action], now: float, held: Sequence[int],
               sources: SourceMap | None = None, tag: str | None = None) -> Segment | None:
        """New steps replace the queue; a move starts now (taking over), a wait or an
        ``a & b`` step when the running move ends. Returns the segment to send now, if
        any.
        ``sources`` has the text the steps' diagnostics point into; ``tag`` names the
        request they come from."""
        self.queue = deque((step, sources, tag) for step in steps)
        first = self.queue[0][0] if self.queue else None
        if first and first.hold == 0 and not first.branches and first.speech is None:
            return self._start(now, held)
        return self.next(now, held)

    def append(self, steps: Sequence[Action], now: float, held: Sequence[int],
               sources: SourceMap | None = None, tag: str | None = None) -> Segment | None:
        """New steps after the queued ones (a script, not a takeover)."""
        self.queue.extend((step, sources, tag) for step in steps)
        return self.next(now, held)

    def stop(self, now: float, held: Sequence[int]) -> None:
        """The hand holds ``held`` from ``now`` (a CANCEL has stopped it): nothing runs
        and nothing is queued."""
        self.queue.clear()
        hold = Action((), hold=0.0)
        self.current = Segment(now, self.planner.plan([hold], held), (), hold)

    def tags(self) -> set[str | None]:
        """The tags of the queued steps."""
        return {tag for _, _, tag in self.queue}

    def next(self, now: float, held: Sequence[int]) -> Segment | None:
        """The next queued step, once the current one has ended."""
        if not self.queue or now < self.end:
            return None
        return self._start(max(now, self.end), held)

    def _start(self, now: float, held: Sequence[int]) -> Segment:
        """Plan the first queued step; if it cannot be, the steps queued with it (the
        rest of its line) are dropped and the GestError goes on."""
        step, sources, tag = self.queue.popleft()
        try:
            self.current = replace(self._plan(step, sources, now, held), tag=tag)
            return self.current
        except GestError:
            self.queue = deque(q for q in self.queue if q[1] is not sources)
            raise

    def _plan(self, step: Action, sources: SourceMap | None, now: float,
              held: Sequence[int]) -> Segment:
        if sources is not None:
            self.planner.sources = sources
        final = list(self.current.plan.final)
        took_over = False
        if step.hold > 0 or step.branches or step.speech is not None:
            plan = self.planner.plan([step], final)
        elif now >= self.end:
            plan = self.planner.plan([step], final)  # from rest: exactly as compiled
        else:
            for i, v in step.targets:
                final[i] = v
            plan, now = self._take_over(now, final, step)
            took_over = True
        plan = replace(plan, start=tuple(held))  # what the board holds is what changed
        self.current = Segment(now, plan, encode(plan), step, plan.warnings,
                               took_over=took_over)
        return self.current

    def _take_over(self, now: float, final: list[int], step: Action) -> tuple[Plan, float]:
        """The plan from where the hand is at ``now`` to ``final``, and when it starts:
        ruckig's solver stumbles on a few moving states, so a failure is tried again
        from where the running move has the hand a little later (RETRY_LATER)."""
        for later in (0.0, *RETRY_LATER[:-1]):
            with contextlib.suppress(GestError):
                return self.planner.take_over(self.state(now + later), final, step.over,
                                              step), now + later
        now += RETRY_LATER[-1]
        return self.planner.take_over(self.state(now), final, step.over, step), now


class _Typed(SourceMap):
    """The texts of a program, and one typed line: line ``number`` of ``file``."""

    def __init__(self, program: Program, file: str, number: int, text: str):
        super().__init__()
        for name, source in program.texts.items():
            self.add(name, source)
        self.typed = (file, number, text)

    def line(self, pos: Pos | None) -> str | None:
        """The source line at ``pos``."""
        if pos is not None and (pos.file, pos.line) == self.typed[:2]:
            return self.typed[2]
        return super().line(pos)


def line_steps(line: str, program: Program, profile: Profile, file: str = LINE,
               number: int = 1, side: str | None = None) -> tuple[list[Action], SourceMap]:
    """The steps of one typed line, e.g. ``index 90, middle 45 over 0.5s``, ``wait 1s``
    or the name of a gesture or pose of ``program`` (on ``side`` of the robot, when
    given). Errors point into the line, line ``number`` of ``file`` (the input it came
    from)."""
    sources = _Typed(program, file, number, line)
    sources.add(file, line)  # what the steps are resolved from (wrapped: unwrap says it)
    with fitting(profile, program), snippet.parsed(line, file, _PREFIX, number) as module:
        gesture = next(item for item in module.items if isinstance(item, GestureDef))
        typed = Program(file, sources, program.texts, {**program.gestures, _NAME: gesture},
                        program.poses, program.groups, [_NAME],
                        in_library=program.in_library, hear=program.hear,
                        robots=program.robots, places=program.places)
        actions = Resolver(typed, profile).gesture(_NAME, side, line.strip()[:40])
    back = functools.partial(snippet.shift, text=line, file=file, prefix=_PREFIX,
                             line=number)
    return [replace(a, pos=back(a.pos), over_pos=back(a.over_pos),
                    aims=tuple(replace(m, pos=back(m.pos)) for m in a.aims))
            for a in actions], sources


def text_steps(text: str, gesture: str | None, program: Program, profile: Profile,
               file: str, side: str | None = None) -> tuple[list[Action], SourceMap, str]:
    """The steps of gesture ``gesture`` of ``text``, a gesture file's text under the name
    ``file`` (its definitions over ``program``'s; ``gesture`` None: the text's only
    one), and its name. The text reads no file: a ``use`` line, or a robot line that
    names a file, is an error at its place."""
    with fitting(profile, program):
        module = parse(text, file)
    sources = SourceMap()
    for name, source in [*program.texts.items(), (file, text)]:
        sources.add(name, source)
    for item in module.items:
        if isinstance(item, Use) or isinstance(item, Robot) and item.is_file:
            raise GestError(sources.error(
                f"{'use' if isinstance(item, Use) else 'a robot file'} reads a file, and "
                f"{file} names no file of this computer", item.pos,
                "send the definitions it needs in the text; the library's are known"))
    own = load_program(file, lambda _: text, text=text, parser=lambda *_: module)
    name = gesture if gesture is not None else (own.own[0] if len(own.own) == 1 else None)
    if name not in own.own:
        raise GestError(Diagnostic(
            "error", f"no gesture '{gesture}' in the text" if gesture is not None else
            f"the text has {len(own.own)} gestures: name the one to play" if own.own else
            "the text defines no gesture", None,
            (did_you_mean(gesture or "", own.own) or f"its gestures: {', '.join(own.own)}")
            if own.own else "write one: 'wave: index 90 over 0.5s'"))
    typed = Program(file, sources, {**program.texts, file: text},
                    {**program.gestures, **own.gestures}, {**program.poses, **own.poses},
                    {**program.groups, **own.groups}, list(own.own),
                    in_library=program.in_library, hear=program.hear,
                    robots={**program.robots, **own.robots},
                    places={**program.places, **own.places})
    return Resolver(typed, profile).gesture(name, side), sources, name
