"""Blender Servo Animation's files (its add-on 2.x, its Arduino library 2.x), written and
read (pure).

- JSON (the add-on's ``json_export.py``): ``description``, ``fps``, ``frames``,
  ``seconds`` (frames / fps, rounded), ``bones`` (the first frame's count), ``file``,
  ``scene``, ``positions``: a dict a frame, the servo's ID as text to its position; a
  position that did not change since the frame before is left out (the add-on's
  default).
- Commands (``base_export.py``): ``<``, the servo's ID, the position big-endian in two
  bytes, ``>``; a line feed ends each frame. The Arduino header holds them in
  ``ANIMATION_DATA`` (PROGMEM), with ``FPS``, ``FRAMES`` and ``LENGTH``.

The library reads commands a byte at a time (``src/Command.cpp``, ``ServoManager``): a
``<`` anywhere starts a command again, a line feed anywhere ends the frame. A command
whose ID or position holds either byte is misread, so the writer moves such a position
by one unit (a microsecond, a tenth of a degree) and refuses such an ID; ``play`` reads
bytes as the library does, so a test sees what the library would do.
"""

from __future__ import annotations

import json
import re
from collections.abc import Iterable, Sequence

import numpy as np

from ..errors import Diagnostic, GestError
from .frames import Frames

START, END, LINE = 0x3C, 0x3E, 0x0A  #: '<', '>', the line feed
DESCRIPTION = "Blender Servo Animation Positions"
MISREAD = (START, LINE)  #: bytes the library takes as markers wherever they are

Positions = list[dict[int, int]]  #: a frame each: servo ID -> position (changes only)


def positions(frames: Frames, units: np.ndarray, skip_unchanged: bool = True,
              safe: bool = False) -> Positions:
    """``units`` ([frame][servo], whole numbers) as a dict a frame keyed by each servo's
    place; unchanged positions left out. ``safe``: no position holds a byte the library
    misreads (``MISREAD``)."""
    places = frames.places
    if safe:
        unsafe = [f"{s.name} (ID {p})" for s, p in zip(frames.servos, places, strict=True)
                  if p in MISREAD]
        if unsafe:
            raise GestError(Diagnostic(
                "error", "Blender Servo Animation's library reads servo ID 10 as a line "
                f"feed and 60 as a '<': {', '.join(unsafe)} cannot be sent in its commands",
                hint="use its JSON (--format bsa-json), or wire the servo to another pin "
                "or channel"))
    out: Positions = []
    last: dict[int, int] = {}
    for row in units.tolist():
        frame = {}
        for p, value in zip(places, row, strict=True):
            value = _safe(value) if safe else value
            if not skip_unchanged or last.get(p) != value:
                frame[p] = last[p] = value
        out.append(frame)
    return out


def _safe(value: int) -> int:
    """``value``, or the next one up if its low byte is a marker; a high byte that is
    one cannot be moved by a unit, so it is an error."""
    if not 0 <= value <= 0xFFFF or (value >> 8) in MISREAD:
        raise GestError(Diagnostic(
            "error", f"position {value} cannot be sent in Blender Servo Animation's "
            "commands (its library reads its high byte as a marker)",
            hint="export in another unit: --units ticks or --units degrees"))
    return value + 1 if (value & 0xFF) in MISREAD else value


def to_json(frames: Frames, found: Positions, file: str, scene: str) -> str:
    """The add-on's JSON (its default indent of 2)."""
    data = {"description": DESCRIPTION, "fps": _fps(frames.fps), "frames": len(found),
            "seconds": round(len(found) / frames.fps), "bones": len(found[0]) if found
            else 0, "file": file, "scene": scene,
            "positions": [{str(k): v for k, v in frame.items()} for frame in found]}
    return json.dumps(data, indent=2)


def commands(found: Positions) -> bytes:
    """The library's commands, a line feed after each frame."""
    out = bytearray()
    for frame in found:
        for servo, position in frame.items():
            out += bytes([START, servo, position >> 8, position & 0xFF, END])
        out.append(LINE)
    return bytes(out)


def to_header(frames: Frames, data: bytes, file: str, scene: str) -> str:
    """The add-on's Arduino header: a comment, ``FPS``, ``FRAMES``, ``LENGTH`` and the
    commands in PROGMEM, twelve bytes a line."""
    count = data.count(LINE)
    rows = "".join("    " + ", ".join(f"{b:#04x}" for b in data[i:i + 12]) + ",\n"
                   for i in range(0, len(data), 12))
    return (f"/*\n  {DESCRIPTION}\n\n  FPS: {_fps(frames.fps)}\n  Frames: {count}\n  "
            f"Seconds: {round(count / frames.fps)}\n  Bones: {len(frames.servos)}\n  "
            f"Scene: {scene}\n  File: {file}\n*/\n\n#include <Arduino.h>\n\n"
            f"const byte FPS = {_fps(frames.fps)};\nconst int FRAMES = {count};\n"
            f"const int LENGTH = {len(data)};\n\n"
            f"const byte PROGMEM ANIMATION_DATA[LENGTH] = {{\n{rows}}};\n")


