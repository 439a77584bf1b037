"""A compiled gesture and its file formats.

``.gestc`` (JSON, versioned) carries each board's bytes with absolute send times,
the board, baud, profile and source hashes, so the player can load it without the
compiler. ``timed`` text is one line per byte, ``<seconds> <byte>``: the contract
for tools. Both are described in docs/compiled-format.md.
"""

from __future__ import annotations

import json
from dataclasses import dataclass

import numpy as np

from .encode import Stream
from .errors import Diagnostic, GestError

FORMAT = "inmoov-dsl-compiled"
VERSION = 1


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


def from_json(text: str, file: str = "<compiled>") -> Compiled:
    """Load a ``.gestc`` file; anything malformed is a GestError naming the file."""

    def bad(why: str) -> GestError:
        return GestError(Diagnostic("error", f"{file}: not a usable compiled gesture: {why}",
                                    hint="compile it again with 'gestc compile'"))

    try:
        doc = json.loads(text)
    except json.JSONDecodeError as exc:
        raise bad(f"invalid JSON ({exc.msg} at line {exc.lineno})") from None
    if not isinstance(doc, dict) or doc.get("format") != FORMAT:
        raise bad("it is not a gestc file")
    if doc.get("version") != VERSION:
        raise bad(f"format version {doc.get('version')!r}, this gestc reads {VERSION}")
    try:
        streams = []
        for s in doc["streams"]:
            times = np.asarray(s["times"], dtype=float)
            data = bytes(s["bytes"])
            if len(times) != len(data):
                raise bad(f"board {s['board']} has {len(times)} times for {len(data)} bytes")
            if len(times) and (np.any(np.diff(times) < 0) or times[0] < 0):
                raise bad(f"board {s['board']}: send times go backwards")
            streams.append(Stream(int(s["board"]), int(s["baud"]), times, data))
        steps = tuple(StepSummary(st["where"], st.get("file"), st.get("line"), st["kind"],
                                  float(st["start"]), float(st["end"]), st.get("asked"),
                                  bool(st.get("stretched", False))) for st in doc["steps"])
        return Compiled(
            gesture=str(doc["gesture"]),
            profile=str(doc["profile"]["name"]),
            profile_sha256=str(doc["profile"]["sha256"]),
            sources=tuple((x["path"], x["sha256"]) for x in doc["sources"]),
            servos=tuple(doc["servos"]),
            start=tuple(int(v) for v in doc["start"]),
            final=tuple(int(v) for v in doc["final"]),
            duration=float(doc["duration"]),
            steps=steps,
            streams=tuple(streams),
        )
    except GestError:
        raise
    except (KeyError, TypeError, ValueError) as exc:
        raise bad(f"missing or malformed field ({exc})") from None


def to_timed(stream: Stream) -> str:
    """One line per byte: seconds from the stream's start, then the byte."""
    return "".join(f"{t:.6f} {b}\n" for t, b in zip(stream.times.tolist(), stream.data,
                                                      strict=True))
