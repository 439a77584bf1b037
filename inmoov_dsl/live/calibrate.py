"""Calibration found at the bench, written into the profile (pure: text in, text out,
through tomlkit so that the user's comments and layout stay).

The board maps command values 0..180 onto a servo's calibration (its angles at
straight and at curled). At the bench a person moves one servo until the finger is
straight, then curled; the angles at those two values are the new calibration, and
whether straight is the higher angle says if the servo is reversed. The speed limits
in the profile are command degrees per second, so they are rescaled to keep the
servo's real speed.

``Ends`` is the session at the bench: keys come in (the bench tools' one key map,
``keymap``), the value moves, Enter keeps it as straight, then as curled.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import tomlkit
import tomlkit.exceptions

from ..errors import Diagnostic, GestError
from ..hardware import Servo
from ..profiles.keys import KeyIndex
from ..protocol import clamp
from . import keymap

ENDS = ("straight", "curled")
HELP = "Move the finger straight and press Enter, then curled and Enter again.\n" + \
    keymap.help_text(
        ("move", "keep", "undo", "save", "quit"),
        {"keep": "keep the pose as an end", "undo": "take back the last end",
         "save": "write the ends into the profile", "quit": "leave without writing"})


@dataclass
class Ends:
    """One servo at the bench: the value it is at, and the values kept as its ends
    (straight, then curled). ``angle`` is the servo angle a value gives on the board."""

    name: str
    value: int
    angle: Callable[[int], int]
    kept: list[int] = field(default_factory=list)
    asking: bool = False  #: q was pressed with ends not written: q again leaves
    note: str = ""

    def press(self, key: str) -> str | None:
        """Apply a key; returns what the caller must do: 'send' (the new value),
        'save' (both ends are kept), 'quit', or None (only redraw). Leaving with ends
        kept asks first: q again leaves, any other key carries on."""
        act, amount = keymap.action(key) or ("", 0)
        asked, self.asking, self.note = self.asking, False, ""
        if act == "move":
            value = clamp(self.value + int(amount))
            if value == self.value:
                return None
            self.value = value
            return "send"
        if act == "keep" and len(self.kept) < 2:
            self.kept.append(self.value)
        elif act == "keep":
            self.note = "both ends kept: s writes them, u takes back the curled one"
        elif act == "undo" and self.kept:
            self.kept.pop()
        elif act == "save" and len(self.kept) == 2:
            return "save"
        elif act == "save":
            self.note = "keep both ends first: Enter at straight, then at curled"
        elif act == "quit":
            if not self.kept or asked:
                return "quit"
            self.asking = True
        return None

    def marks(self) -> dict[str, int]:
        """The ends kept so far, as servo angles: {'straight': .., 'curled': ..}."""
        return {end: self.angle(v) for end, v in zip(ENDS, self.kept, strict=False)}

    def line(self) -> str:
        """The state in one line: value, angle, the ends kept, and what comes next."""
        if self.asking:
            return (f"{len(self.kept)} end{'' if len(self.kept) == 1 else 's'} not "
                    f"written: q again leaves without them, any other key goes on")
        kept = "  ".join(f"{k} {v}" for k, v in self.marks().items())
        then = self.note or (f"Enter keeps {ENDS[len(self.kept)]}" if len(self.kept) < 2
                             else "s writes them")
        return (f"{self.name}: value {self.value:>3}  angle {self.angle(self.value):>3}"
                f"  |  {kept + '  |  ' if kept else ''}{then}")


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
