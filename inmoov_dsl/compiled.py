"""A compiled gesture and its file formats.

``.gestc`` (JSON, versioned) carries each board's bytes with absolute send times,
the board, baud, profile and source hashes, so the player can load it without the
compiler. ``timed`` text is one line per byte, ``<seconds> <byte>``: the contract
for tools. Both are described in docs/compiled-format.md.
"""

from __future__ import annotations

import json
import math
import os
import re
from dataclasses import dataclass

import numpy as np

from . import protocol
from .encode import Stream
from .errors import Diagnostic, GestError, Pos, decode_utf8
from .plan import MAX_GESTURE_DURATION
from .profile import MAX_BAUD, Board, Profile
from .resources import read_regular

FORMAT = "inmoov-dsl-compiled"
VERSION = 1
MAX_COMPILED = 100_000_000  #: bytes (characters) of a .gestc; a larger one is not read
JSON_DEPTH = 64  #: nesting reported as too deep when json.loads gives up
_ROUNDING = 2e-9  #: s; to_json rounds times to 1e-9 s, so a gap may shrink by this
_SLACK = 1e-6  #: s; steps and bytes may end this much after the rounded duration


@dataclass(frozen=True)
class StepSummary:
    where: str
    file: str | None
    line: int | None
    kind: str
    start: float
    end: float
    asked: float | None
    stretched: bool


@dataclass(frozen=True)
class Compiled:
    """Everything the player needs: streams, poses, steps, and where they came from."""

    gesture: str
    profile: str
    profile_sha256: str
    sources: tuple[tuple[str, str], ...]  #: (path, sha256) of every file read
    servos: tuple[str, ...]
    start: tuple[int, ...]
    final: tuple[int, ...]
    duration: float  #: s; the plan's end (a final hold sends no bytes but counts)
    steps: tuple[StepSummary, ...]
    streams: tuple[Stream, ...]
    warnings: tuple[Diagnostic, ...] = ()

    def stream(self, board: int | None = None) -> Stream:
        """The stream of ``board``; with no board, the only one."""
        if board is None:
            if len(self.streams) != 1:
                boards = ", ".join(str(s.board) for s in self.streams)
                raise GestError(Diagnostic(
                    "error", f"profile '{self.profile}' has {len(self.streams)} boards "
                    f"({boards}): choose one", hint="add --board ID"))
            return self.streams[0]
        for s in self.streams:
            if s.board == board:
                return s
        raise GestError(Diagnostic("error", f"no board {board} in profile '{self.profile}'"))


def to_json(c: Compiled) -> str:
    doc = {
        "format": FORMAT,
        "version": VERSION,
        "gesture": c.gesture,
        "profile": {"name": c.profile, "sha256": c.profile_sha256},
        "sources": [{"path": p, "sha256": h} for p, h in c.sources],
        "duration": round(c.duration, 9),
        "servos": list(c.servos),
        "start": list(c.start),
        "final": list(c.final),
        "steps": [
            {"where": s.where, "file": s.file, "line": s.line, "kind": s.kind,
             "start": round(s.start, 9), "end": round(s.end, 9), "asked": s.asked,
             "stretched": s.stretched}
            for s in c.steps
        ],
        "streams": [
            {"board": s.board, "baud": s.baud,
             "times": [round(t, 9) for t in s.times.tolist()], "bytes": list(s.data)}
            for s in c.streams
        ],
    }
    return json.dumps(doc, indent=1) + "\n"


def read_compiled(path: str | os.PathLike) -> Compiled:
    """Read a ``.gestc`` file: at most MAX_COMPILED bytes (a larger file is refused before
    it is read), UTF-8, then everything ``from_json`` checks."""
    file = os.fspath(path)
    try:
        data = read_regular(file, MAX_COMPILED)
    except FileNotFoundError:
        raise GestError(Diagnostic("error", f"cannot find '{file}'")) from None
    except (OSError, ValueError) as exc:  # ValueError: a NUL in the name
        why = exc.strerror if isinstance(exc, OSError) and exc.strerror else exc
        raise GestError(Diagnostic("error", f"cannot read '{file}': {why}")) from None
    return from_json(data, file)


def from_json(text: str | bytes, file: str = "<compiled>") -> Compiled:
    """Load a ``.gestc`` document (text, or UTF-8 bytes). Anything malformed is a
    GestError at its place in the file, and a stream is accepted only if it keeps the
    rules a board relies on: CANCEL at time 0, then whole (servo ID, value) pairs with
    IDs and values in 0..180, each board's IDs its own, send times finite, in order, at
    least a byte-time apart and within the gesture's duration (at most
    MAX_GESTURE_DURATION), poses of one value 0..180 per servo."""
    if len(text) > MAX_COMPILED:
        raise _Reader("", file).bad(f"the file is larger than {MAX_COMPILED:,} bytes: "
                                    f"it is not read")
    if not isinstance(text, str):
        text = decode_utf8(bytes(text), file)
    return _Reader(text, file).read()


