"""A servo value as a pulse width: the one mapping every kind of board uses.

A servo's calibration is an angle range: the firmware maps a command value 0..180 onto
it with the Arduino's integer ``map()`` (reversed servos map 180..0), and the Arduino
Servo library turns the angle into a pulse of 544 + angle x 1856 / 180 us. That width
is what a maker's calibration was made with, so every kind of board gives a whole value
exactly the firmware's width. A controller finer than a degree (a Maestro's quarter
microseconds, a PCA9685's ticks) takes the plan between whole values too: the width
is then interpolated between the firmware's widths at the whole values around it. A
profile may give a servo's widths for 0 and 180 in microseconds instead (``pulse``):
then the width is linear in the value.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence

import numpy as np

MAX_VALUE = 180  #: the largest command value (``protocol.MAX_VALUE``)
PULSE_MIN, PULSE_MAX = 544, 2400  #: us: the Servo library's pulse for angle 0 and 180


def arduino_map(x: int, in_min: int, in_max: int, out_min: int, out_max: int) -> int:
    """Arduino's ``map()``: integer arithmetic, the division truncated toward zero."""
    num = (x - in_min) * (out_max - out_min)
    den = in_max - in_min
    quotient = abs(num) // abs(den)
    return (quotient if (num < 0) == (den < 0) else -quotient) + out_min


def pulse_us(angle: int) -> int:
    """The pulse width (us) for a servo angle 0..180, as the Servo library computes it."""
    return arduino_map(angle, 0, MAX_VALUE, PULSE_MIN, PULSE_MAX)


def angle(value: int, calibration: Sequence[int], reversed: bool) -> int:
    """The servo angle for a command value, as the firmware computes it:
    ``map(v, 0, 180, lo, hi)``, or ``map(v, 180, 0, lo, hi)`` when reversed."""
    lo, hi = calibration
    if reversed:
        return arduino_map(value, MAX_VALUE, 0, lo, hi)
    return arduino_map(value, 0, MAX_VALUE, lo, hi)


class Widths:
    """One servo's pulse width (us) for any value 0..180, whole or not, and back."""

    def __init__(self, calibration: Sequence[int], reversed: bool,
                 pulse: Sequence[int] | None = None):
        whole = np.arange(MAX_VALUE + 1)
        if pulse is not None:
            a, b = (pulse[1], pulse[0]) if reversed else (pulse[0], pulse[1])
            self.table = self.exact = a + (b - a) * whole / MAX_VALUE
        else:
            self.table = np.array([pulse_us(angle(v, calibration, reversed))
                                   for v in whole.tolist()], dtype=float)
            lo, hi = (calibration[1], calibration[0]) if reversed else calibration
            self.exact = PULSE_MIN + (lo + (hi - lo) * whole / MAX_VALUE) * \
                (PULSE_MAX - PULSE_MIN) / MAX_VALUE

    def us(self, values) -> np.ndarray:
        """The width for each of ``values`` (clipped to 0..180)."""
        v = np.clip(np.asarray(values, dtype=float), 0, MAX_VALUE)
        return np.interp(v, np.arange(MAX_VALUE + 1), self.table)

    def value(self, us: float) -> int:
        """The whole value whose width is nearest ``us`` (a pose read back from a
        controller); of several with the same width (the firmware's truncation), the one
        whose untruncated width is nearest: 180, not 179, when both give the same."""
        off = np.abs(self.table - us)
        tied = np.flatnonzero(off <= off.min() + 1e-9)
        return int(tied[np.argmin(np.abs(self.exact[tied] - us))])


def widths(servo) -> Widths:
    """The widths of a profile's ``servo`` (its calibration, direction and ``pulse``),
    made once for each (a board's encoding asks for them at every compile)."""
    pulse = getattr(servo, "pulse", None)
    return _widths(tuple(servo.calibration), bool(servo.reversed),
                   None if pulse is None else tuple(pulse))


@functools.lru_cache(maxsize=1024)
def _widths(calibration: tuple[int, ...], reversed: bool,
            pulse: tuple[int, ...] | None) -> Widths:
    made = Widths(calibration, reversed, pulse)
    made.table.flags.writeable = made.exact.flags.writeable = False  # shared: read only
    return made
