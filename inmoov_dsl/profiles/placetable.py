"""The ``[place.NAME]`` tables of a profile: the robot's own places (its desk, a cup's
spot), which its gestures name as they name the places a file defines (beside
``tables``: one validator per table)."""

from __future__ import annotations

import math
from typing import Any

from ..errors import did_you_mean
from ..language.syntax import KEYWORDS
from ..language.tree import LENGTHS, MAX_DISTANCE
from . import fields as check
from .keys import Report

EXAMPLE = "[place.cup] and mm = [350, -200, 300] (x forward, y to the left, z up)"


def places(report: Report, data: Any) -> dict[str, tuple[float, float, float]]:
    """``[place.NAME]`` tables, each one key: ``mm`` or ``m``, three numbers in the
    robot's base frame. Each place in metres, by name; a wrong one left out (told)."""
    if not isinstance(data, dict):
        report.error(("place",), "'place' must hold tables: " + EXAMPLE)
        return {}
    found: dict[str, tuple[float, float, float]] = {}
    for name, table in data.items():
        at = ("place", name)
        if not isinstance(table, dict):
            report.error(at, f"place '{check.cut(name)}' must be a table: " + EXAMPLE)
            continue
        if not name.isidentifier() or name in KEYWORDS:
            report.error(at, f"'{check.cut(name)}' cannot be a place's name",
                         "a place's name is a word of letters, digits and _")
            continue
        fields = check.Fields(report, at, table, tuple(LENGTHS), f"place '{name}'")
        units = [u for u in LENGTHS if u in table]
        if len(units) != 1:
            if not fields.unknown:
                fields.fail("needs its place once, in mm or in m",
                            hint=did_you_mean("mm", list(table)) or EXAMPLE)
            continue
        xyz = fields.get(units[0], _xyz(LENGTHS[units[0]]))
        if xyz is not None:
            found[name] = xyz
    return found


def _xyz(scale: float) -> check.Check[tuple[float, float, float] | None]:
    def read(key: str, value: Any) -> tuple[float, float, float]:
        if not (isinstance(value, list) and len(value) == 3 and all(
                isinstance(v, int | float) and not isinstance(v, bool) for v in value)):
            raise check.Problem(f"'{key}' must be three numbers, x, y and z, got "
                                f"{check.shown(value)}", EXAMPLE)
        if not all(math.isfinite(v) and abs(v * scale) <= MAX_DISTANCE for v in value):
            raise check.Problem(f"'{key}' is further than any robot reaches (at most "
                                f"{MAX_DISTANCE:g} m from its base)")
        return tuple(float(v) * scale for v in value)  # type: ignore[return-value]
    return read
