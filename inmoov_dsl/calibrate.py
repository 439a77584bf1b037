"""Calibration found at the bench, written into the profile (pure: text in, text out,
through tomlkit so that the user's comments and layout stay).

The board maps command values 0..180 onto a servo's calibration (its angles at
straight and at curled). At the bench a person moves one servo until the finger is
straight, then curled; the angles at those two values are the new calibration, and
whether straight is the higher angle says if the servo is reversed. The speed limits
in the profile are command degrees per second, so they are rescaled to keep the
servo's real speed.
"""

from __future__ import annotations

from dataclasses import dataclass

import tomlkit
import tomlkit.exceptions

from .errors import Diagnostic, GestError
from .profile import Servo
from .profile_keys import KeyIndex


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
    """A limit as the profile writes it: whole from 10 up, three digits below."""
    return str(int(round(x))) if abs(x) >= 10 else f"{x:.3g}"


def edit_profile(text: str, name: str, new: Found) -> str:
    """``text`` with servo ``name``'s table (``[servo.NAME]``) carrying ``new``: its
    calibration and reversed (added when missing) and its limits (where it has them).
    tomlkit edits that table, keeping its comments, key order and spacing; the rest of
    the text is not touched."""
    span = KeyIndex(text, "<profile>").table(("servo", name))
    if span is None:
        raise GestError(Diagnostic("error", f"no [servo.{name}] table in the profile",
                                   hint=f"set calibration = [{new.calibration[0]}, "
                                   f"{new.calibration[1]}] and reversed = "
                                   f"{str(new.reversed).lower()} by hand"))
    start, end = span
    table, tail = _without_tail(text[start:end])
    try:
        doc = tomlkit.parse(table)
    except tomlkit.exceptions.TOMLKitError as exc:
        raise GestError(Diagnostic("error", f"cannot edit [servo.{name}]: {exc}")) from None
    servo = doc["servo"][name]
    values = {
        "calibration": f"[{new.calibration[0]}, {new.calibration[1]}]",
        "reversed": str(new.reversed).lower(),
        "max_velocity": _number(new.max_velocity),
        "max_acceleration": _number(new.max_acceleration),
        "max_jerk": _number(new.max_jerk),
    }
    for key, value in values.items():
        if key in servo or key in ("calibration", "reversed"):
            servo[key] = tomlkit.value(value)  # in place: its comment and spacing stay
    return text[:start] + tomlkit.dumps(doc) + tail + text[end:]


def _without_tail(table: str) -> tuple[str, str]:
    """A table's text, and the blank and comment lines at its end (often the next
    table's introduction), where keys added to the table must not go."""
    lines = table.split("\n")
    k = len(lines)
    while k > 1 and (not lines[k - 1].strip() or lines[k - 1].lstrip().startswith("#")):
        k -= 1
    body = "\n".join(lines[:k]) + ("\n" if k < len(lines) else "")
    return body, table[len(body):]
