"""The flex-sensor glove: its rules (the firmware's GloveCore, in Python), a virtual
glove that performs a known motion, and its clock recovered from the times its reports
arrive (``on_the_clock``, for gestc record). Pure: no clock and no I/O.

Every frame the glove maps each sensor's reading from its calibration onto 0..180 and
sends ``255 id v id v ...`` with the servos that moved more than the dead-band (or
reached 0 or 180); MIN and MAX from the computer (read by ``decode.Reader`` with the
``GLOVE`` policy) capture the readings as the bounds.
The firmware's host tests drive the C++ core through the same timelines.
"""

from __future__ import annotations

import random
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..compiling.plan import Plan
from ..decode import GLOVE, Reader
from ..hardware import Glove, Profile
from ..protocol import MAX_VALUE, Signal, clamp, frame


class GloveCore:
    """One glove: readings in, the bytes it sends out."""

    def __init__(self, ids: Sequence[int], calibration: Sequence[tuple[int, int]],
                 reversed_: Sequence[bool], deadband: int):
        self.ids = list(ids)
        self.settings = [tuple(c) for c in calibration]
        self.reversed = list(reversed_)
        self.deadband = deadband
        self.bounds = [list(c) for c in self.settings]
        self.sent: list[int | None] = [None] * len(self.ids)
        self._reader = Reader(GLOVE)

    @classmethod
    def from_profile(cls, profile: Profile, glove: Glove) -> GloveCore:
        """The glove of ``profile`` described by ``glove``."""
        ids = {s.name: s.id for s in profile.servos}
        return cls([ids[s.servo] for s in glove.sensors], [s.calibration for s in glove.sensors],
                   [s.reversed for s in glove.sensors], glove.deadband)

    def value(self, index: int, reading: int) -> int:
        """Sensor ``index``'s reading mapped from its bounds onto 0..180 (reversed if
        the sensor is)."""
        low, high = self.bounds[index]
        if high <= low:
            v = MAX_VALUE if reading > low else 0
        else:
            v = clamp((reading - low) * MAX_VALUE // (high - low))
        return MAX_VALUE - v if self.reversed[index] else v

    def update(self, readings: Sequence[int]) -> bytes:
        """One frame: the bytes the glove sends for ``readings`` (CANCEL, then the
        fingers that moved beyond the dead-band or reached 0 or 180), or none."""
        moved = []
        for i, reading in enumerate(readings):
            v = self.value(i, reading)
            last = self.sent[i]
            if last is not None and abs(v - last) <= self.deadband and \
                    (v not in (0, MAX_VALUE) or v == last):
                continue
            moved.append((self.ids[i], v))
            self.sent[i] = v
        return frame(moved) if moved else b""

    def feed(self, byte: int, readings: Sequence[int]) -> None:
        """Read a byte from the computer (``decode.GLOVE``): MIN or MAX captures
        ``readings`` as the lower or upper bounds, and every finger is reported again;
        any other byte is ignored."""
        for event in self._reader.feed(byte):
            match event:
                case Signal.MIN | Signal.MAX:
                    for i, reading in enumerate(readings):
                        self.bounds[i][1 if event == Signal.MAX else 0] = reading
                    self.sent = [None] * len(self.ids)


@dataclass(frozen=True)
class Imperfections:
    """What makes a real glove's stream untidy."""

    noise: float = 0.0  #: standard deviation of each reading, in command degrees
    drop: float = 0.0  #: chance that any one byte is lost
    gaps: tuple[tuple[float, float], ...] = ()  #: (start, end) s with nothing sent
    mid_command: bool = True  #: the stream starts in the middle of a command
    seed: int = 1


def glove_stream(plan: Plan, glove: Glove, untidy: Imperfections = Imperfections()
                 ) -> list[tuple[float, bytes]]:
    """(time, bytes) of a glove whose fingers perform ``plan``: each frame, every
    sensor reads the plan's position (through its calibration, plus noise), and the
    glove sends what it sends. The motion starts at time 0 and the stream runs one
    second past its end."""
    profile = plan.profile
    core = GloveCore.from_profile(profile, glove)
    rng = random.Random(untidy.seed)
    period = glove.frame_ms / 1000
    times = np.arange(0.0, plan.duration + 1.0, period)
    tracks = [plan.tracks[profile.index(s.servo)] for s in glove.sensors]
    positions = np.stack([t.position(times) for t in tracks], axis=1)
    out: list[tuple[float, bytes]] = []
    if untidy.mid_command:  # the tail of a command sent before we were listening
        out.append((0.0, bytes([core.ids[-1] if core.ids else 0, 90])))
    for t, row in zip(times.tolist(), positions.tolist(), strict=True):
        readings = []
        for (low, high), reversed_, x in zip(core.settings, core.reversed, row, strict=True):
            value = x + rng.gauss(0.0, untidy.noise) if untidy.noise else x
            share = min(1.0, max(0.0, value / MAX_VALUE))
            share = 1 - share if reversed_ else share
            readings.append(round(low + share * (high - low)))
        data = core.update(readings)
        if any(a <= t < b for a, b in untidy.gaps):
            continue
        if untidy.drop:
            data = bytes(b for b in data if rng.random() >= untidy.drop)
        if data:
            out.append((t, data))
    return out


def on_the_clock(samples: Sequence[tuple[float, int, int]], period: float
                 ) -> list[tuple[float, int, int]]:
    """A glove reports on its own clock, every ``period`` s; the computer sees the
    reports late by a varying few ms (a USB-serial chip holds them up to 16 ms). When
    the arrival times fit that clock, each is moved back onto its tick."""
    if len(samples) < 3:
        return list(samples)
    t = np.asarray([s[0] for s in samples])
    t0 = t[0]
    shift = float(np.median(t - t0 - np.round((t - t0) / period) * period))
    ticks = np.round((t - t0 - shift) / period)
    off = t - t0 - shift - ticks * period
    if np.mean(np.abs(off) < period / 3) < 0.9:
        return list(samples)  # not a periodic sender: the arrival times as they are
    return [(t0 + shift + k * period, sid, v)
            for k, (_, sid, v) in zip(ticks.tolist(), samples, strict=True)]


class VirtualGlove:
    """A glove on a simulated link: the stream of ``glove_stream`` from ``origin`` on
    (the time is passed in, as for the virtual board)."""

    def __init__(self, events: Sequence[tuple[float, bytes]], origin: float):
        self.events = list(events)
        self.origin = origin
        self.next = 0

    def write(self, data: bytes, now: float) -> None:
        """What the computer sends (MIN, MAX): this glove's readings are synthetic."""

    def read(self, now: float) -> bytes:
        """Everything the glove has sent by ``now``."""
        out = bytearray()
        while self.next < len(self.events) and self.origin + self.events[self.next][0] <= now:
            out += self.events[self.next][1]
            self.next += 1
        return bytes(out)
