"""The checks of a ``.gestc`` document: ``compiled.from_json`` builds on what they accept.

A stream is accepted only if it keeps the rules a board relies on (docs/compiler.md,
"Compiled files"); anything else is a GestError at its place in the file: the line and
column of the field or list element it is about.
"""

from __future__ import annotations

import json
import math
import re
from typing import TypeVar

import numpy as np

from . import jsonpos, protocol
from .encode import Stream
from .errors import Diagnostic, GestError, Pos
from .plan import MAX_GESTURE_DURATION
from .profile import MAX_BAUD

FORMAT = "inmoov-dsl-compiled"
VERSION = 1
JSON_DEPTH = 64  #: nesting reported as too deep when json.loads gives up
_ROUNDING = 2e-9  #: s; to_json rounds times to 1e-9 s, so a gap may shrink by this
_SLACK = 1e-6  #: s; steps and bytes may end this much after the rounded duration

T = TypeVar("T")


class _NotANumber(ValueError):
    pass


class _Fields:
    """A JSON document read for people: typed fields, each error at the field it is about."""

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
            "error", f"not a usable compiled gesture: {why}", Pos(self.file, line, column,
                                                                   width),
            "compile it again with 'gestc compile'", source))

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
            raise self.bad(f"'{key}' must be {names[kind]}, got {_shown(value)}", (*path, key))
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
                or not _finite(value):
            raise self.bad(f"'{key}' must be a finite number, got {_shown(value)}",
                           (*path, key))
        return float(value)


