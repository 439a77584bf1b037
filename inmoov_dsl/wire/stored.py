"""Gestures stored in a servo board's flash: the bytes the firmware keeps and reads
(docs/firmware.md, "Gestures stored in the board"), pure.

One blob (``StoredSet.to_bytes``) holds everything: the catalog the board sends when
asked (``PLAY CATALOG``: its gestures' names, numbers, durations, and what starts
them), then per servo the approach's limits, then each gesture: the pose it starts
from and its stream, frame by frame. The firmware reads the blob from ``PROGMEM``; the
virtual board reads the same bytes (``read_blob`` on the ``stored.h`` a build wrote).

A gesture's stream is the compiled stream's pairs, one 20 ms servo frame at a time, in
nibbles (high nibble first): a header of ``header_nibbles(n)`` nibbles whose top bit set
means "no pair for (rest + 1) frames", clear means "this frame: the servos of this
mask", then a nibble per servo of the mask: the change from its last value (1..7:
-7..-1, 8..15: +1..+8), or 0 and two nibbles: the value itself. A pair of frame ``f``
for servo ``j`` of ``n`` arrives ``(f + 1) * 20 ms - (n - 1 - j) * pair_us`` after the
stream starts, as the compiler times it (``encode._fixed_slots``).
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path

from .. import protocol
from ..errors import Diagnostic, GestError

FORMAT = 1  #: the blob's first byte
FRAME_US = 20_000  #: a servo frame, in us
UNIT = 64  #: the approach's positions are in 1/64 of a command degree
NONE = 0xFF  #: no gesture (the boot and idle bytes)
DEFAULT_IDLE_AFTER = 20  #: s of quiet before the idle gesture plays (again)
BOOT_QUIET = 0.25  #: s after power-up that a host byte can still stop the boot gesture
DEBOUNCE = 0.02  #: s a button must read the same before it counts as pressed or not
ESCAPE = 0  #: the nibble before an absolute value


@dataclass(frozen=True)
class StoredGesture:
    """One gesture as the board keeps it."""

    name: str
    start: tuple[int, ...]  #: the pose its stream starts from, one value per servo
    frames: int  #: its duration, in 20 ms frames
    data: bytes  #: its stream (``pack``)


@dataclass(frozen=True)
class StoredSet:
    """What a board's flash holds besides its firmware."""

    gestures: tuple[StoredGesture, ...]
    pair_us: int  #: us one (servo ID, value) pair takes on the board's link
    limits: tuple[tuple[int, int], ...]  #: per servo: speed, acceleration (``approach``)
    boot: int | None = None  #: the gesture played at power-up
    idle: int | None = None  #: the gesture played after ``idle_after`` s of quiet
    idle_after: int = DEFAULT_IDLE_AFTER
    buttons: tuple[tuple[int, int], ...] = ()  #: (Arduino pin, gesture number)

    def number(self, name: str) -> int | None:
        """The number of the gesture called ``name``, or None."""
        return next((k for k, g in enumerate(self.gestures) if g.name == name), None)

    def catalog(self) -> bytes:
        """What the board lists (``Catalog``): counts, triggers, each gesture's
        duration and name."""
        def none(n: int | None) -> int:
            return NONE if n is None else n

        out = bytearray([len(self.gestures), none(self.boot), none(self.idle)])
        out += self.idle_after.to_bytes(2, "little")
        out.append(len(self.buttons))
        for pin, number in self.buttons:
            out += bytes([pin, number])
        for g in self.gestures:
            name = g.name.encode("utf-8")
            out += g.frames.to_bytes(2, "little") + bytes([len(name)]) + name
        return bytes(out)

    def size(self) -> int:
        """The blob's length in bytes (``to_bytes``), however large."""
        n = len(self.limits)
        return (3 + len(self.catalog()) + 3 + 4 * n +
                sum(2 + 2 + n + 2 + len(g.data) for g in self.gestures))

    def to_bytes(self) -> bytes:
        """The blob: FORMAT, the catalog's length (2 bytes) and the catalog; the number
        of servos, ``pair_us`` (2), each servo's limits (2 + 2); where each gesture is
        (2 each, from the blob's start); each gesture: its frames (2), its start pose,
        its stream's length (2) and the stream. Little-endian."""
        catalog = self.catalog()
        n = len(self.limits)
        head = bytearray([FORMAT, *len(catalog).to_bytes(2, "little"), *catalog, n])
        head += self.pair_us.to_bytes(2, "little")
        for speed, accel in self.limits:
            head += speed.to_bytes(2, "little") + accel.to_bytes(2, "little")
        records = [g.frames.to_bytes(2, "little") + bytes(g.start) +
                   len(g.data).to_bytes(2, "little") + g.data for g in self.gestures]
        at = len(head) + 2 * len(records)
        for record in records:
            head += at.to_bytes(2, "little")
            at += len(record)
        return bytes(head) + b"".join(records)


