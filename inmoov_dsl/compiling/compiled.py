"""What the compiler makes: a board's timed byte ``Stream``, a ``Compiled`` gesture,
and the writing of its file formats.

``.gestc`` (JSON, versioned) carries each board's bytes with absolute send times,
the board, baud, profile and source hashes, so the player can load it without the
compiler. ``timed`` text is one line per byte, ``<seconds> <byte>``: the contract
for tools. Both are described in docs/compiled-format.md; ``compiled_reader`` reads a
``.gestc`` back, after the checks it passes.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import protocol
from ..errors import Diagnostic, GestError

FORMAT = "inmoov-dsl-compiled"  #: a .gestc document's "format"
VERSION = 1  #: and its "version"


@dataclass(frozen=True)
class Stream:
    """The bytes for one board and the time (s from the stream's start) each goes out,
    in the protocol of the board's ``kind`` (``boards/``)."""

    board: int
    baud: int
    times: np.ndarray
    data: bytes
    kind: str = "rig"

    @property
    def byte_time(self) -> float:
        """Seconds one byte takes on this board's link (a rig's: 8N1 at its baud)."""
        return protocol.byte_time(self.baud)

    @property
    def idle(self) -> bool:
        """Does it move none of its board's servos: a rig's, the CANCEL every stream
        starts with and no (servo ID, value) pair; another kind's, no bytes?"""
        return not protocol.pairs(self.data) if self.kind == "rig" else not self.data

    @property
    def servo_ids(self) -> set[int]:
        """The servo IDs a rig stream's pairs command (another kind's: none)."""
        return {sid for sid, _ in protocol.pairs(self.data)} if self.kind == "rig" else set()




@dataclass(frozen=True)
class StepSummary:
    """One step of the plan, for ``gestc show``: where it is in the source, its kind
    ("move" or "hold") and times (s), the duration asked for and whether it was
    stretched to keep the servos' limits."""

    where: str
    file: str | None
    line: int | None
    kind: str
    start: float
    end: float
    asked: float | None
    stretched: bool


@dataclass(frozen=True)
class Cue:
    """A sound the gesture plays (a ``say``): when (s from the gesture's start), what the
    step said, where the sound comes from (the WAV file's path, or the voice that speaks
    the text: name, words per minute, pitch), its SHA-256 and its length (s).
    ``sound``: the sound itself, when the compiler made it (a file read back has none)."""

    start: float
    said: str
    file: str | None
    voice: tuple[str, int, int] | None
    sha256: str
    duration: float
    sound: Any = field(default=None, compare=False, repr=False)


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
    sounds: tuple[Cue, ...] = ()  #: what ``say`` steps play, in time order

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
    """The ``.gestc`` document of ``c``; times rounded to 1e-9 s. A stream for a board of
    another kind than the rig says its ``kind``."""
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
            {"board": s.board, "baud": s.baud, **({"kind": s.kind} if s.kind != "rig" else {}),
             "times": [round(t, 9) for t in s.times.tolist()], "bytes": list(s.data)}
            for s in c.streams
        ],
    }
    if c.sounds:
        doc["sounds"] = [{"start": round(q.start, 9), "say": q.said, "file": q.file,
                          "voice": list(q.voice) if q.voice else None, "sha256": q.sha256,
                          "duration": round(q.duration, 9)} for q in c.sounds]
    return json.dumps(doc, indent=1) + "\n"


def to_timed(stream: Stream) -> str:
    """One line per byte: seconds from the stream's start, then the byte."""
    return "".join(f"{t:.6f} {b}\n" for t, b in zip(stream.times.tolist(), stream.data,
                                                      strict=True))
