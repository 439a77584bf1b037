"""The ``[voice]`` table of a profile: the servo that is the mouth, its closed and
open values, and espeak-ng's voice, speed and pitch (beside ``tables``: one validator
per table)."""

from __future__ import annotations

import re
from collections.abc import Sequence
from typing import Any

from .. import protocol
from ..errors import did_you_mean
from ..hardware import Servo, Voice
from . import fields as check
from .keys import Report

VOICE_NAME = re.compile(r"[A-Za-z0-9_+-]{1,40}\Z")  #: an espeak-ng voice: en, en-us, de...
DEFAULTS = Voice("", 0, 0)
KEYS = ("mouth", "closed", "open", "voice", "speed", "pitch")


def voice(report: Report, data: Any, servos: Sequence[Servo]) -> Voice | None:
    """``[voice]``: ``mouth`` (a servo), ``closed`` and ``open`` (values within its
    range), ``voice``, ``speed`` (words per minute) and ``pitch`` (0..99)."""
    if not isinstance(data, dict):
        report.error(("voice",), "[voice] must be a table: mouth, closed, open")
        return None
    get = check.Fields(report, ("voice",), data, KEYS, "[voice]").get
    by_name = {s.name: s for s in servos}
    mouth = get("mouth", check.text, "")
    if mouth not in by_name:
        report.error(("voice", "mouth"), f"[voice]: 'mouth' must be a servo of the profile, "
                     f"got '{check.cut(mouth)}'", did_you_mean(mouth, by_name)
                     or 'mouth = "jaw"')
        return None
    servo = by_name[mouth]
    span = check.whole(servo.lo, servo.hi, f"{mouth}'s range {servo.lo}..{servo.hi}")
    closed = get("closed", span, servo.lo)
    opened = get("open", span, min(servo.hi, protocol.MAX_VALUE))
    if closed == opened:
        report.error(("voice", "open"), "[voice]: 'closed' and 'open' must differ: the mouth "
                     "would not move")
    name = get("voice", check.text, DEFAULTS.voice)
    if not VOICE_NAME.match(name):
        report.error(("voice", "voice"), f"[voice]: 'voice' must be an espeak-ng voice name "
                     f"(en, en-us, fr...), got '{check.cut(name)}'")
    speed = get("speed", check.whole(80, 450), DEFAULTS.speed)
    pitch = get("pitch", check.whole(0, 99), DEFAULTS.pitch)
    return Voice(mouth, closed, opened, name, speed, pitch, report.where(("voice",)))
