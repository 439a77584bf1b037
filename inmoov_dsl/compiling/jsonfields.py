"""A JSON document read for people: ``Fields`` gives typed fields and puts each error at
the line and column of the field it is about (``jsonpos``)."""

from __future__ import annotations

import json
import math
import re
from typing import TypeVar

from ..errors import Diagnostic, GestError, Pos
from . import jsonpos

JSON_DEPTH = 64  #: nesting reported as too deep when json.loads gives up

T = TypeVar("T")


class _NotANumber(ValueError):
    pass


class Fields:
    """A JSON document read for people: typed fields, each error at the field it is about
    (``WHAT: why``, with ``HINT``)."""

    WHAT = "not a usable document"
    HINT: str | None = None

    def __init__(self, text: str, file: str):
        self.text, self.file = text, file

    def bad(self, why: str, path: tuple = (), at: int | None = None) -> GestError:
        """An error about the value at ``path`` (keys and indices), or at offset ``at``."""
        line, column, width = (jsonpos.position(self.text, at) if at is not None
                               else jsonpos.locate(self.text, path))
        lines = self.text.split("\n", line)
        source = lines[line - 1] if line <= len(lines) else None
        if not source or len(source) > 10_000:
            source = None  # nothing to show, or a whole document on one line
        return GestError(Diagnostic(
            "error", f"{self.WHAT}: {why}", Pos(self.file, line, column, width), self.HINT,
            source))

    def parse(self) -> object:
        """The document, as ``json.loads`` reads it (NaN and Infinity refused)."""
        def constant(name: str) -> float:
            raise _NotANumber(name)

        try:
            return json.loads(self.text, parse_constant=constant)
        except json.JSONDecodeError as exc:
            raise self.bad(f"invalid JSON ({exc.msg})", at=exc.pos) from None
        except _NotANumber as exc:
            raise self.bad(f"{exc} is not a number JSON allows",
                           at=max(0, self.text.find(str(exc)))) from None
        except RecursionError:
            raise self.bad("arrays or objects nested too deep",
                           at=jsonpos.nested_deeper(self.text, JSON_DEPTH)) from None
        except ValueError:  # an integer of more than 4,300 digits
            found = re.search(r"\d{100}", self.text)
            raise self.bad("invalid JSON (a number of thousands of digits)",
                           at=found.start() if found else 0) from None

    def field(self, obj: dict, key: str, kind: type[T], path: tuple) -> T:
        """``obj[key]``, which must be there and a ``kind`` (list, dict, str or bool)."""
        if key not in obj:
            raise self.bad(f"missing field '{key}'", path)
        value = obj[key]
        if not isinstance(value, kind) or isinstance(value, bool) and kind is not bool:
            names = {list: "a list", dict: "an object", str: "a string", bool: "true or false"}
            raise self.bad(f"'{key}' must be {names[kind]}, got {shown(value)}", (*path, key))
        return value

    def number(self, obj: dict, key: str, path: tuple, optional: bool = False
               ) -> float | None:
        """``obj[key]`` as a finite float; None if it is ``optional`` and missing or null."""
        if key not in obj and not optional:
            raise self.bad(f"missing field '{key}'", path)
        value = obj.get(key)
        if optional and value is None:
            return None
        if isinstance(value, bool) or not isinstance(value, int | float) \
                or not finite(value):
            raise self.bad(f"'{key}' must be a finite number, got {shown(value)}",
                           (*path, key))
        return float(value)


def whole(value: object) -> bool:
    """An integer, not a boolean."""
    return isinstance(value, int) and not isinstance(value, bool)


def finite(value: int | float) -> bool:
    """A number a float can hold (an integer of 309 digits or more cannot)."""
    try:
        return math.isfinite(value)
    except OverflowError:
        return False


def shown(value: object) -> str:
    """A value as a message quotes it."""
    text = json.dumps(value) if not isinstance(value, float) or math.isfinite(value) \
        else repr(value)
    return text if len(text) <= 40 else text[:37] + "..."
