"""What a ``[[board]]`` says of its kind (``kind``, and the keys each kind reads), and
the channels its servos take: read once here, for every kind (``boards/`` drives them).

- ``rig`` (the default): our firmware or the original; ``baud`` (9600).
- ``maestro``: a Pololu Maestro; ``model`` (``micro6``, ``mini12``, ``mini18``,
  ``mini24``; ``mini12``), ``device`` (its device number: the Pololu protocol; none:
  the compact protocol), ``baud`` (115200: the pace its commands are timed at).
- ``mrlcomm``: an Arduino (an InMoov's Mega) running MyRobotLab's MrlComm; ``baud``
  (115200).
- ``pca9685``: a PCA9685 on an I2C bus; ``oscillator`` (Hz, the chip's measured clock,
  25,000,000), ``bus_speed`` (Hz, the bus's clock, 100,000 or 400,000).

A servo of a Maestro or a PCA9685 gives its channel as ``pin``.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from ..errors import did_you_mean
from . import fields as check
from .fields import Problem, shown

KINDS = ("rig", "maestro", "pca9685", "mrlcomm")
MODELS = ("micro6", "mini12", "mini18", "mini24")
CHANNELS = {"micro6": 6, "mini12": 12, "mini18": 18, "mini24": 24}
DEFAULT_BAUD = {"rig": 9600, "maestro": 115_200, "pca9685": 115_200, "mrlcomm": 115_200}


def kind(key: str, value: Any) -> str:
    """One of ``KINDS``."""
    if value not in KINDS:
        raise Problem(f"'{key}' must be one of {', '.join(KINDS)}, got {shown(value)}",
                      did_you_mean(str(value), KINDS) if isinstance(value, str) else None)
    return value


def model(key: str, value: Any) -> int:
    """A Maestro's model, as its place in ``MODELS``."""
    if value not in MODELS:
        raise Problem(f"'{key}' must be one of {', '.join(MODELS)}, got {shown(value)}",
                      did_you_mean(str(value), MODELS) if isinstance(value, str) else None)
    return MODELS.index(value)


def options(fields, what: str) -> tuple[tuple[str, int], ...]:
    """The keys of kind ``what`` of the board table ``fields`` reads."""
    if what == "maestro":
        found = [("model", fields.get("model", model, "mini12"))]
        device = fields.get("device", check.optional(check.whole(0, 127)))
        return tuple(found + ([("device", device)] if device is not None else []))
    if what == "pca9685":
        return (("oscillator", fields.get("oscillator", check.whole(
                    20_000_000, 30_000_000, "20,000,000..30,000,000 Hz"), 25_000_000)),
                ("bus", fields.get("bus_speed", check.whole(
                    10_000, 1_000_000, "10,000..1,000,000 Hz"), 100_000)))
    return ()


def channels(what: str, opts: Sequence[tuple[str, int]]) -> int:
    """How many channels a board of kind ``what`` has (0: pins, not channels)."""
    if what == "maestro":
        return CHANNELS[MODELS[dict(opts).get("model", 1)]]
    return {"pca9685": 16, "mrlcomm": 70}.get(what, 0)  # a Mega's pins: 0..69


def pulse(key: str, value: Any) -> tuple[int, int]:
    """[width at 0, width at 180] in us, each 400..2600, not equal."""
    pair = check.pair(value)
    if pair is None or pair[0] == pair[1] or not all(400 <= p <= 2600 for p in pair):
        raise Problem(f"'{key}' must be [width at 0, width at 180] in microseconds, each "
                      f"400..2600 and not equal, got {shown(value)}",
                      "leave it out to use the calibration's widths (the firmware's)")
    return pair


def check_channels(report, boards, servos) -> None:
    """Each servo of a Maestro or a PCA9685 on a channel the board has, one a channel."""
    for board in boards:
        count = channels(board.kind, board.options)
        if not count:
            continue
        taken: dict[int, str] = {}
        for s in (s for s in servos if s.board == board.id):
            at = ("servo", s.name, "pin")
            if s.pin is None or s.pin >= count:
                report.error(at if s.pin is not None else ("servo", s.name),
                             f"servo '{s.name}': board {board.id} ({board.kind}) has channels "
                             f"0..{count - 1}: give the servo's channel as 'pin', got "
                             f"{shown(s.pin)}")
            elif s.pin in taken:
                report.error(at, f"servo '{s.name}': channel {s.pin} of board {board.id} is "
                             f"servo '{taken[s.pin]}''s already")
            else:
                taken[s.pin] = s.name
