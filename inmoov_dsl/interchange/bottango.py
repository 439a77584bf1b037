"""Bottango's servo and curve commands (its Arduino driver, 0.8), written from a plan and
read as its driver evaluates them (pure).

``rSVPin,<pin>,<min us>,<max us>,<max us per s>,<start us>`` registers a servo;
``sC,<pin>,<start ms>,<duration ms>,<start Y>,<start control X>,<start control Y>,<end Y>,
<end control X>,<end control Y>`` gives it a cubic Bézier curve: the points (0, start Y),
(start control X, start Y + start control Y), (duration + end control X, end Y + end
control Y), (duration, end Y), time in ms from the curve's start, Y in 8192ths of the
servo's movement from min to max (``BezierCurve``, ``BasicCommands::setCurve``). The
driver finds a moment's point by bisection on the curve's parameter until its time is
within 1 ms, and gives the servo ``round(min + (max - min) * Y / 8192)``; out of every
curve it holds the end of the last one.

A plan is piecewise cubic in time (ruckig's phases), and a cubic in time is a Bézier
curve whose time handles sit at a third of it; so each stretch of motion between two
phase changes, their times rounded to the millisecond, becomes one curve through its
ends with the plan's speed there (Hermite's form). Where a phase is shorter than a
millisecond its neighbours take it, which is the only place a curve leaves the plan
(``docs/interchange.md`` gives how far).
"""

from __future__ import annotations

import bisect
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..boards.pulses import MAX_VALUE, widths
from ..compiling.tracks import Track
from ..errors import Diagnostic, GestError
from ..hardware import Servo
from .frames import place

SCALE = 8192  #: Bottango's whole movement (COMPRESSED_SIGNAL_MAX)
STILL = 1e-6  #: degrees/s: a piece slower than this does not move


@dataclass(frozen=True)
class Curve:
    """One ``sC`` command's numbers."""

    pin: int
    start: int  #: ms
    duration: int  #: ms
    y0: int
    cx0: int
    cy0: int
    y1: int
    cx1: int
    cy1: int

    def line(self) -> str:
        """The command as Bottango's driver reads it."""
        return "sC," + ",".join(str(v) for v in (
            self.pin, self.start, self.duration, self.y0, self.cx0, self.cy0, self.y1,
            self.cx1, self.cy1))

    def at(self, ms: int) -> float:
        """The movement (0..1) at ``ms`` (within the curve), as ``FloatBezierCurve``
        finds it: bisection from u = 0.5 until the time is within 1 ms."""
        x = ms - self.start
        lo, hi, u = 0.0, 1.0, 0.5
        for _ in range(64):
            ex = _bezier(u, 0.0, self.cx0, self.duration + self.cx1, self.duration)
            if abs(ex - x) < 1:
                break
            lo, hi = (lo, u) if ex > x else (u, hi)
            u = (hi - lo) / 2 + lo
        return _bezier(u, self.y0, self.y0 + self.cy0, self.y1 + self.cy1, self.y1) / SCALE


def _bezier(u: float, p0: float, p1: float, p2: float, p3: float) -> float:
    """De Casteljau's construction, as the driver's ``lerp``s make it."""
    a, b, c = p0 + (p1 - p0) * u, p1 + (p2 - p1) * u, p2 + (p3 - p2) * u
    d, e = a + (b - a) * u, b + (c - b) * u
    return d + (e - d) * u


@dataclass(frozen=True)
class Setup:
    """One ``rSVPin`` command's numbers."""

    pin: int
    low: int  #: us at movement 0
    high: int  #: us at movement 1
    speed: int  #: us per s at most
    start: int  #: us at power-up

    def line(self) -> str:
        """The command as Bottango's driver reads it."""
        return f"rSVPin,{self.pin},{self.low},{self.high},{self.speed},{self.start}"

    def us(self, movement: float) -> int:
        """The width the driver gives for ``movement`` (``lerpSignal``: rounded, within
        the servo's bounds)."""
        us = int(round(self.low + (self.high - self.low) * movement))
        return min(max(us, min(self.low, self.high)), max(self.low, self.high))


