"""Where the keys of a profile's TOML text are, so that every error points at its key.

tomllib gives values, not positions. One pass over the text (already valid TOML) records
where each key, table header and array element starts, by its path of keys:
``("board", 0, "baud")`` is ``baud`` of the first ``[[board]]``, ``("servo", "a")`` the
header ``[servo.a]``, ``("glove", 0, "sensors", 2, "pin")`` the ``pin`` of the third
sensor of the first glove. ``Report`` collects a profile's errors, each placed there.
"""

from __future__ import annotations

import re
from bisect import bisect_left, bisect_right
from itertools import accumulate

from ..errors import Diagnostic, GestError, Pos

Key = tuple[str | int, ...]  #: a path of keys (table names, keys, array positions)

_SKIP = re.compile(r"(?:[ \t\r\n]|#[^\n]*)*")  # blanks, newlines, comments
_BLANKS = re.compile(r"[ \t]*")
_BASIC = r'"(?:[^"\\\n]|\\.)*"'  # a string on one line, "..." or '...'
_LITERAL = r"'[^'\n]*'"
_PART = rf"[A-Za-z0-9_-]+|{_BASIC}|{_LITERAL}"
_KEY = re.compile(rf"(?:{_PART})(?:[ \t]*\.[ \t]*(?:{_PART}))*")
_PARTS = re.compile(_PART)
_STRING = re.compile(rf'''"""(?:[^\\]|\\[\s\S])*?"""(?:""?)?|\'\'\'[\s\S]*?\'\'\'(?:\'\'?)?'''
                     rf"|{_BASIC}|{_LITERAL}")
_SCALAR = re.compile(r"[^,\]}\n#]*")  # a number, a boolean, a date: up to what ends it
#: a whole line ``key = value`` with a one-line string or a scalar (most of a profile)
_SIMPLE = re.compile(rf"({_KEY.pattern})[ \t]*=[ \t]*(?:{_BASIC}|{_LITERAL}"
                     rf"""|[^\s\[\]{{}}"'#,=][^\n#\[\]{{}}"',]*)[ \t\r]*(?:#[^\n]*)?(?=\n|\Z)""")


class KeyIndex:
    """The place of every key, header and array element of a profile's text."""

    def __init__(self, text: str, file: str):
        self.file = file
        self.lines = text.split("\n")
        self._starts = [0, *accumulate(len(line) + 1 for line in self.lines)]
        self._places: dict[Key, tuple[int, int]] = {}  #: offset, width
        self._headers: list[int] = []  #: where each table header starts, in order
        self._length = len(text)
        self._scan(text)

    def find(self, key: Key) -> tuple[Pos, str]:
        """Where ``key`` is, and its line: the key itself, else the nearest table or
        array element that holds it (a missing key's table), else line 1."""
        for n in range(len(key), 0, -1):
            if (place := self._places.get(key[:n])) is not None:
                break
        else:
            return Pos(self.file, 1, 1), self.lines[0]
        offset, width = place
        line = bisect_right(self._starts, offset)
        column = offset - self._starts[line - 1] + 1
        return Pos(self.file, line, column, width), self.lines[line - 1]

    def table(self, key: Key) -> tuple[int, int] | None:
        """Where the table with the header ``[key]`` is in the text: from its header to
        the next header (or the end); None when no header names it."""
        place = self._places.get(key)
        k = bisect_left(self._headers, place[0]) if place else len(self._headers)
        if k == len(self._headers) or self._headers[k] != place[0]:
            return None
        return place[0], self._headers[k + 1] if k + 1 < len(self._headers) else self._length

    def _scan(self, text: str) -> None:
        table: Key = ()  # the table of the last header
        arrays: dict[Key, int] = {}  # arrays of tables: the last index of each
        stack: list[list] = []  # open values: [path, next index] of an array, [path, None]
        i = _SKIP.match(text).end()
        while i < len(text):
            top = stack[-1] if stack else None
            if top is None and (simple := _SIMPLE.match(text, i)):  # key = 1, most keys
                self._key(table, simple[1], i)
                i = simple.end()
            elif top is None and text[i] == "[":
                table, i = self._header(text, i, arrays)
            elif text[i] in "]}":
                if stack:
                    stack.pop()
                i += 1
            elif text[i] == ",":
                i += 1
            elif top is not None and top[1] is not None:  # an element of an array
                path = (*top[0], top[1])
                top[1] += 1
                i = self._value(text, i, path, stack)
            elif found := _KEY.match(text, i):  # key = value, in a table or inline table
                path = self._key(top[0] if top else table, found[0], i)
                i = _SKIP.match(text, found.end()).end()
                i = _SKIP.match(text, i + text.startswith("=", i)).end()
                i = self._value(text, i, path, stack, record=False)
            else:
                i += 1
            i = _SKIP.match(text, i).end()

    def _key(self, table: Key, key: str, i: int) -> Key:
        """The path of the (dotted) ``key`` at ``i`` in ``table``, recorded with the
        tables its dots make (``a.b = 1`` makes ``a``)."""
        path = table
        for part in _parts(key):
            path = (*path, part)
            self._places.setdefault(path, (i, len(key)))
        return path

    def _header(self, text: str, i: int, arrays: dict[Key, int]) -> tuple[Key, int]:
        """The table of the header ``[a.b]`` or ``[[a.b]]`` at ``i``, and where it ends."""
        double = text.startswith("[[", i)
        found = _KEY.match(text, _BLANKS.match(text, i + 1 + double).end())
        parts = _parts(found[0]) if found else []
        close = text.find("]", found.end() if found else i + 1)
        end = max(i + 1, close + 1 + double if close >= 0 else len(text))
        path: Key = ()
        for n, part in enumerate(parts):
            path = (*path, part)
            if double and n == len(parts) - 1:
                arrays[path] = arrays.get(path, -1) + 1
            self._places.setdefault(path, (i, end - i))  # a table, or its first header
            if path in arrays:
                path = (*path, arrays[path])
                self._places.setdefault(path, (i, end - i))
        self._headers.append(i)
        return path, end

    def _value(self, text: str, i: int, path: Key, stack: list[list], record: bool = True
               ) -> int:
        """Past the value at ``i``; an array or inline table is opened on ``stack``."""
        if text.startswith(("[", "{"), i):
            stack.append([path, 0 if text[i] == "[" else None])
            end, width = i + 1, 1
        else:
            found = _STRING.match(text, i) or _SCALAR.match(text, i)
            end, width = found.end(), max(1, len(found[0].rstrip()))
        if record:
            self._places.setdefault(path, (i, width))
        return end


def _parts(key: str) -> list[str]:
    """The names of a dotted key, unquoted: ``a."b.c"`` is ``["a", "b.c"]``."""
    return [p[1:-1] if p[0] in "\"'" else p for p in _PARTS.findall(key)]


class Report:
    """The errors found in one profile, each at the line of the key it is about."""

    def __init__(self, text: str, file: str):
        self.index = KeyIndex(text, file)
        self.errors: list[Diagnostic] = []

    def where(self, key: Key) -> Pos:
        """The place of ``key`` (see ``KeyIndex.find``)."""
        return self.index.find(key)[0]

    def error(self, key: Key, message: str, hint: str | None = None) -> None:
        """An error at ``key``'s place, with its line."""
        pos, line = self.index.find(key)
        self.errors.append(Diagnostic("error", message, pos, hint, line))

    def stop(self) -> None:
        """Raise the errors found so far as one GestError, if there are any."""
        if self.errors:
            raise GestError(self.errors)