def _fps(fps: float) -> int:
    return int(round(fps))


class Commands:
    """BSA's library reading bytes (``ServoManager::parseData`` into its ``Command``): a
    ``<`` starts a command again, a command is valid with ``<`` first and ``>`` fifth and
    is acted on after each byte, a servo moved only to a position it is not at. A line
    feed ends a frame (in a file; live mode sends none)."""

    def __init__(self) -> None:
        self.values, self.index = [0] * 5, 0
        self.at: dict[int, int] = {}  #: servo ID -> where the library last moved it

    def feed(self, byte: int) -> tuple[int, int] | None:
        """Read one byte (not a line feed): the (ID, position) a servo moves to, if any."""
        if byte == START:
            self.values, self.index = [0] * 5, 0
        if self.index < 5:
            self.values[self.index] = byte
            self.index += 1
        v = self.values
        if v[0] == START and v[4] == END and self.at.get(v[1]) != (v[3] | v[2] << 8):
            self.at[v[1]] = v[3] | v[2] << 8
            return v[1], self.at[v[1]]
        return None


def play(data: bytes) -> Positions:
    """What the library moves on each frame of ``data`` (``Commands``)."""
    out: Positions = []
    reader = Commands()
    frame: dict[int, int] = {}
    for byte in data:
        if byte == LINE:
            out.append(frame)
            frame = {}
        elif (moved := reader.feed(byte)) is not None:
            frame[moved[0]] = moved[1]
    if frame:
        out.append(frame)
    return out


def read_json(text: str, where: str) -> tuple[float, Positions]:
    """(fps, positions) of the add-on's JSON; anything else is an error naming ``where``."""
    try:
        data = json.loads(text)
    except ValueError as e:
        raise _not(where, f"it is not JSON ({e})") from None
    if not isinstance(data, dict) or not isinstance(data.get("positions"), list):
        raise _not(where, "it has no 'positions' list")
    fps = data.get("fps")
    if isinstance(fps, bool) or not isinstance(fps, (int, float)) or not 0 < fps <= 1000:
        raise _not(where, f"its fps is {fps!r}: a number above 0 (at most 1000)")
    out: Positions = []
    for k, frame in enumerate(data["positions"]):
        if not isinstance(frame, dict):
            raise _not(where, f"frame {k} is {type(frame).__name__}, not an object")
        out.append({_id(key, where, k): _position(v, where, k) for key, v in frame.items()})
    return float(fps), out


def read_header(text: str, where: str) -> tuple[float, Positions]:
    """(fps, positions) of the add-on's Arduino header: its ``FPS`` and the bytes of its
    ``ANIMATION_DATA``, read as the library reads them (``play``)."""
    fps = re.search(r"\bFPS\s*=\s*(\d+)\s*;", text)
    body = re.search(r"ANIMATION_DATA\s*\[[^\]]*\]\s*=\s*\{([^}]*)\}", text)
    if fps is None or body is None:
        raise _not(where, "it has no 'const byte FPS = N;' and ANIMATION_DATA = {...}")
    if not 0 < int(fps.group(1)) <= 255:
        raise _not(where, f"its FPS is {fps.group(1)}: 1 to 255")
    data = bytearray()
    for token in (t.strip() for t in body.group(1).split(",")):
        if token and not re.fullmatch(r"0[xX][0-9a-fA-F]{1,2}|\d{1,3}", token) or \
                token and int(token, 0) > 255:
            raise _not(where, f"ANIMATION_DATA holds {token[:20]!r}, not a byte")
        if token:
            data.append(int(token, 0))
    return float(fps.group(1)), play(bytes(data))


def _id(key: str, where: str, frame: int) -> int:
    if not key.isdigit() or int(key) > 255:
        raise _not(where, f"frame {frame} names servo {key!r}: an ID is 0 to 255")
    return int(key)


def _position(value: object, where: str, frame: int) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value <= 0xFFFF:
        raise _not(where, f"frame {frame} has position {value!r}: a whole number 0..65535")
    return value


def _not(where: str, why: str) -> GestError:
    return GestError(Diagnostic("error", f"{where}: not a Blender Servo Animation file: "
                                f"{why}"))


def changes(found: Iterable[dict[int, int]], fps: float) -> list[tuple[float, int, int]]:
    """(time, ID, position) of every position set, frame k at k / fps."""
    return [(k / fps, servo, p) for k, frame in enumerate(found) for servo, p in frame.items()]


def ids(found: Sequence[dict[int, int]]) -> set[int]:
    """Every servo ID the frames name."""
    return {servo for frame in found for servo in frame}
