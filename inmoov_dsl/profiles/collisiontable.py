"""The ``[collision]`` table of a profile: how close two of the robot's parts may come
before they count as touching (beside ``tables``: one validator per table)."""

from __future__ import annotations

from typing import Any

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
    fields = check.Fields(report, ("collision",), data, KEYS, "[collision]")
    return fields.get("clearance_mm", clearance, CLEARANCE_MM)


def clearance(key: str, value: Any) -> float:
    """Millimetres, 0..MAX_CLEARANCE_MM."""
    if isinstance(value, bool) or not isinstance(value, int | float) or not (
            0 <= value <= MAX_CLEARANCE_MM):
        raise check.Problem(f"'{key}' must be a number of millimetres in "
                            f"0..{MAX_CLEARANCE_MM:.0f}, got {check.shown(value)}",
                            "clearance_mm = 10 (0: only parts that overlap touch)")
    return float(value)
