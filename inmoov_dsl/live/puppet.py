"""Puppeteering (pure but for the input it waits on): a hand-driven input's messages (a
MIDI controller's control changes, Blender's positions) as the drive loop's requests.
The values asked for together become one move of their servos, as fast as the limits
allow, that takes over the running one (the drive loop plans it from where the hand is
going, so a fader pushed hard moves the hand at its limits, never in a jump; its guard
refuses a move into the body). What was taken is kept as the take's samples, for the
recorder (``record.py``).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any, Literal, Protocol

from ..compiling.actions import Action, Steps
from ..hardware import Profile
from .controls import Control, samples
from .orders import Order

#: what an input gives: the messages that came, None at its end, False if none came in time
Got = list[Any] | None | Literal[False]


class Input(Protocol):
    """A source of messages (``midi.TakeFile``, ``midi.PortInput``, ``blender.Listener``)."""

    def wait(self, timeout: float) -> Got:
        """The messages that came within ``timeout`` s (all that have come, once one has)."""

    def close(self) -> None:
        """Stop listening."""


#: an input's messages as the (s, servo ID, value) each asks for, in time order
Reading = Callable[[list[Any]], list[tuple[float, int, int]]]


def midi_reading(controls: Sequence[Control], profile: Profile) -> Reading:
    """A MIDI input's control changes through the map's ``controls``."""
    return lambda got: samples(got, controls, profile)


class Puppet:
    """``next_request`` for the drive loop (``drive.Drive.run``): waits on ``source``;
    the values its messages ask for (``read``), one move of the servos whose value
    changed. ``show`` is told each move, as the .gest text it is."""

    def __init__(self, source: Input, read: Reading, profile: Profile,
                 show: Callable[[str], None] | None = None):
        self.source, self.read, self.profile = source, read, profile
        self.show = show
        self.samples: list[tuple[float, int, int]] = []  #: (s, servo ID, value) taken
        self.asked: dict[int, int] = {}  #: servo index -> the value last asked for
        self.moves = 0  #: requests made
        self._index = {s.id: i for i, s in enumerate(profile.servos)}

    def __call__(self, timeout: float) -> Order | None | Literal[False]:
        got = self.source.wait(timeout)
        if got is None or got is False:
            return got
        wanted: dict[int, int] = {}
        for t, sid, value in self.read(got):
            self.samples.append((t, sid, value))
            wanted[self._index[sid]] = value
        targets = tuple(sorted((i, v) for i, v in wanted.items() if self.asked.get(i) != v))
        if not targets:
            return False
        self.asked.update(targets)
        self.moves += 1
        text = ", ".join(f"{self.profile.servos[i].name} {v}" for i, v in targets)
        if self.show is not None:
            self.show(text)
        return Order(Steps((Action(targets, where="puppet"),), text), after=False)
