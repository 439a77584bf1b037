"""Servo values as the robot model's joint positions, and back (pure).

Each servo turns one joint of the model (``joint`` in its profile table: the original
InMoov model's names, ``right_palm_to_index``, ...). The model's zero pose is the
profile's rest pose, and a joint turns as far as its servo does: a command degree is
``(max - min) / 180`` real degrees of the servo's calibration. So a joint's position
in radians is ``(value - rest) * (max - min) / 180`` degrees, and its limits are those
of the servo's range. The URDF (urdf.py), the joint-state export, the ROS node and the
browser view all convert through here.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

from ..hardware import Profile, Servo
from ..protocol import MAX_VALUE


def scale(servo: Servo) -> float:
    """Radians of the joint per command degree."""
    low, high = servo.calibration
    return math.radians((high - low) / MAX_VALUE)


def position(servo: Servo, value: Any) -> Any:
    """The joint's position (radians) when the servo holds ``value`` (a number, or a
    numpy array of them)."""
    return (value - servo.rest) * scale(servo)


def value(servo: Servo, radians: float) -> float:
    """The command value that puts the joint at ``radians`` (the rest value when the
    servo has no travel); not rounded nor clamped: the caller checks the range."""
    k = scale(servo)
    return servo.rest + radians / k if k else float(servo.rest)


def limits(servo: Servo) -> tuple[float, float]:
    """The joint's lowest and highest positions: the servo's range."""
    return position(servo, servo.lo), position(servo, servo.hi)


def names(profile: Profile) -> list[str]:
    """The joints of the profile's servos, in the profile's order."""
    return [s.joint for s in profile.servos]


def positions(profile: Profile, values: Sequence[float]) -> list[float]:
    """Joint positions of a pose given as values in the profile's servo order."""
    return [position(s, v) for s, v in zip(profile.servos, values, strict=True)]


def servo_of(profile: Profile) -> Mapping[str, Servo]:
    """Each joint's servo, by joint name."""
    return {s.joint: s for s in profile.servos}
