"""Reading a ``.gestc`` file back (``read_compiled``, ``from_json``), after the checks
its document passes.

A stream is accepted only if it keeps the rules a board relies on (docs/compiler.md,
"Compiled files"); anything else is a GestError at its place in the file: the line and
column of the field or list element it is about.
"""

from __future__ import annotations

import os
import re

import numpy as np

from .. import boards, protocol
from ..errors import Diagnostic, GestError, counted, decode_utf8
from ..resources import read_regular
from .compiled import FORMAT, VERSION, Compiled, Cue, StepSummary, Stream
from .jsonfields import Fields, shown, whole
from .plan import MAX_GESTURE_DURATION

MAX_COMPILED = 100_000_000  #: bytes (characters) of a .gestc; a larger one is not read
_ROUNDING = 2e-9  #: s; to_json rounds times to 1e-9 s, so a gap may shrink by this
_SLACK = 1e-6  #: s; steps and bytes may end this much after the rounded duration

class CompiledReader(Fields):
    """Checks one .gestc document against the format and the rules a board relies on."""

    WHAT = "not a usable compiled gesture"
    HINT = "compile it again with 'gestc compile'"

    def read(self) -> dict[str, object]:
        """The keyword arguments of ``compiled.Compiled``, checked; its ``steps`` are
        those of ``compiled.StepSummary``."""
        doc = self.parse()
        if not isinstance(doc, dict) or doc.get("format") != FORMAT:
            raise self.bad("it is not a gestc file", ("format",))
        version = doc.get("version")
        if not whole(version) or version != VERSION:  # (not true, not 1.0)
            raise self.bad(f"format version {shown(doc.get('version'))}, this gestc reads "
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
            raise self.bad(f"'servos' must be the names of 1 to {protocol.MAX_SERVO_ID + 1} "
                           "servos, each once", ("servos",))
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
            sounds=tuple(_cue(self, q, k, duration) for k, q in enumerate(
                self.field(doc, "sounds", list, ()) if "sounds" in doc else ())),
        )

    def pose(self, doc: dict, key: str, count: int) -> tuple[int, ...]:
        """``doc[key]``: one value 0..180 for each of ``count`` servos."""
        values = self.field(doc, key, list, ())
        if len(values) != count or not all(whole(v) and 0 <= v <= protocol.MAX_VALUE
                                           for v in values):
            raise self.bad(f"'{key}' must be {count} whole numbers in 0..{protocol.MAX_VALUE}, "
                           "one per servo", (key,))
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
        if kind not in ("move", "hold", "say"):
            raise self.bad(f"a step's kind is 'move', 'hold' or 'say', got {shown(kind)}",
                           (*path, "kind"))
        file, line = st.get("file"), st.get("line")
        if file is not None and not isinstance(file, str):
            raise self.bad(f"'file' must be a string or null, got {shown(file)}",
                           (*path, "file"))
        if line is not None and not (whole(line) and line >= 1):
            raise self.bad(f"'line' must be a line number or null, got {shown(line)}",
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
        low, high = protocol.FIRST_BOARD_ID, protocol.LAST_BOARD_ID
        if not whole(board) or not low <= board <= high:
            raise self.bad(f"a board ID is a whole number in {low}..{high}, got "
                           f"{shown(board)}", (*path, "board"))
        baud = s.get("baud")
        if not whole(baud) or not protocol.usable_baud(baud):
            raise self.bad(f"board {board}: a baud that carries a servo command per 20 ms "
                           f"frame is a whole number up to {protocol.MAX_BAUD:,}, got "
                           f"{shown(baud)}",
                           (*path, "baud"))
        times_list = self.field(s, "times", list, path)
        data_list = self.field(s, "bytes", list, path)
        if len(times_list) != len(data_list):
            raise self.bad(f"board {board} has {counted(len(times_list), 'time')} for "
                           f"{counted(len(data_list), 'byte')}", (*path, "times"))
        kind = s.get("kind", "rig")
        if kind not in boards.KINDS:
            raise self.bad(f"board {board}: 'kind' must be one of {', '.join(boards.KINDS)}, got "
                           f"{shown(kind)}", (*path, "kind"))
        times = self.times(times_list, board, baud, (*path, "times"), kind == "rig")
        data = self.bytes(data_list, board, (*path, "bytes"), kind)
        return Stream(board, baud, times, data, kind)

    def times(self, values: list, board: int, baud: int, path: tuple, rig: bool = True
              ) -> np.ndarray:
        """Send times: finite, in order, at least a byte-time apart, and a rig's from 0
        (its CANCEL; another kind's first command goes when it is due)."""
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
            if (times[0] != 0) if rig else (times[0] < 0):
                raise self.bad(f"board {board}: the first byte goes at {times[0]:g} s, not 0",
                               (*path, 0))
            tau = protocol.byte_time(baud)
            if np.any(steps < tau - _ROUNDING):
                raise self.bad(f"board {board}: two bytes closer than a byte-time "
                               f"({tau * 1000:.3f} ms at {baud} baud)",
                               (*path, int(np.argmax(steps < tau - _ROUNDING)) + 1))
        return times

    def bytes(self, values: list, board: int, path: tuple, kind: str = "rig") -> bytes:
        """The bytes: a rig's CANCEL, then whole (servo ID, value) pairs, each 0..180;
        another kind's, whole commands of its own (``boards.fault``)."""
        bad = next((n for n, b in enumerate(values) if not whole(b) or not 0 <= b <= 255),
                   None)
        if bad is not None:
            raise self.bad(f"board {board}: byte {bad + 1} is not a whole number in 0..255",
                           (*path, bad))
        data = bytes(values)
        if kind != "rig":
            if (wrong := boards.fault(kind, data)) is not None:
                raise self.bad(f"board {board} ({kind}): {wrong}", path)
            return data
        fault = protocol.frame_fault(data)
        if fault is None:
            return data
        n, what = fault
        if what in ("CANCEL", "pair"):
            raise self.bad(f"board {board}: a stream is CANCEL ({protocol.Signal.CANCEL:d}) "
                           f"then whole (servo ID, value) pairs", (*path, n))
        raise self.bad(f"board {board}: byte {n} is {data[n]}, a {what} above "
                       f"{protocol.MAX_VALUE}", (*path, n))

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
            if len(s.times) and s.times[-1] > duration + 2 * protocol.SERVO_FRAME + _SLACK:
                raise self.bad(f"board {s.board}: a byte goes at {s.times[-1]:g} s, after "
                               f"the gesture's {duration:g} s",
                               ("streams", k, "times", len(s.times) - 1))
            for sid in s.servo_ids:
                if owner.setdefault(sid, s.board) != s.board:
                    raise self.bad(f"servo ID {sid} is on board {owner[sid]} and on board "
                                   f"{s.board}", ("streams", k, "bytes"))
        if len(owner) > servos:
            raise self.bad(f"the streams command {len(owner)} servo IDs, more than the "
                           f"{servos} servos of the gesture", ("streams",))


def _cue(self: CompiledReader, q: object, k: int, duration: float) -> Cue:
    """A sound of ``sounds``: when it starts (within the gesture), what was said,
    its WAV file or the voice that speaks it, its SHA-256 and length."""
    at = ("sounds", k)
    if not isinstance(q, dict):
        raise self.bad("a sound must be an object", at)
    start, length = self.number(q, "start", at), self.number(q, "duration", at)
    if not 0 <= start <= duration + _SLACK or not 0 < length <= duration + _SLACK:
        raise self.bad("a sound must start and end within the gesture", at)
    said, digest = self.field(q, "say", str, at), self.field(q, "sha256", str, at)
    file, voice = q.get("file"), q.get("voice")
    if not re.fullmatch(r"[0-9a-f]{64}", digest):
        raise self.bad("'sha256' must be 64 hexadecimal digits", (*at, "sha256"))
    if (file is None) == (voice is None) or file is not None and not isinstance(file, str) \
            or voice is not None and not (isinstance(voice, list) and len(voice) == 3
                                          and isinstance(voice[0], str)
                                          and whole(voice[1]) and whole(voice[2])):
        raise self.bad("a sound has a 'file' (a path) or a 'voice' ([name, words per "
                       "minute, pitch])", at)
    return Cue(start, said, file, tuple(voice) if voice else None, digest, length)


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
        raise CompiledReader("", file).bad(f"the file is larger than {MAX_COMPILED:,} "
                                           f"bytes: it is not read")
    if not isinstance(text, str):
        text = decode_utf8(bytes(text), file)
    fields = CompiledReader(text, file).read()
    steps = tuple(StepSummary(**step) for step in fields.pop("steps"))
    return Compiled(**fields, steps=steps)