class _Reader:
    """Checks one .gestc document; each error points at the field it is about."""

    def __init__(self, text: str, file: str):
        self.text, self.file = text, file

    def bad(self, why: str, path: tuple = (), at: int | None = None) -> GestError:
        """An error about the value at ``path`` (keys and indices), or at offset ``at``."""
        line, column, width = (_offset_position(self.text, at) if at is not None
                               else _locate(self.text, path))
        lines = self.text.split("\n", line)
        source = lines[line - 1] if line <= len(lines) else None
        if not source or len(source) > 10_000:
            source = None  # nothing to show, or a whole document on one line
        return GestError(Diagnostic(
            "error", f"not a usable compiled gesture: {why}", Pos(self.file, line, column,
                                                                   width),
            "compile it again with 'gestc compile'", source))

    def read(self) -> Compiled:
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
        return Compiled(
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

    def parse(self) -> object:
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
                           at=_too_deep(self.text)) from None
        except ValueError:  # an integer of more than 4,300 digits
            found = re.search(r"\d{100}", self.text)
            raise self.bad("invalid JSON (a number of thousands of digits)",
                           at=found.start() if found else 0) from None

    def field(self, obj: dict, key: str, kind: type, path: tuple):
        if key not in obj:
            raise self.bad(f"missing field '{key}'", path)
        value = obj[key]
        if not isinstance(value, kind) or isinstance(value, bool) and kind is not bool:
            names = {list: "a list", dict: "an object", str: "a string", bool: "true or false"}
            raise self.bad(f"'{key}' must be {names[kind]}, got {_shown(value)}", (*path, key))
        return value

    def number(self, obj: dict, key: str, path: tuple, optional: bool = False
               ) -> float | None:
        if key not in obj and not optional:
            raise self.bad(f"missing field '{key}'", path)
        value = obj.get(key)
        if optional and value is None:
            return None
        if isinstance(value, bool) or not isinstance(value, int | float) \
                or not math.isfinite(value):
            raise self.bad(f"'{key}' must be a finite number, got {_shown(value)}",
                           (*path, key))
        return float(value)

    def pose(self, doc: dict, key: str, count: int) -> tuple[int, ...]:
        values = self.field(doc, key, list, ())
        if len(values) != count or not all(_whole(v) and 0 <= v <= protocol.MAX_VALUE
                                           for v in values):
            raise self.bad(f"'{key}' must be {count} whole numbers in 0..180, one per servo",
                           (key,))
        return tuple(values)

    def source(self, x: object, k: int) -> tuple[str, str]:
        if not isinstance(x, dict):
            raise self.bad("a source must be {\"path\": ..., \"sha256\": ...}", ("sources", k))
        return (self.field(x, "path", str, ("sources", k)),
                self.field(x, "sha256", str, ("sources", k)))

    def step(self, st: object, k: int, duration: float) -> StepSummary:
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
        return StepSummary(self.field(st, "where", str, path), file, line, kind, start, end,
                           asked, self.field(st, "stretched", bool, path)
                           if "stretched" in st else False)

    def stream(self, s: object, k: int) -> Stream:
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
        times = self.times(times_list, board, (*path, "times"))
        tau = protocol.byte_time(baud)
        if len(times):
            steps = np.diff(times)
            if np.any(steps < 0):
                raise self.bad(f"board {board}: send times go backwards",
                               (*path, "times", int(np.argmax(steps < 0)) + 1))
            if times[0] != 0:
                raise self.bad(f"board {board}: the first byte goes at {times[0]:g} s, not 0",
                               (*path, "times", 0))
            if np.any(steps < tau - _ROUNDING):
                raise self.bad(f"board {board}: two bytes closer than a byte-time "
                               f"({tau * 1000:.3f} ms at {baud} baud)",
                               (*path, "times", int(np.argmax(steps < tau - _ROUNDING)) + 1))
        data = self.bytes(data_list, board, (*path, "bytes"))
        if len(data) % 2 == 0 or data[0] != protocol.Signal.CANCEL:
            raise self.bad(f"board {board}: a stream is CANCEL (255) then whole (servo ID, "
                           f"value) pairs", (*path, "bytes", 0 if not data or
                                             data[0] != protocol.Signal.CANCEL else
                                             len(data) - 1))
        pairs = np.frombuffer(data, dtype=np.uint8)[1:]
        above = pairs > protocol.MAX_VALUE
        if np.any(above):
            n = int(np.argmax(above))
            what = "servo ID" if n % 2 == 0 else "value"
            raise self.bad(f"board {board}: byte {n + 1} is {pairs[n]}, a {what} above "
                           f"{protocol.MAX_VALUE}", (*path, "bytes", n + 1))
        return Stream(board, baud, times, data)

    def times(self, values: list, board: int, path: tuple) -> np.ndarray:
        bad = next((n for n, t in enumerate(values) if isinstance(t, bool)
                    or not isinstance(t, int | float)), None)
        if bad is None:
            try:
                times = np.asarray(values, dtype=float)
            except OverflowError:  # an integer too large for a float
                times = np.full(len(values), np.inf)
            finite = np.isfinite(times)
            if np.all(finite):
                return times
            bad = int(np.argmin(finite))
        raise self.bad(f"board {board}: send time {bad + 1} is not a finite number of "
                       f"seconds", (*path, bad))

    def bytes(self, values: list, board: int, path: tuple) -> bytes:
        bad = next((n for n, b in enumerate(values) if not _whole(b) or not 0 <= b <= 255),
                   None)
        if bad is not None:
            raise self.bad(f"board {board}: byte {bad + 1} is not a whole number in 0..255",
                           (*path, bad))
        return bytes(values)

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


