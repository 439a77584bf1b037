"""The checks of a profile's values, one per kind of field (as packaging's metadata
validators): each takes the key and its value, returns the value as the profile keeps
it, or raises a ``Problem`` saying what the key takes. ``Fields`` reads one TOML table
through them, reports each problem at its key, and is the one rule of unknown keys:
every key a table does not take is an error at that key, with a did-you-mean."""

from __future__ import annotations

import re
from collections.abc import Callable, Collection, Mapping
from typing import Any, TypeVar

from .. import protocol
from ..errors import did_you_mean
from .keys import Key, Report

T = TypeVar("T")

NAME_RE = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")  #: a servo's, group's or side's name
LIMITS = {"max_velocity": (1.0, 1e5), "max_acceleration": (1.0, 1e7), "max_jerk": (1.0, 1e9)}
Check = Callable[[str, Any], T]  #: (key, value) -> the value kept; raises Problem
_UNITS = {"max_velocity": "", "max_acceleration": " squared", "max_jerk": " cubed"}


class Problem(ValueError):
    """A value its key does not take: what is wrong, and what might fix it."""

    def __init__(self, message: str, hint: str | None = None):
        super().__init__(message)
        self.message = message
        self.hint = hint


def is_whole(value: Any) -> bool:
    """A TOML integer (not a boolean)."""
    return isinstance(value, int) and not isinstance(value, bool)


def cut(text: str, most: int = 40) -> str:
    """``text`` cut short to ``most`` characters."""
    return text if len(text) <= most else text[:most - 3] + "..."


def shown(value: Any) -> str:
    """A value as an error quotes it, cut short."""
    return cut(repr(value), 60)


def whole(low: int, high: int, named: str | None = None) -> Check[int]:
    """A whole number in low..high (``named`` says the range another way)."""
    def check(key: str, value: Any) -> int:
        """``value`` if it is such a number."""
        if not is_whole(value) or not low <= value <= high:
            raise Problem(f"'{key}' must be a whole number in {named or f'{low}..{high}'}, "
                          f"got {shown(value)}")
        return value
    return check


def optional(inner: Check[T]) -> Check[T | None]:
    """``inner``, or None when the key is not there."""
    return lambda key, value: None if value is None else inner(key, value)


def limit(key: str, value: Any) -> float:
    """A speed limit (``LIMITS[key]``) in command degrees per second (squared, cubed)."""
    low, high = LIMITS[key]
    if value is None:
        raise Problem(f"missing '{key}'",
                      f"add {key} = N, in command degrees per second{_UNITS[key]}")
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise Problem(f"'{key}' must be a number, got {shown(value)}")
    if not value > 0:
        raise Problem(f"'{key}' must be greater than 0, got {shown(value)}")
    if not low <= value <= high:
        raise Problem(f"'{key}' must be in {low:,.0f}..{high:,.0f}, got {shown(value)}",
                      "limits are command degrees per second (squared, cubed): see "
                      "docs/profiles.md")
    return float(value)


def pair(value: Any) -> tuple[int, int] | None:
    """Two whole numbers, as a list (or the tuple of a default), else None."""
    if isinstance(value, list | tuple) and len(value) == 2 and all(map(is_whole, value)):
        return (value[0], value[1])
    return None


def span(key: str, value: Any) -> tuple[int, int]:
    """[low, high] command degrees with 0 <= low <= high <= MAX_VALUE (180)."""
    found = pair(value)
    if found is None or not 0 <= found[0] <= found[1] <= protocol.MAX_VALUE:
        raise Problem(f"'{key}' must be [low, high] with 0 <= low <= high <= "
                      f"{protocol.MAX_VALUE}, "
                      f"got {shown(value)}")
    return found


def readings(key: str, value: Any) -> tuple[int, int]:
    """[low, high] sensor readings with 0 <= low < high <= 1023."""
    found = pair(value)
    if found is None or not 0 <= found[0] < found[1] <= 1023:
        raise Problem(f"'{key}' must be [low, high] readings with 0 <= low < high <= 1023, "
                      f"got {shown(value)}")
    return found


def pins(key: str, value: Any) -> tuple[int, int]:
    """[rx, tx], two pins 0..255."""
    found = pair(value)
    if found is None or not all(0 <= p <= 255 for p in found):
        raise Problem(f"'{key}' must be [rx, tx], got {shown(value)}")
    return found


def baud(key: str, value: Any) -> int:
    """A board's link: bits per second, fast enough to carry a servo command a frame."""
    value = whole(1, protocol.MAX_BAUD, f"1..{protocol.MAX_BAUD:,}")(key, value)
    if not protocol.usable_baud(value):
        raise Problem(f"baud {value} is too slow: not one servo command fits in a "
                      f"{protocol.SERVO_FRAME * 1000:g} ms servo frame",
                      f"use {protocol.DEFAULT_BAUD} or more")
    return value


def names(key: str, value: Any) -> list[str]:
    """A list of servo names."""
    if not isinstance(value, list) or not all(isinstance(n, str) for n in value):
        raise Problem(f"'{key}' must be a list of servo names")
    return value


def flag(key: str, value: Any) -> bool:
    """true or false."""
    if not isinstance(value, bool):
        raise Problem(f"'{key}' must be true or false, got {shown(value)}")
    return value


def joint(key: str, value: Any) -> str:
    """A joint's name in the robot's model: letters, digits and _ (as URDF and ROS want)."""
    if not isinstance(value, str) or not NAME_RE.match(value):
        raise Problem(f"'{key}' must be a joint name of letters, digits and _, got "
                      f"{shown(value)}")
    return value


def text(key: str, value: Any) -> str:
    """A string."""
    if not isinstance(value, str):
        raise Problem(f"'{key}' must be a string, got {shown(value)}")
    return value


class Fields:
    """One TOML table being read: its values (``data``), its key path (``at``), the
    keys it takes (``keys``) and the name its errors begin with (``where``: ``servo
    'index'``; none at the top level). Every key of ``data`` not in ``keys`` is an error
    at that key, at once; ``elsewhere``: a hint for a key another kind of the table
    takes. ``unknown``: those keys."""

    def __init__(self, report: Report, at: Key, data: Any, keys: Collection[str],
                 where: str = "", elsewhere: Mapping[str, str] | None = None):
        self.report, self.at, self.data, self.keys, self.where = report, at, data, keys, where
        self.unknown = [k for k in data if k not in keys] if isinstance(data, dict) else []
        takes = f"{'the keys it takes' if where else 'a profile holds'}: {', '.join(keys)}"
        for key in self.unknown:
            value = data[key]
            table = isinstance(value, dict) or bool(value) and isinstance(value, list) and all(
                isinstance(v, dict) for v in value)
            self.fail(f"unknown {'table' if table else 'key'} '{cut(key)}'", (key,),
                      did_you_mean(key, keys) or (elsewhere or {}).get(key) or takes)

    def get(self, key: str, check: Check[T], default: Any = None, fallback: Any = None
            ) -> T:
        """``check`` of the value of ``key`` (``default`` when it is not there); on a
        Problem, an error at the key, and ``fallback`` (or ``default``)."""
        try:
            return check(key, self.data.get(key, default))
        except Problem as problem:
            self.fail(problem.message, (key,), problem.hint)
            return default if fallback is None else fallback

    def fail(self, message: str, key: Key = (), hint: str | None = None) -> None:
        """An error about this table, at ``key`` under it (the table itself for ``()``)."""
        self.report.error((*self.at, *key), f"{self.where}: {message}" if self.where
                          else message, hint)
