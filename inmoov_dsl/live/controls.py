"""A hand-driven input's map to the robot's servos (pure): ``[[control]]`` tables of a
TOML file, each a MIDI controller's control (``cc``, on ``channel`` or any) turning one
servo from ``low`` (the control at 0) to ``high`` (at 127); and what a take's messages
become: the (time, servo ID, value) samples the recorder reduces (``record.py``).

Every mistake is an error at its key, all told at once, before anything moves: an
unknown key or servo (with did-you-mean), a number out of its range, a control or a
servo mapped twice (docs/puppet.md).
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import Any

from ..errors import Diagnostic, GestError, Pos, did_you_mean
from ..hardware import Profile
from ..profiles import fields as check
from ..profiles.keys import Report
from ..profiles.profile import read_toml

KEYS = ("cc", "channel", "servo", "low", "high")
EXAMPLE = '[[control]] with cc = 1 and servo = "index"'
MAX_CONTROLS = 512  #: tables in one map: a controller has at most 16 x 128 controls


@dataclass(frozen=True)
class Control:
    """One control: MIDI control number ``cc`` on ``channel`` (1..16; None: any) turns
    the servo ``servo`` (its index in the profile) from ``low`` to ``high``."""

    cc: int
    channel: int | None
    servo: int
    low: int
    high: int

    def value(self, level: int) -> int:
        """The servo's value for the control at ``level`` (0..127), whole."""
        return int(round(self.low + (self.high - self.low) * level / 127))


def read_map(text: str, file: str, profile: Profile) -> tuple[Control, ...]:
    """The controls of a map's TOML ``text`` for ``profile``; a GestError with every
    mistake, each at its key."""
    data = read_toml(text, file)
    report = Report(text, file)
    check.Fields(report, (), data, ("control",))
    tables = data.get("control", [])
    if not isinstance(tables, list) or not all(isinstance(t, dict) for t in tables):
        report.error(("control",), "'control' must be tables: " + EXAMPLE)
        tables = []
    if not tables and not report.errors:
        report.error((), "the map has no [[control]]", EXAMPLE)
    if len(tables) > MAX_CONTROLS:
        report.error(("control",), f"the map has {len(tables)} controls: at most "
                     f"{MAX_CONTROLS}")
        tables = []
    found: list[Control] = []
    taken: dict[tuple[int, int | None], int] = {}
    turned: dict[int, int] = {}
    for k, table in enumerate(tables):
        control = _control(report, k, table, profile)
        if control is None:
            continue
        key = (control.cc, control.channel)
        clash = next((n for (cc, ch), n in taken.items() if cc == control.cc and
                      (ch is None or control.channel is None or ch == control.channel)), None)
        if clash is not None:
            report.error(("control", k, "cc"), f"control {control.cc} is mapped twice: "
                         f"control {clash + 1} of the map takes it too")
        elif control.servo in turned:
            name = profile.servos[control.servo].name
            report.error(("control", k, "servo"), f"servo '{name}' is mapped twice: "
                         f"control {turned[control.servo] + 1} of the map turns it too")
        else:
            taken[key], turned[control.servo] = k, k
            found.append(control)
    report.stop()
    return tuple(found)


def _control(report: Report, k: int, table: dict[str, Any], profile: Profile
             ) -> Control | None:
    """One ``[[control]]`` table (the k-th), or None where it is wrong (told)."""
    at = ("control", k)
    fields = check.Fields(report, at, table, KEYS, f"control {k + 1}")
    errors = len(report.errors)
    cc = fields.get("cc", _whole(0, 127, "a MIDI control number"))
    channel = fields.get("channel", _whole(1, 16, "a MIDI channel", optional=True))
    name = table.get("servo")
    if not isinstance(name, str) or name not in profile.names:
        shown = check.shown(name)
        hint = (did_you_mean(name, profile.names) if isinstance(name, str) else None) or \
            f"one of profile '{profile.name}': " + ", ".join(profile.names[:12]) + \
            (", ..." if len(profile.names) > 12 else "")
        fields.fail(f"unknown servo {shown}" if name is not None else
                    "which servo does it turn? servo = \"index\"", ("servo",) if
                    "servo" in table else (), hint)
        return None
    servo = profile.servos[profile.index(name)]
    span = _whole(servo.lo, servo.hi, f"a value of '{name}' ({servo.lo}..{servo.hi})")
    low = fields.get("low", span, servo.lo)
    high = fields.get("high", span, servo.hi)
    if len(report.errors) > errors:
        return None
    return Control(cc, channel, profile.index(name), low, high)


def _whole(lo: int, hi: int, what: str, optional: bool = False) -> check.Check[int | None]:
    def read(key: str, value: Any) -> int | None:
        if value is None and optional:
            return None
        if isinstance(value, bool) or not isinstance(value, int) or not lo <= value <= hi:
            raise check.Problem(f"'{key}' must be {what}, a whole number {lo}..{hi}, got "
                                f"{check.shown(value)}")
        return value
    return read


Message = tuple[float, int, int, int]  #: (s, channel 1..16, control number, level 0..127)


def taking(controls: Sequence[Control], channel: int, cc: int) -> Control | None:
    """The map's control that takes control change ``cc`` on ``channel`` (None: none)."""
    return next((c for c in controls if c.cc == cc and c.channel in (None, channel)), None)


def samples(messages: Iterable[Message], controls: Sequence[Control], profile: Profile
            ) -> list[tuple[float, int, int]]:
    """The (time, servo ID, value) samples of a take's control changes, in time order:
    each message a control of the map takes becomes its servo's value (the others are
    passed over)."""
    out = []
    for t, channel, cc, level in messages:
        if (c := taking(controls, channel, cc)) is not None:
            out.append((t, profile.servos[c.servo].id, c.value(level)))
    return sorted(out, key=lambda s: s[0])


def no_samples(source: str) -> GestError:
    """The error of a take that moved none of the map's controls."""
    return GestError(Diagnostic("error", f"{source} has no control change that the map "
                                f"takes", Pos(source, 1, 1),
                                "are the map's cc and channel the controller's?"))
