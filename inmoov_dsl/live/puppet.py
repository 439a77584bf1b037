"""Puppeteering (pure but for the input it waits on): a hand-driven input's messages as
the drive loop's requests. The control changes that came together become one move of
their servos, as fast as the limits allow, that takes over the running one (the drive
loop plans it from where the hand is going, so a fader pushed hard moves the hand at its
limits, never in a jump; its guard refuses a move into the body). What was taken is kept
as the take's samples, for the recorder (``record.py``).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Literal, Protocol

from ..compiling.actions import Action, Steps
from ..hardware import Profile
from .controls import Control, Message, taking
from .orders import Order

#: what an input gives: the messages that came, None at its end, False if none came in time
Got = list[Message] | None | Literal[False]


class Input(Protocol):
    """A source of control changes (``midi.TakeFile``, ``midi.PortInput``)."""

    def wait(self, timeout: float) -> Got:
        """The messages that came within ``timeout`` s (all that have come, once one has)."""

    def close(self) -> None:
        """Stop listening."""


class Puppet:
    """``next_request`` for the drive loop (``drive.Drive.run``): waits on ``source``;
    the values its messages ask for, one move of the servos whose value changed.
    ``show`` is told each move, as the .gest text it is."""

    def __init__(self, source: Input, controls: Sequence[Control], profile: Profile,
                 show: Callable[[str], None] | None = None):
        self.source, self.controls, self.profile = source, controls, profile
        self.show = show
        self.samples: list[tuple[float, int, int]] = []  #: (s, servo ID, value) taken
        self.asked: dict[int, int] = {}  #: servo index -> the value last asked for
        self.moves = 0  #: requests made

    def __call__(self, timeout: float) -> Order | None | Literal[False]:
        got = self.source.wait(timeout)
        if got is None or got is False:
            return got
        wanted: dict[int, int] = {}
        for t, channel, cc, level in got:
            control = taking(self.controls, channel, cc)
            if control is None:
                continue
            value = control.value(level)
            self.samples.append((t, self.profile.servos[control.servo].id, value))
            wanted[control.servo] = value
        targets = tuple(sorted((i, v) for i, v in wanted.items() if self.asked.get(i) != v))
        if not targets:
            return False
        self.asked.update(targets)
        self.moves += 1
        text = ", ".join(f"{self.profile.servos[i].name} {v}" for i, v in targets)
        if self.show is not None:
            self.show(text)
        return Order(Steps((Action(targets, where="puppet"),), text), after=False)