class CompiledReader(_Fields):
    """Checks one .gestc document against the format and the rules a board relies on."""

    def read(self) -> dict[str, object]:
        """The keyword arguments of ``compiled.Compiled``, checked; its ``steps`` are
        those of ``compiled.StepSummary``."""
        doc = self.parse()
        if not isinstance(doc, dict) or doc.get("format") != FORMAT:
            raise self.bad("it is not a gestc file", ("format",))
        if doc.get("version") != VERSION:
            raise self.bad(f"format version {_shown(doc.get('version'))}, this gestc reads "
                           f"{VERSION}", ("version",))
        streams = self.field(doc, "streams", list, ())
        if not streams:
            raise self.bad("there is no stream", ("streams",))
        read = tuple(self.stream(s, k) for k, s in enumerate(streams))
        duration = self.number(doc, "duration", ())
        if not 0 <= duration <= MAX_GESTURE_DURATION:
            raise self.bad(f"a duration of {duration:g} s (at most "
                           f"{MAX_GESTURE_DURATION:g} s)", ("duration",))
        servos = self.field(doc, "servos", list, ())
        if not servos or len(servos) > protocol.MAX_SERVO_ID + 1 \
                or not all(isinstance(n, str) for n in servos) or len(set(servos)) < len(servos):
            raise self.bad("'servos' must be the names of 1 to 181 servos, each once",
                           ("servos",))
        self.together(read, duration, len(servos))
        start, final = (self.pose(doc, key, len(servos)) for key in ("start", "final"))
        profile = self.field(doc, "profile", dict, ())
        return dict(
            gesture=self.field(doc, "gesture", str, ()),
            profile=self.field(profile, "name", str, ("profile",)),
            profile_sha256=self.field(profile, "sha256", str, ("profile",)),
            sources=tuple(self.source(x, k)
                          for k, x in enumerate(self.field(doc, "sources", list, ()))),
            servos=tuple(servos),
            start=start,
            final=final,
            duration=duration,
            steps=tuple(self.step(st, k, duration)
                        for k, st in enumerate(self.field(doc, "steps", list, ()))),
            streams=read,
        )

    def pose(self, doc: dict, key: str, count: int) -> tuple[int, ...]:
        """``doc[key]``: one value 0..180 for each of ``count`` servos."""
        values = self.field(doc, key, list, ())
        if len(values) != count or not all(_whole(v) and 0 <= v <= protocol.MAX_VALUE
                                           for v in values):
            raise self.bad(f"'{key}' must be {count} whole numbers in 0..180, one per servo",
                           (key,))
        return tuple(values)

    def source(self, x: object, k: int) -> tuple[str, str]:
        """Source ``k``: (path, sha256)."""
        if not isinstance(x, dict):
            raise self.bad("a source must be {\"path\": ..., \"sha256\": ...}", ("sources", k))
        return (self.field(x, "path", str, ("sources", k)),
                self.field(x, "sha256", str, ("sources", k)))

    def step(self, st: object, k: int, duration: float) -> dict[str, object]:
        """Step ``k``, within the gesture's ``duration``: StepSummary's keyword arguments."""
        path = ("steps", k)
        if not isinstance(st, dict):
            raise self.bad("a step must be an object", path)
        kind = self.field(st, "kind", str, path)
        if kind not in ("move", "hold"):
            raise self.bad(f"a step's kind is 'move' or 'hold', got {_shown(kind)}",
                           (*path, "kind"))
        file, line = st.get("file"), st.get("line")
        if file is not None and not isinstance(file, str):
            raise self.bad(f"'file' must be a string or null, got {_shown(file)}",
                           (*path, "file"))
        if line is not None and not (_whole(line) and line >= 1):
            raise self.bad(f"'line' must be a line number or null, got {_shown(line)}",
                           (*path, "line"))
        start, end = self.number(st, "start", path), self.number(st, "end", path)
        if not 0 <= start <= end <= duration + _SLACK:
            raise self.bad(f"step {k + 1} runs from {start:g} s to {end:g} s, outside the "
                           f"gesture's {duration:g} s", path)
        asked = self.number(st, "asked", path, optional=True)
        return dict(where=self.field(st, "where", str, path), file=file, line=line,
                    kind=kind, start=start, end=end, asked=asked,
                    stretched=self.field(st, "stretched", bool, path)
                    if "stretched" in st else False)

    def stream(self, s: object, k: int) -> Stream:
        """Stream ``k``: its board, baud, send times and bytes, each by its own rules."""
        path = ("streams", k)
        if not isinstance(s, dict):
            raise self.bad("a stream must be an object", path)
        board = s.get("board")
        low, high = protocol.FIRST_BOARD_ID, min(protocol.Signal) - 1
        if not _whole(board) or not low <= board <= high:
            raise self.bad(f"a board ID is a whole number in {low}..{high}, got "
                           f"{_shown(board)}", (*path, "board"))
        baud = s.get("baud")
        if not _whole(baud) or not 0 < baud <= MAX_BAUD or protocol.pairs_per_frame(baud) < 1:
            raise self.bad(f"board {board}: a baud that carries a servo command per 20 ms "
                           f"frame is a whole number up to {MAX_BAUD:,}, got {_shown(baud)}",
                           (*path, "baud"))
        times_list = self.field(s, "times", list, path)
        data_list = self.field(s, "bytes", list, path)
        if len(times_list) != len(data_list):
            raise self.bad(f"board {board} has {len(times_list)} times for "
                           f"{len(data_list)} bytes", (*path, "times"))
        times = self.times(times_list, board, baud, (*path, "times"))
        data = self.bytes(data_list, board, (*path, "bytes"))
        return Stream(board, baud, times, data)

    def times(self, values: list, board: int, baud: int, path: tuple) -> np.ndarray:
        """Send times: finite, from 0, in order and at least a byte-time apart."""
        bad = next((n for n, t in enumerate(values) if isinstance(t, bool)
                    or not isinstance(t, int | float)), None)
        if bad is None:
            try:
                times = np.asarray(values, dtype=float)
            except OverflowError:  # an integer too large for a float
                times = np.full(len(values), np.inf)
            finite = np.isfinite(times)
            bad = None if np.all(finite) else int(np.argmin(finite))
        if bad is not None:
            raise self.bad(f"board {board}: send time {bad + 1} is not a finite number of "
                           f"seconds", (*path, bad))
        if len(times):
            steps = np.diff(times)
            if np.any(steps < 0):
                raise self.bad(f"board {board}: send times go backwards",
                               (*path, int(np.argmax(steps < 0)) + 1))
            if times[0] != 0:
                raise self.bad(f"board {board}: the first byte goes at {times[0]:g} s, not 0",
                               (*path, 0))
            tau = protocol.byte_time(baud)
            if np.any(steps < tau - _ROUNDING):
                raise self.bad(f"board {board}: two bytes closer than a byte-time "
                               f"({tau * 1000:.3f} ms at {baud} baud)",
                               (*path, int(np.argmax(steps < tau - _ROUNDING)) + 1))
        return times

    def bytes(self, values: list, board: int, path: tuple) -> bytes:
        """The bytes: CANCEL, then whole (servo ID, value) pairs, each 0..180."""
        bad = next((n for n, b in enumerate(values) if not _whole(b) or not 0 <= b <= 255),
                   None)
        if bad is not None:
            raise self.bad(f"board {board}: byte {bad + 1} is not a whole number in 0..255",
                           (*path, bad))
        data = bytes(values)
        if len(data) % 2 == 0 or data[0] != protocol.Signal.CANCEL:
            raise self.bad(f"board {board}: a stream is CANCEL (255) then whole (servo ID, "
                           f"value) pairs", (*path, 0 if not data or
                                             data[0] != protocol.Signal.CANCEL else
                                             len(data) - 1))
        pairs = np.frombuffer(data, dtype=np.uint8)[1:]
        above = pairs > protocol.MAX_VALUE
        if np.any(above):
            n = int(np.argmax(above))
            what = "servo ID" if n % 2 == 0 else "value"
            raise self.bad(f"board {board}: byte {n + 1} is {pairs[n]}, a {what} above "
                           f"{protocol.MAX_VALUE}", (*path, n + 1))
        return data

    def together(self, streams: tuple[Stream, ...], duration: float, servos: int) -> None:
        """Each board once, its bytes within the gesture's duration (and the two frames
        the encoder may send after it), a servo ID on one board only (IDs are the
        robot's), no more servo IDs than servos."""
        owner: dict[int, int] = {}
        boards: set[int] = set()
        for k, s in enumerate(streams):
            if s.board in boards:
                raise self.bad(f"board {s.board} has two streams", ("streams", k, "board"))
            boards.add(s.board)
            if s.times[-1] > duration + 2 * protocol.SERVO_FRAME + _SLACK:
                raise self.bad(f"board {s.board}: a byte goes at {s.times[-1]:g} s, after "
                               f"the gesture's {duration:g} s",
                               ("streams", k, "times", len(s.times) - 1))
            for sid in set(s.data[1::2]):
                if owner.setdefault(sid, s.board) != s.board:
                    raise self.bad(f"servo ID {sid} is on board {owner[sid]} and on board "
                                   f"{s.board}", ("streams", k, "bytes"))
        if len(owner) > servos:
            raise self.bad(f"the streams command {len(owner)} servo IDs, more than the "
                           f"{servos} servos of the gesture", ("streams",))


def _whole(value: object) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def _finite(value: int | float) -> bool:
    """A number a float can hold (an integer of 309 digits or more cannot)."""
    try:
        return math.isfinite(value)
    except OverflowError:
        return False


def _shown(value: object) -> str:
    text = json.dumps(value) if not isinstance(value, float) or math.isfinite(value) \
        else repr(value)
    return text if len(text) <= 40 else text[:37] + "..."