def _u16(data: bytes, at: int) -> int:
    return int.from_bytes(data[at:at + 2], "little")


@dataclass(frozen=True)
class Catalog:
    """What a board holds, as it lists it: each gesture's name and duration (s), and
    what starts one besides the host (a gesture number, or None)."""

    names: tuple[str, ...]
    durations: tuple[float, ...]
    boot: int | None
    idle: int | None
    idle_after: int
    buttons: tuple[tuple[int, int], ...]

    @classmethod
    def parse(cls, data: bytes) -> Catalog:
        """Read a catalog (``StoredSet.catalog``); ValueError if it is not one."""
        count, boot, idle = data[0], data[1], data[2]
        idle_after, buttons = _u16(data, 3), data[5]
        pins = tuple((data[6 + 2 * k], data[7 + 2 * k]) for k in range(buttons))
        at, names, durations = 6 + 2 * buttons, [], []
        for _ in range(count):
            frames, size = _u16(data, at), data[at + 2]
            names.append(data[at + 3:at + 3 + size].decode("utf-8"))
            durations.append(frames * FRAME_US / 1e6)
            at += 3 + size
        if at != len(data) or len(names) != count:
            raise ValueError("not a catalog")
        return cls(tuple(names), tuple(durations), None if boot == NONE else boot,
                   None if idle == NONE else idle, idle_after, pins)

    def triggers(self, number: int) -> list[str]:
        """What starts gesture ``number`` besides the host: ``power-up``, ``button
        D8``, ``idle 20 s``."""
        out = ["power-up"] if self.boot == number else []
        out += [f"button {pin_name(pin)}" for pin, g in self.buttons if g == number]
        return out + ([f"idle {self.idle_after} s"] if self.idle == number else [])


def catalog_reply(board_id: int, blob: bytes) -> bytes:
    """The board's answer to ``PLAY CATALOG``: START PLAY BOARD_ID, the blob's first
    bytes (FORMAT, the catalog's length, the catalog), END."""
    size = 3 + _u16(blob, 1)
    return bytes([protocol.Signal.START, protocol.PLAY, board_id, *blob[:size],
                  protocol.Signal.END])


def find_catalog(data: bytes, board_id: int) -> Catalog | None:
    """The catalog reply of board ``board_id`` in bytes from it (WAIT bytes and other
    replies around it are skipped), or None if no whole one is there."""
    head = bytes([protocol.Signal.START, protocol.PLAY, board_id, FORMAT])
    at = data.find(head)
    while at >= 0:
        size = _u16(data, at + 4) if at + 6 <= len(data) else -1
        end = at + 6 + size
        if size >= 0 and end < len(data) and data[end] == protocol.Signal.END:
            try:
                return Catalog.parse(data[at + 6:end])
            except (ValueError, IndexError, UnicodeDecodeError):
                pass
        at = data.find(head, at + 1)
    return None


def pin_name(pin: int, analog: int = 14) -> str:
    """An Arduino's pin as printed on the board: D8, A0 (``analog``: A0's number, 14 on
    an Uno or a Nano, 54 on a Mega)."""
    count = 16 if analog > 14 else 8
    return f"A{pin - analog}" if analog <= pin < analog + count else f"D{pin}"


def header_nibbles(servos: int) -> int:
    """Nibbles of a frame's header on a board of ``servos`` servos: a flag bit and a bit
    per servo."""
    return (servos + 4) // 4