class _NotANumber(ValueError):
    pass


def check_profile(c: Compiled, profile: Profile) -> None:
    """Raise GestError unless ``profile`` can play ``c``: each stream's board is a board
    of the profile, its servo IDs are that board's servos', and its baud is no faster
    than the board's link (bytes timed for a faster link would pile up). Errors point
    at the board in the profile."""
    boards = {b.id: b for b in profile.boards}
    hint = f"compile it for this profile: gestc compile GESTURE --profile {profile.name}"
    errors = []
    for s in c.streams:
        board = boards.get(s.board)
        if board is None:
            errors.append(Diagnostic(
                "error", f"'{c.gesture}' has a stream for board {s.board}, and profile "
                f"'{profile.name}' has no board {s.board} (its boards: "
                f"{', '.join(str(b) for b in boards)})", _board_pos(profile, None), hint))
            continue
        ids = {profile.servos[profile.index(n)].id for n in board.servos}
        foreign = sorted(set(s.data[1::2]) - ids)
        if foreign:
            errors.append(Diagnostic(
                "error", f"'{c.gesture}' commands servo ID{'s' if len(foreign) > 1 else ''} "
                f"{', '.join(map(str, foreign))} on board {s.board}, which profile "
                f"'{profile.name}' does not give that board", _board_pos(profile, board), hint))
        if s.baud > board.baud:
            errors.append(Diagnostic(
                "error", f"'{c.gesture}' is timed for board {s.board} at {s.baud} baud, and "
                f"profile '{profile.name}' runs that board at {board.baud}",
                _board_pos(profile, board), "compile it again for the board's baud"))
    if errors:
        raise GestError(errors)


def _board_pos(profile: Profile, board: Board | None) -> Pos:
    """Where ``board`` (or the first board) is in the profile's file."""
    board = board or (profile.boards[0] if profile.boards else None)
    return (board.pos if board is not None and board.pos is not None
            else Pos(profile.path or "<profile>", 1, 1))


_JSON_TOKEN = re.compile(r'"(?:[^"\\]|\\.)*"|[{}\[\]:,]|[^\s{}\[\]:,"]+')


def _locate(text: str, path: tuple) -> tuple[int, int, int]:
    """(line, column, width) of ``path`` (object keys and list indices) in a JSON text:
    a key's name, a list element's value, or the deepest part of the path there is. A
    scan of the tokens, made only for an error (json.loads keeps no positions)."""
    at, width, found = 0, 1, 0
    keys: list = []  # per open container: its current key or index
    kinds: list[str] = []
    expect_key = False
    for m in _JSON_TOKEN.finditer(text):
        tok = m.group()
        if tok == ":":
            continue
        if tok == ",":
            if kinds and kinds[-1] == "[":
                keys[-1] += 1
            else:
                expect_key = True
            continue
        if tok in ("}", "]"):
            if kinds:
                kinds.pop()
                keys.pop()
            expect_key = False
            continue
        if expect_key:
            keys[-1] = tok[1:-1]
            expect_key = False
        depth = len(keys)
        if depth > found and tuple(keys) == path[:depth]:
            at, width, found = m.start(), len(tok), depth
            if depth == len(path):
                break
        if tok in ("{", "["):
            kinds.append(tok)
            keys.append(0 if tok == "[" else None)
            expect_key = tok == "{"
    line, column, _ = _offset_position(text, at)
    return line, column, max(1, min(width, 40))


def _offset_position(text: str, offset: int) -> tuple[int, int, int]:
    line = text.count("\n", 0, offset) + 1
    return line, offset - (text.rfind("\n", 0, offset) + 1) + 1, 1


def _too_deep(text: str) -> int:
    """The offset where arrays and objects first nest deeper than JSON_DEPTH."""
    depth = 0
    for m in _JSON_TOKEN.finditer(text):
        tok = m.group()
        if tok in "{[":
            depth += 1
            if depth > JSON_DEPTH:
                return m.start()
        elif tok in "}]":
            depth -= 1
    return 0


def _whole(value: object) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def _shown(value: object) -> str:
    text = json.dumps(value) if not isinstance(value, float) or math.isfinite(value) \
        else repr(value)
    return text if len(text) <= 40 else text[:37] + "..."


def to_timed(stream: Stream) -> str:
    """One line per byte: seconds from the stream's start, then the byte."""
    return "".join(f"{t:.6f} {b}\n" for t, b in zip(stream.times.tolist(), stream.data,
                                                      strict=True))
