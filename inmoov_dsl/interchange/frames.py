"""A compiled gesture as the frames another animation tool keeps: the pulse width each
servo of one board is given on every frame (pure).

A frame is a moment, ``k / fps`` s from the start; its width is the one the board gives
for the servo's planned value then (a rig's whole value, another kind's finer width):
the plan, not the link's delay in reaching the board, so another tool plays the motion
our boards are told to follow. Widths are written in the unit the other tool's servos
take (``UNITS``): microseconds, the Servo library's degrees (``Servo.write``), or a
PCA9685's 4096ths of its frame.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..boards import controller
from ..boards.pca9685.chip import OSCILLATOR, prescale
from ..boards.pulses import MAX_VALUE, PULSE_MAX, PULSE_MIN, widths
from ..boards.rig.encode import round_values
from ..compiling.plan import Plan
from ..hardware import Board, Profile, Servo

FRAME_HZ = 50  #: the servo frame a PCA9685 is set up for


@dataclass(frozen=True)
class Frames:
    """One board's servos on every frame of a gesture."""

    board: Board
    servos: tuple[Servo, ...]  #: the board's, in its order
    fps: float
    times: np.ndarray  #: s: frame k at k / fps, the last at or after the gesture's end
    widths: np.ndarray  #: [frame][servo] us, as the board gives them

    @property
    def places(self) -> tuple[int, ...]:
        """Each servo's place on its board (pin or channel): how other tools address it."""
        return tuple(place(s) for s in self.servos)


def place(servo: Servo) -> int:
    """The servo's pin (a Maestro's or a PCA9685's channel), else its ID."""
    return servo.id if servo.pin is None else servo.pin


def board_frames(plan: Plan, board: Board, fps: float) -> Frames:
    """Every frame of ``board`` at ``fps``, from the start to the first frame at or after
    the end: each servo's planned value then, as the width the board gives for it (a
    rig's whole value, rounded as its encoder rounds; another kind's width between)."""
    times = np.arange(int(math.ceil(plan.duration * fps - 1e-9)) + 1) / fps
    profile = plan.profile
    kind = controller(profile, board)
    servos = tuple(kind.servos)
    out = np.empty((len(times), len(servos)))
    for k, servo in enumerate(servos):
        value = plan.tracks[profile.index(servo.name)].position(times)
        if kind.unit_us is None:
            value = round_values(value)
        out[:, k] = widths(servo).us(value)
    return Frames(board, servos, float(fps), times, out)


def tick_us(profile: Profile, board: Board) -> float:
    """A PCA9685 tick (us): the board's own if it is one, else a 25 MHz chip's at 50 Hz."""
    if board.kind == "pca9685":
        return float(controller(profile, board).tick) * 1e6
    return (prescale(FRAME_HZ, OSCILLATOR) + 1) / OSCILLATOR * 1e6


def to_units(us: np.ndarray, unit: str, tick: float) -> np.ndarray:
    """Widths (us) as whole numbers of ``unit``: us, the Servo library's degrees (the
    angle whose pulse is nearest), or PCA9685 ticks of ``tick`` us."""
    us = np.asarray(us, dtype=float)
    if unit == "us":
        out = np.round(us)
    elif unit == "degrees":
        out = np.round((us - PULSE_MIN) * MAX_VALUE / (PULSE_MAX - PULSE_MIN))
    else:
        out = np.round(us / tick)
    return out.astype(np.int64)


def from_units(values: np.ndarray, unit: str, tick: float) -> np.ndarray:
    """Positions in ``unit`` back to widths (us)."""
    v = np.asarray(values, dtype=float)
    if unit == "us":
        return v
    if unit == "degrees":
        return PULSE_MIN + v * (PULSE_MAX - PULSE_MIN) / MAX_VALUE
    return v * tick

