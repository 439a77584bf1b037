"""The library gestures that ask the most of a board, for the tests that run gestures in
simavr (a second of the board's time is seconds of the machine's: every gesture of the
library there took a quarter of the suite). Every gesture's bytes are checked in Python
(test_stored, test_controllers, test_golden); what simavr adds, the firmware reading and
pulsing them, is proven on the streams that stress it: the longest, the most bytes, the
densest burst, the most servos in one frame, the shortest, and the ones a test names."""

from __future__ import annotations

from collections.abc import Iterable, Mapping

import numpy as np

from inmoov_dsl.compiling.compiled import Stream

BURST = 0.1  #: s: the window the densest burst of bytes is counted in


def hardest(streams: Mapping[str, Stream], named: Iterable[str] = ()) -> list[str]:
    """``named``, then the gestures whose stream is the longest in time, has the most
    bytes, the densest burst, the most servo commands in one frame, the fewest bytes
    (each once, in that order)."""
    def burst(stream: Stream) -> int:
        t = np.asarray(stream.times)
        return int(np.max(np.searchsorted(t, t + BURST) - np.arange(len(t)))) if len(t) else 0

    def frame(stream: Stream) -> int:
        t = np.round(np.asarray(stream.times) / 0.02)
        return int(np.max(np.unique(t, return_counts=True)[1])) if len(t) else 0

    moving = {n: s for n, s in streams.items() if len(s.data)}
    picks = [*named,
             max(moving, key=lambda n: moving[n].times[-1]),
             max(moving, key=lambda n: len(moving[n].data)),
             max(moving, key=lambda n: burst(moving[n])),
             max(moving, key=lambda n: frame(moving[n])),
             min(moving, key=lambda n: len(moving[n].data))]
    return list(dict.fromkeys(picks))
