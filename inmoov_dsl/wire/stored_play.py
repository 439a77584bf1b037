"""A stored gesture playing on a board, as the firmware plays it (``stored_player.cpp``),
pure: the approach from wherever the hand is to the gesture's start, within each
servo's speed and acceleration, one step a servo frame; then the stream's pairs at
their times. The virtual board (``sim.py``) runs it on its clock; the firmware's host
tests check the C++ player against ``approach``.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Sequence

from .stored import FRAME_US, UNIT, StoredSet, arrival_us, unpack

FRAME = FRAME_US / 1e6  #: s


def approach_step(position: int, speed: int, target: int, limits: tuple[int, int]
                  ) -> tuple[int, int]:
    """One frame of a servo's approach (positions in 1/UNIT of a command degree, speed
    per frame): as fast as ``limits`` (top speed, acceleration per frame) allow and
    slow enough to stop at ``target`` without passing it. The new position and speed."""
    top, accel = limits
    left = abs(target - position)
    if left == 0:
        return position, 0
    # the fastest speed from which slowing by ``accel`` a frame stops within ``left``
    stop = (math.isqrt(accel * accel + 8 * accel * left) - accel) // 2
    step = min(speed + accel, top, stop, left)
    return position + (step if target > position else -step), step


def approach(values: Sequence[int], start: Sequence[int], limits: Sequence[tuple[int, int]]
             ) -> Iterator[list[int]]:
    """The values the servos are written, frame after frame, from ``values`` until
    they reach ``start`` (nothing if they are there)."""
    at = [v * UNIT for v in values]
    speeds = [0] * len(at)
    goal = [v * UNIT for v in start]
    while at != goal:
        for j, limit in enumerate(limits):
            at[j], speeds[j] = approach_step(at[j], speeds[j], goal[j], limit)
        yield [p // UNIT for p in at]


class Playback:
    """Stored gesture ``number`` of ``flash`` started at ``now`` on servos holding
    ``values``: ``due()`` says when it next writes, ``run()`` writes what is due."""

    def __init__(self, flash: StoredSet, number: int, values: Sequence[int], now: float):
        gesture = flash.gestures[number]
        n = len(values)
        self.number = number
        self._limits = flash.limits
        self._at = [v * UNIT for v in values]  # the approach: positions, speeds, goal
        self._speeds = [0] * n
        self._goal = [v * UNIT for v in gesture.start]
        self._pairs = sorted(((arrival_us(f, j, n, flash.pair_us) / 1e6, j, v)
                              for f, j, v in unpack(gesture.data, gesture.start)),
                             key=lambda p: p[0])
        self._frames = gesture.frames
        self._played = 0
        #: when the stream started (None: still approaching the gesture's start)
        self.t0: float | None = now if self._at == self._goal else None
        self._tick = now + FRAME  # the approach's next step

    @property
    def end(self) -> float | None:
        """When the gesture ends (None: still approaching its start)."""
        return None if self.t0 is None else self.t0 + self._frames * FRAME

    def due(self) -> float:
        """When it next does something: a step of the approach, a pair, or its end."""
        if self.t0 is None:
            return self._tick
        if self._played < len(self._pairs):
            return self.t0 + self._pairs[self._played][0]
        return self.end

    def run(self) -> tuple[list[tuple[int, int]], bool]:
        """Do what is due at ``due()``: the (servo index, value) writes, and whether
        the gesture is over."""
        if self.t0 is None:
            writes = []
            for j, limit in enumerate(self._limits):
                before = self._at[j] // UNIT
                self._at[j], self._speeds[j] = approach_step(
                    self._at[j], self._speeds[j], self._goal[j], limit)
                if self._at[j] // UNIT != before:
                    writes.append((j, self._at[j] // UNIT))
            if self._at == self._goal:  # there: the stream starts now
                self.t0 = self._tick
            self._tick += FRAME
            return writes, False
        if self._played < len(self._pairs):
            _, j, value = self._pairs[self._played]
            self._played += 1
            return [(j, value)], False
        return [], True