def pack(pairs: Iterable[tuple[int, int, int]], start: Iterable[int]) -> bytes:
    """A gesture's stream: ``pairs`` (frame, servo index, value), in time order with at
    most one pair per servo and frame, from the ``start`` pose."""
    held = list(start)
    width = header_nibbles(len(held))
    flag = 1 << (4 * width - 1)
    frames: dict[int, dict[int, int]] = {}
    for frame, index, value in pairs:
        if index in frames.setdefault(frame, {}):
            raise ValueError(f"two values for servo {index} in frame {frame}")
        frames[frame][index] = value
    nibbles: list[int] = []

    def number(value: int) -> None:
        nibbles.extend((value >> 4 * k) & 15 for k in reversed(range(width)))

    at = 0
    for frame in sorted(frames):
        while frame > at:  # frames without a pair
            skip = min(frame - at, flag)
            number(flag | (skip - 1))
            at += skip
        number(sum(1 << j for j in frames[frame]))
        for j, value in sorted(frames[frame].items()):
            change = value - held[j]
            if -7 <= change <= -1 or 1 <= change <= 8:
                nibbles.append(change + 8 if change < 0 else change + 7)
            else:
                nibbles += [ESCAPE, value >> 4, value & 15]
            held[j] = value
        at = frame + 1
    nibbles += [0] * (len(nibbles) % 2)
    return bytes(hi << 4 | lo for hi, lo in zip(nibbles[::2], nibbles[1::2], strict=True))


def unpack(data: bytes, start: Iterable[int]) -> list[tuple[int, int, int]]:
    """The pairs (frame, servo index, value) of a stream ``pack`` made."""
    held = list(start)
    width = header_nibbles(len(held))
    flag = 1 << (4 * width - 1)
    nibbles = [n for b in data for n in (b >> 4, b & 15)]
    at, frame, out = 0, 0, []
    while len(nibbles) - at >= width:
        head = 0
        for n in nibbles[at:at + width]:
            head = head << 4 | n
        at += width
        if head & flag:
            frame += (head & (flag - 1)) + 1
            continue
        for j in (j for j in range(len(held)) if head >> j & 1):
            code = nibbles[at]
            if code == ESCAPE:
                held[j] = nibbles[at + 1] << 4 | nibbles[at + 2]
                at += 3
            else:
                held[j] += code - 8 if code < 8 else code - 7
                at += 1
            out.append((frame, j, held[j]))
        frame += 1
    return out


def arrival_us(frame: int, index: int, servos: int, pair_us: int) -> int:
    """When the pair of frame ``frame`` for servo ``index`` of ``servos`` plays: us
    after the stream starts (the compiler's fixed slots, packed at the frame's end)."""
    return (frame + 1) * FRAME_US - (servos - 1 - index) * pair_us


def read_blob(path: str | Path) -> bytes:
    """The blob in a ``stored.h`` a build wrote (or in the sketch folder that has
    one): the very bytes the image keeps in flash. A GestError if there is none."""
    path = Path(path)
    if path.is_dir():
        path = path / "stored.h"
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise GestError(Diagnostic("error", f"cannot read the stored gestures in {path}: "
                                   f"{exc.strerror if isinstance(exc, OSError) else exc}",
                                   hint="give the folder of a sketch built with --store "
                                   "(gestc firmware PROFILE --store ... -o DIR)")) from None
    body = re.search(r"INMOOV_STORED\[\] PROGMEM = \{(.*?)\};", text, re.S)
    if body is None:
        raise GestError(Diagnostic("error", f"{path} holds no stored gestures",
                                   hint="gestc firmware PROFILE --store GESTURE,... writes "
                                   "one"))
    return bytes(int(x, 16) for x in re.findall(r"0x([0-9a-f]{2})", body[1]))


def read_set(blob: bytes) -> StoredSet:
    """The StoredSet of a blob (``StoredSet.to_bytes``); ValueError if it is not one."""
    if not blob or blob[0] != FORMAT:
        raise ValueError("not a stored-gesture blob of this version")
    size = _u16(blob, 1)
    catalog = Catalog.parse(blob[3:3 + size])
    at = 3 + size
    n, pair_us = blob[at], _u16(blob, at + 1)
    limits = tuple((_u16(blob, at + 3 + 4 * k), _u16(blob, at + 5 + 4 * k))
                   for k in range(n))
    table = at + 3 + 4 * n
    gestures = []
    for k, name in enumerate(catalog.names):
        record = _u16(blob, table + 2 * k)
        frames, start = _u16(blob, record), tuple(blob[record + 2:record + 2 + n])
        length = _u16(blob, record + 2 + n)
        data = blob[record + 4 + n:record + 4 + n + length]
        gestures.append(StoredGesture(name, start, frames, bytes(data)))
    return StoredSet(tuple(gestures), pair_us, limits, catalog.boot, catalog.idle,
                     catalog.idle_after, catalog.buttons)
