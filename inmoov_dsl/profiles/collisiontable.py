"""The ``[collision]`` table of a profile: how close two of the robot's parts may come
before they count as touching (beside ``tables``: one validator per table)."""

from __future__ import annotations

from typing import Any

from ..errors import did_you_mean
from ..hardware import CLEARANCE_MM
from . import fields as check
from .keys import Report

MAX_CLEARANCE_MM = 100.0
KEYS = ("clearance_mm",)


def collision(report: Report, data: Any) -> float:
    """``[collision]``: ``clearance_mm``, a number from 0 (only parts that overlap
    touch) to MAX_CLEARANCE_MM. The clearance; the default where it is wrong."""
    if not isinstance(data, dict):
        report.error(("collision",), "[collision] must be a table: clearance_mm = 10")
        return CLEARANCE_MM
    for key in data:
        if key not in KEYS:
            report.error(("collision", key), f"[collision]: unknown key '{check.cut(key)}'",
                         did_you_mean(key, KEYS) or "its key is clearance_mm")
    value = data.get("clearance_mm", CLEARANCE_MM)
    if isinstance(value, bool) or not isinstance(value, int | float) or not (
            0 <= value <= MAX_CLEARANCE_MM):
        report.error(("collision", "clearance_mm"), "[collision]: 'clearance_mm' must be a "
                     f"number of millimetres in 0..{MAX_CLEARANCE_MM:.0f}, got "
                     f"{check.shown(value)}", "clearance_mm = 10 (0: only parts that overlap "
                     "touch)")
        return CLEARANCE_MM
    return float(value)
