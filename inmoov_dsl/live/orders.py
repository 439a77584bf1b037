"""Requests with their ids, and what the drive loop tells about each (pure).

A front end that names its requests (the service) sends ``Order``s: the steps, their
id, whether they wait behind what runs (``after``) and how many passes (``loop``). The
``Tracker`` follows the ids through the session: a request has *started* when its
first step begins, *finished* when its last one has run and the hand has moved on, and
is *stopped* when a stop or another request's takeover drops its steps. ``Control``s
stop the hand or relax it.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Literal

from ..compiling.actions import Action, Steps
from ..errors import SourceMap

#: a typed line of .gest text, or resolved steps
Request = str | Steps


@dataclass(frozen=True)
class Order:
    """A request with how to do it: ``after`` queues it behind what runs instead of
    taking over (None: the front end's way), ``loop`` is its passes (0: until stopped or
    taken over); ``allow_contact`` plays it though the robot's parts meet (None: the
    front end's way); ``checked``: the front end has checked it (the drive loop's guard
    need not, from where the hand stands)."""

    what: Request
    id: str | None = None
    after: bool | None = None
    loop: int = 1
    allow_contact: bool | None = None
    checked: bool = False


@dataclass(frozen=True)
class Control:
    """Stop the hand where it is (CANCEL, the queue emptied) or relax it."""

    kind: Literal["stop", "relax"]
    id: str | None = None


@dataclass(frozen=True)
class Rejoin:
    """A board that was away is back, holding ``values`` (servo ID -> value): the hand
    goes on from there."""

    board: int
    values: dict[int, int]


Tell = Callable[[str, str], None]  #: (event: started, finished or stopped; request id)
Append = Callable[[Sequence[Action], SourceMap | None, str], None]  #: queue another pass


@dataclass
class Tracker:
    """Which request is playing, and the passes left of those that loop."""

    tell: Tell
    playing: str | None = None
    loops: dict[str, tuple[list[Action], SourceMap | None, int]] = field(default_factory=dict)

    def ordered(self, order: Order, steps: list[Action], sources: SourceMap | None,
                dropped: set[str | None]) -> None:
        """``order`` was accepted; its takeover dropped the steps of ``dropped``."""
        for tag in sorted(t for t in dropped if t is not None and t != order.id):
            self.stopped(tag)
        if order.id is not None and order.loop != 1:
            self.loops[order.id] = (steps, sources, order.loop)

    def began(self, tag: str | None, queued: set[str | None], append: Append) -> None:
        """A step of ``tag`` has begun; ``queued`` are the tags still queued."""
        if tag != self.playing:
            if self.playing is not None and self.playing not in queued:
                self.finished(self.playing)
            self.playing = tag
            if tag is not None:
                self.tell("started", tag)
        if tag in self.loops and tag not in queued:  # its pass's last step: queue the next
            steps, sources, left = self.loops[tag]
            if left == 2:
                del self.loops[tag]
            elif left > 2:
                self.loops[tag] = (steps, sources, left - 1)
            append(steps, sources, tag)

    def still(self) -> None:
        """The hand is still and nothing is queued: what played has finished."""
        if self.playing is not None:
            self.finished(self.playing)
        self.playing = None

    def finished(self, tag: str) -> None:
        """``tag``'s steps have all run."""
        self.loops.pop(tag, None)
        self.tell("finished", tag)

    def stopped(self, tag: str) -> None:
        """``tag``'s steps were dropped before they all ran."""
        self.loops.pop(tag, None)
        if tag == self.playing:
            self.playing = None
        self.tell("stopped", tag)

    def halt(self, queued: set[str | None]) -> None:
        """A stop: what plays and what is queued are stopped."""
        for tag in sorted(t for t in {self.playing, *queued} if t is not None):
            self.stopped(tag)
        self.playing = None