def setup(servo: Servo, start: float) -> Setup:
    """``servo`` registered with movement 0..1 as values 0..180 (its widths are linear
    in the value: ``Widths.exact``), its speed limit above the servo's own."""
    exact = widths(servo).exact
    low, high = int(round(exact[0])), int(round(exact[-1]))
    speed = math.ceil(servo.max_velocity * abs(high - low) / MAX_VALUE * 1.1) + 1
    return Setup(place(servo), low, high, speed, int(round(np.interp(
        start, np.arange(MAX_VALUE + 1), exact))))


def curves(servo: Servo, track: Track, duration: float) -> list[Curve]:
    """The servo's motion in ``track`` as Bézier curves, one a stretch between phase
    changes (rounded to the ms), in time order; where it holds, no curve."""
    knots = sorted({int(round(t * 1000)) for t in track.breaks.tolist()
                    if 0 <= t <= duration} | {0, int(round(duration * 1000))})
    out = []
    for a, b in zip(knots, knots[1:], strict=False):
        ta, tb = a / 1000, b / 1000
        inside = np.linspace(ta, tb, 5)
        if np.all(np.abs(track.velocity(inside)) < STILL):
            continue
        p0, p1 = (float(v) for v in track.position(np.array([ta, tb])))
        v0, v1 = (float(v) for v in track.velocity(np.array([ta, tb])))
        d, third = tb - ta, (b - a) / 3
        y = [round(SCALE * p / MAX_VALUE) for p in (p0, p1)]
        out.append(Curve(place(servo), a, b - a, y[0], round(third),
                         round(SCALE * v0 * d / 3 / MAX_VALUE), y[1], -round(third),
                         -round(SCALE * v1 * d / 3 / MAX_VALUE)))
    return out


def read(text: str, where: str) -> tuple[dict[int, Setup], dict[int, list[Curve]]]:
    """The servos and curves of a file of Bottango's commands (one a line; lines of
    other commands are passed over); anything else an error naming its line."""
    setups: dict[int, Setup] = {}
    found: dict[int, list[Curve]] = {}
    for n, raw in enumerate(text.splitlines(), 1):
        fields = raw.strip().split(",")
        if fields[0] not in ("rSVPin", "sC"):
            continue
        want = 6 if fields[0] == "rSVPin" else 10
        try:
            numbers = [int(f) for f in fields[1:]]
        except ValueError:
            numbers = []
        if len(numbers) != want - 1:
            raise GestError(Diagnostic("error", f"{where}:{n}: {fields[0]} takes {want - 1} "
                                       f"whole numbers: {raw.strip()[:80]!r}"))
        if fields[0] == "rSVPin":
            setups[numbers[0]] = Setup(*numbers)
        else:
            curve = Curve(*numbers)
            if curve.duration < 0 or curve.start < 0:
                raise GestError(Diagnostic("error", f"{where}:{n}: a curve's start and "
                                           "duration are 0 or more ms"))
            found.setdefault(curve.pin, []).append(curve)
    if not found:
        raise GestError(Diagnostic("error", f"{where}: not Bottango's commands: no 'sC' "
                                   "curve in it"))
    return setups, found


def evaluate(setup_: Setup, found: Sequence[Curve], times_ms: Sequence[int]) -> list[int]:
    """The width the driver gives at each of ``times_ms``: the curve in progress (of
    several, the latest begun), else the end of the curve that ended last, else the
    start width."""
    by_start = sorted(found, key=lambda c: c.start)
    starts = [c.start for c in by_start]
    by_end = sorted(found, key=lambda c: c.start + c.duration)
    ends = [c.start + c.duration for c in by_end]
    out = []
    for ms in times_ms:
        k = bisect.bisect_right(starts, ms) - 1
        if k >= 0 and ms <= ends_of(by_start[k]):
            out.append(setup_.us(by_start[k].at(ms)))
            continue
        e = bisect.bisect_left(ends, ms) - 1
        out.append(setup_.us(by_end[e].y1 / SCALE) if e >= 0 else setup_.start)
    return out


def ends_of(curve: Curve) -> int:
    """When ``curve`` ends (ms)."""
    return curve.start + curve.duration
