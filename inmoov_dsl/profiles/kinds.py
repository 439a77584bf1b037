"""What a ``[[board]]`` says of its kind (``kind``, and the keys each kind reads), and
the channels its servos take: read once here, for every kind (``boards/`` drives them).

- ``rig`` (the default): our firmware or the original; ``baud`` (9600), ``arduino``
  (``uno``, ``nano``, ``mega``; ``uno``): the board it runs on (its pins, the image built).
- ``maestro``: a Pololu Maestro; ``model`` (``micro6``, ``mini12``, ``mini18``,
  ``mini24``; ``mini12``), ``device`` (its device number: the Pololu protocol; none:
  the compact protocol), ``baud`` (115200: the pace its commands are timed at).
- ``mrlcomm``: an Arduino (an InMoov's Mega) running MyRobotLab's MrlComm; ``baud``
  (115200), ``arduino`` (``mega``).
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
#: the Arduinos a board of ours or MrlComm's runs on: (name, its MCU, its digital pins,
#: its first analog pin, A0)
ARDUINOS = (("uno", "atmega328p", 20, 14), ("nano", "atmega328p", 20, 14),
            ("mega", "atmega2560", 70, 54))
ARDUINO_NAMES = tuple(a[0] for a in ARDUINOS)
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


def arduino(key: str, value: Any) -> int:
    """An Arduino's name, as its place in ``ARDUINOS``."""
    if value not in ARDUINO_NAMES:
        raise Problem(f"'{key}' must be one of {', '.join(ARDUINO_NAMES)}, got {shown(value)}",
                      did_you_mean(str(value), ARDUINO_NAMES) if isinstance(value, str)
                      else None)
    return ARDUINO_NAMES.index(value)


def most_servos(opts: Sequence[tuple[str, int]]) -> int:
    """The servos our firmware pulses on that Arduino (its timers: 12 on an Uno, 32 on a
    Mega; firmware/libraries/InmoovDsl/src/servo_pulses.h)."""
    return 32 if mcu(opts) == "atmega2560" else 12


def _arduino(opts: Sequence[tuple[str, int]]) -> tuple[str, str, int, int]:
    """The Arduino a board's options name (an Uno when they name none)."""
    return ARDUINOS[dict(opts).get("arduino", 0)]


def mcu(opts: Sequence[tuple[str, int]]) -> str:
    """The microcontroller of an Arduino board (of kind ``rig`` or ``mrlcomm``)."""
    return _arduino(opts)[1]


def arduino_of(board) -> tuple[str, str, int, int]:
    """The Arduino a board runs on: (name, MCU, digital pins, A0's pin)."""
    return _arduino(board.options)


def options(fields, what: str) -> tuple[tuple[str, int], ...]:
    """The keys of kind ``what`` of the board table ``fields`` reads."""
    if what == "maestro":
        found = [("model", fields.get("model", model, "mini12", fallback=1))]
        device = fields.get("device", check.optional(check.whole(0, 127)))
        return tuple(found + ([("device", device)] if device is not None else []))
    if what == "pca9685":
        return (("oscillator", fields.get("oscillator", check.whole(
                    20_000_000, 30_000_000, "20,000,000..30,000,000 Hz"), 25_000_000)),
                ("bus", fields.get("bus_speed", check.whole(
                    10_000, 1_000_000, "10,000..1,000,000 Hz"), 100_000)))
    if what in ("rig", "mrlcomm"):
        default = "mega" if what == "mrlcomm" else "uno"
        return (("arduino", fields.get("arduino", arduino, default,
                                       fallback=ARDUINO_NAMES.index(default))),)
    return ()


def channels(what: str, opts: Sequence[tuple[str, int]]) -> int:
    """How many channels a board of kind ``what`` has (an Arduino's: its digital pins)."""
    if what == "maestro":
        return CHANNELS[MODELS[dict(opts).get("model", 1)]]
    if what == "pca9685":
        return 16
    return _arduino(opts)[2]


def _pin_problem(board, pin: int | None) -> str | None:
    """What is wrong with an Arduino's servo on ``pin`` (None: nothing)."""
    name, _, count, _ = arduino_of(board)
    if pin is None:
        # our firmware's sketch asks for it when it is built; MrlComm needs it at once
        return None if board.kind == "rig" else "give the servo's Arduino pin as 'pin'"
    if 2 <= pin < count:
        return None
    where = ("pins 0 and 1 are the board's serial port" if pin in (0, 1)
             else f"an Arduino {name.capitalize()} has pins 2..{count - 1}")
    return f"pin {pin} cannot drive a servo: {where}"


def pulse(key: str, value: Any) -> tuple[int, int]:
    """[width at 0, width at 180] in us, each 400..2600, not equal."""
    pair = check.pair(value)
    if pair is None or pair[0] == pair[1] or not all(400 <= p <= 2600 for p in pair):
        raise Problem(f"'{key}' must be [width at 0, width at 180] in microseconds, each "
                      f"400..2600 and not equal, got {shown(value)}",
                      "leave it out to use the calibration's widths (the firmware's)")
    return pair


def check_channels(report, boards, servos) -> None:
    """Each servo on a channel (a pin) its board has, one a channel."""
    for board in boards:
        count = channels(board.kind, board.options)
        taken: dict[int, str] = {}
        for s in (s for s in servos if s.board == board.id):
            at = ("servo", s.name, "pin")
            if board.kind in ("rig", "mrlcomm"):
                problem = _pin_problem(board, s.pin)
                if problem:
                    mega = (mcu(board.options) != "atmega2560" and s.pin is not None
                            and s.pin < 70)
                    report.error(at if s.pin is not None else ("servo", s.name),
                                 f"servo '{s.name}' of board {board.id}: {problem}",
                                 hint="on a Mega? say arduino = \"mega\" in its [[board]]"
                                 if mega and s.pin > 1 else None)
                elif s.pin is not None and s.pin in taken:
                    report.error(at, f"servo '{s.name}': pin {s.pin} of board {board.id} is "
                                 f"servo '{taken[s.pin]}''s already")
                if s.pin is not None:
                    taken.setdefault(s.pin, s.name)
                continue
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
