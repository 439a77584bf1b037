"""Calibration found at the bench, written into the profile (pure: text in, text out).

The board maps command values 0..180 onto a servo's calibration (its angles at
straight and at curled). At the bench a person moves one servo until the finger is
straight, then curled; the angles at those two values are the new calibration, and
whether straight is the higher angle says if the servo is reversed. The speed limits
in the profile are command degrees per second, so they are rescaled to keep the
servo's real speed.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from .errors import Diagnostic, GestError
from .profile import Servo


@dataclass(frozen=True)
class Found:
    """The new settings of one servo."""

    calibration: tuple[int, int]
    reversed: bool
    max_velocity: float
    max_acceleration: float
    max_jerk: float


def found(servo: Servo, straight: int, curled: int) -> Found:
    """From the servo angles at straight and curled, and the servo's old settings."""
    if straight == curled:
        raise GestError(Diagnostic("error", f"straight and curled are the same angle "
                                   f"({straight}): move the servo between marking them"))
    lo, hi = sorted((straight, curled))
    old = servo.calibration[1] - servo.calibration[0]
    scale = old / (hi - lo) if old > 0 else 1.0
    return Found((lo, hi), straight > curled, servo.max_velocity * scale,
                 servo.max_acceleration * scale, servo.max_jerk * scale)


def _number(x: float) -> str:
    return str(int(round(x))) if abs(x) >= 10 else f"{x:.3g}"


def edit_profile(text: str, name: str, new: Found) -> str:
    """``text`` with servo ``name``'s table (``[servo.NAME]``) carrying ``new``;
    comments and everything else stay as they were."""
    lines = text.splitlines(keepends=True)
    header = re.compile(rf"\s*\[\s*servo\s*\.\s*{re.escape(name)}\s*\]")
    start = next((k for k, line in enumerate(lines) if header.match(line)), None)
    if start is None:
        raise GestError(Diagnostic("error", f"no [servo.{name}] table in the profile",
                                   hint=f"set calibration = [{new.calibration[0]}, "
                                   f"{new.calibration[1]}] and reversed = "
                                   f"{str(new.reversed).lower()} by hand"))
    end = next((k for k in range(start + 1, len(lines))
                if lines[k].lstrip().startswith("[")), len(lines))
    values = {
        "calibration": f"[{new.calibration[0]}, {new.calibration[1]}]",
        "reversed": str(new.reversed).lower(),
        "max_velocity": _number(new.max_velocity),
        "max_acceleration": _number(new.max_acceleration),
        "max_jerk": _number(new.max_jerk),
    }
    last = start
    for k in range(start + 1, end):
        m = re.match(r"(\s*)([A-Za-z_]+)(\s*=\s*)([^#\r\n]*?)(\s*(#.*)?)(\r?\n)?$", lines[k])
        if m is None:
            continue
        last = k
        if m.group(2) in values:
            value = values.pop(m.group(2))
            lines[k] = f"{m.group(1)}{m.group(2)}{m.group(3)}{value}{m.group(5)}" \
                       f"{m.group(7) or ''}"
    added = [f"{key} = {value}\n" for key, value in values.items()
             if key in ("calibration", "reversed")]
    if added and not lines[last].endswith("\n"):
        lines[last] += "\n"
    lines[last + 1:last + 1] = added
    return "".join(lines)
