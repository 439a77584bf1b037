"""Gestures to store in a board's flash (``gestc firmware/upload --store``): each one
compiled for the board's profile from its rest pose, made into the stored form
(``wire.stored``), checked to fit beside the firmware before anything is built, and
written as the sketch's ``stored.h``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

from .. import protocol
from ..boards import arduino
from ..compiling.compiled import Compiled
from ..errors import Diagnostic, GestError
from ..hardware import Board, Profile
from ..wire.stored import (
    DEFAULT_IDLE_AFTER,
    FRAME_US,
    UNIT,
    StoredGesture,
    StoredSet,
    pack,
    pin_name,
)

FLASH_MAX = 30_720  #: bytes: an old-bootloader Nano's room for a sketch (Makefile's FLASH_MAX)
#: bytes of flash the servo firmware takes with the stored-gesture player and no
#: gesture (measured: tests/test_stored.py keeps the real build below it)
FIRMWARE_FLASH = 7_300
FRAME = FRAME_US / 1e6
MAX_FRAMES = 0xFFFF  #: a stored gesture's duration in frames (2 bytes): 21 minutes
STORED_SERVOS = 28  #: a frame's header: a flag and a bit per servo, in 32 bits
LED_PIN = 13  #: the Nano's LED pulls a button's pin low
ANALOG_ONLY = (20, 21)  #: A6, A7 on a Nano: no digital input


@dataclass(frozen=True)
class Request:
    """What ``--store``, ``--on-boot``, ``--button`` and ``--idle`` ask, by gesture name:
    the gestures in the order they are numbered (the triggers' gestures too)."""

    names: tuple[str, ...]
    boot: str | None = None
    idle: str | None = None
    idle_after: int = DEFAULT_IDLE_AFTER
    buttons: tuple[tuple[int, str], ...] = field(default=())  #: (pin, gesture)
    #: (pin, as the user wrote it: D8, A0, 8) of the buttons, for what is said of them
    written: tuple[tuple[int, str], ...] = field(default=())

    @property
    def every(self) -> tuple[str, ...]:
        """Every gesture to store, numbered in this order: those of ``--store``, then
        those only a trigger names."""
        more = [self.boot, self.idle, *(g for _, g in self.buttons)]
        out = list(dict.fromkeys(self.names))
        out += [g for g in dict.fromkeys(more) if g is not None and g not in out]
        return tuple(out)


def parse_pin(text: str, analog: int = 14) -> int:
    """An Arduino pin as a user writes it (``8``, ``D8``, ``A0``): its number."""
    word = text.strip().upper()
    try:
        if word.startswith("A"):
            return analog + int(word[1:])
        return int(word[1:] if word.startswith("D") else word)
    except ValueError:
        raise GestError(Diagnostic("error", f"--button {text}: not a pin", hint="--button "
                                   "8=wave (pin D8), or A0=wave")) from None


def check_pins(buttons: Sequence[tuple[int, str]], profile: Profile, board: Board,
               written: Sequence[tuple[int, str]] = ()) -> None:
    """Each button's pin is free on ``board``: not the serial port's, a servo's, the
    LED's or an analog-only one, and not two buttons'; an error names a pin as
    ``written`` says the user wrote it."""
    servos = {profile.servos[profile.index(n)].pin: n for n in board.servos}
    _, _, count, analog = arduino.of(board.options)
    nano = analog == 14  # a pin of an Uno is one of a Nano's
    seen: set[int] = set()
    names = dict(written)
    for pin, gesture in buttons:
        where = f"--button {names.get(pin, pin_name(pin, analog))}={gesture}"
        problem = ("it is the serial port's (D0, D1)" if pin in (0, 1) else
                   f"servo {servos[pin]} is on it" if pin in servos else
                   "the board's LED holds it low on a Nano" if pin == LED_PIN and nano else
                   "it reads no digital input on a Nano" if pin in ANALOG_ONLY and nano else
                   "there is no such pin" if not 0 <= pin < count else
                   "another button is on it" if pin in seen else None)
        if problem:
            free = [pin_name(p, analog) for p in range(2, count)
                    if p not in servos and (p != LED_PIN or not nano)]
            raise GestError(Diagnostic("error", f"{where}: {problem}",
                                       hint=f"free pins on board {board.id}: "
                                       f"{', '.join(free)}"))
        seen.add(pin)


def limits(profile: Profile, board: Board) -> tuple[tuple[int, int], ...]:
    """Each servo's approach limits: whole command degrees per frame (at least one)
    within its max_velocity, and its max_acceleration per frame per frame, in 1/UNIT
    of a degree."""
    out = []
    for name in board.servos:
        servo = profile.servos[profile.index(name)]
        top = min(max(1, math.floor(servo.max_velocity * FRAME)), protocol.MAX_VALUE)
        accel = math.floor(servo.max_acceleration * FRAME * FRAME * UNIT)
        out.append((top * UNIT, min(max(1, accel), protocol.MAX_VALUE * UNIT)))
    return tuple(out)


def stored_gesture(compiled: Compiled, profile: Profile, board: Board) -> StoredGesture:
    """``compiled``'s stream for ``board`` in the stored form: each pair in the servo
    frame it arrives in (an error if a gesture moves another board's servos)."""
    others = [s.board for s in compiled.streams if s.board != board.id and not s.idle]
    if others:
        raise GestError(Diagnostic("error", f"'{compiled.gesture}' moves servos of board "
                                   f"{others[0]}: a stored gesture plays on one board "
                                   f"({board.id})", hint="store it in the board it moves"))
    stream = compiled.stream(board.id)
    ids = [profile.servos[profile.index(n)].id for n in board.servos]
    n, tau = len(ids), stream.byte_time
    pair = protocol.PAIR_BYTES * tau
    pairs = []
    for t, sid, value in protocol.timed_pairs(stream.times, stream.data):
        arrival, j = t + tau, ids.index(sid)
        frame = round((arrival + (n - 1 - j) * pair) / FRAME) - 1
        if abs((frame + 1) * FRAME - (n - 1 - j) * pair - arrival) > 1e-6:
            frame = math.ceil(arrival / FRAME - 1e-9) - 1  # not in its own slot
        pairs.append((frame, j, value))
    start = tuple(compiled.start[profile.index(n)] for n in board.servos)
    last = max((f for f, _, _ in pairs), default=-1)
    frames = max(math.ceil(compiled.duration / FRAME - 1e-9), last + 1)
    if frames > MAX_FRAMES:
        raise GestError(Diagnostic("error", f"'{compiled.gesture}' lasts "
                                   f"{compiled.duration:,.0f} s: a stored gesture lasts at "
                                   f"most {MAX_FRAMES * FRAME:,.0f} s",
                                   hint="store its parts as gestures of their own"))
    return StoredGesture(compiled.gesture, start, frames, pack(pairs, start))


def stored_set(gestures: Sequence[StoredGesture], request: Request, profile: Profile,
               board: Board) -> StoredSet:
    """The set ``request`` asks for, from its gestures (``stored_gesture``, in the
    order of ``request.every``); it must fit beside the firmware (``check_fit``)."""
    if len(gestures) > protocol.MAX_STORED:
        raise GestError(Diagnostic("error", f"{len(gestures)} gestures to store: a board "
                                   f"holds at most {protocol.MAX_STORED}"))
    if len(board.servos) > STORED_SERVOS:
        raise GestError(Diagnostic("error", f"board {board.id} has {len(board.servos)} "
                                   f"servos: a board with stored gestures has at most "
                                   f"{STORED_SERVOS} (a frame's servos are a 32-bit mask)"))
    check_pins(request.buttons, profile, board, request.written)
    number = {g.name: k for k, g in enumerate(gestures)}
    pair_us = round(protocol.PAIR_BYTES * protocol.byte_time(board.baud) * 1e6)
    flash = StoredSet(tuple(gestures), pair_us, limits(profile, board),
                      number.get(request.boot), number.get(request.idle), request.idle_after,
                      tuple((pin, number[g]) for pin, g in request.buttons))
    check_fit(flash, *room(board))
    return flash


#: a Mega's stored gestures: what pgm_read_byte reaches (the first 64 KB of flash, the
#: interrupt vectors before them)
MEGA_ROOM = 65_536 - 512


def room(board: Board) -> tuple[int, str]:
    """The flash ``board`` has for stored gestures, and what leaves it so."""
    if arduino.mcu(board.options) == "atmega2560":
        return MEGA_ROOM, "the first 64 KB of a Mega's flash (what PROGMEM reaches) leave"
    return FLASH_MAX - FIRMWARE_FLASH, (f"beside the firmware's {FIRMWARE_FLASH:,}, an "
                                        f"old-bootloader Nano's {FLASH_MAX:,} leave")


def check_fit(flash: StoredSet, space: int = FLASH_MAX - FIRMWARE_FLASH,
              why: str | None = None) -> None:
    """An error naming the sizes, and what to leave out, if ``flash`` does not fit in
    ``space`` bytes (``why``: what leaves that much)."""
    room = space
    blob = flash.size()
    if blob <= room:
        return
    sizes = sorted(((len(g.data) + len(g.name) + 3 + 6 + len(g.start), g.name)
                    for g in flash.gestures), reverse=True)
    out, over = [], blob - room
    for size, name in sizes:
        if over <= 0:
            break
        out.append(f"{name} ({size:,} bytes)")
        over -= size
    why = why or (f"beside the firmware's {FIRMWARE_FLASH:,}, an old-bootloader Nano's "
                  f"{FLASH_MAX:,} leave")
    raise GestError(Diagnostic(
        "error", f"the {len(flash.gestures)} gestures take {blob:,} bytes of flash: {why} "
        f"room for {room:,}", hint=f"leave out {', '.join(out)}"))


def stored_header(flash: StoredSet, profile: Profile, board: Board) -> str:
    """The sketch's ``stored.h``: the blob in ``PROGMEM``, and what it holds in words."""
    blob = flash.to_bytes()
    rows = []
    for k, g in enumerate(flash.gestures):
        starts = [("power-up", flash.boot == k), (f"idle {flash.idle_after} s",
                                                   flash.idle == k)]
        why = [w for w, yes in starts if yes]
        why += [f"button {pin_name(p, arduino.of(board.options)[3])}" for p, n in flash.buttons
                if n == k]
        rows.append(f"//   {k:>3}  {g.name:<16} {g.frames * FRAME:7.2f} s  "
                    f"{len(g.data):>6,} bytes  {', '.join(why)}".rstrip())
    data = ",\n".join("    " + ", ".join(f"0x{b:02x}" for b in blob[k:k + 12])
                      for k in range(0, len(blob), 12))
    return (f"// Gestures stored in board {board.id} ({board.name}) of profile "
            f"'{profile.name}', generated by\n//     gestc firmware --store ... (or gestc "
            f"upload --store ...)\n// {len(blob):,} bytes of flash:\n"
            f"//   number name             duration    stream  started by (and the host)\n"
            + "\n".join(rows) +
            "\n#ifndef INMOOV_STORED_H\n#define INMOOV_STORED_H\n\n#include <avr/pgmspace.h>\n"
            "#include <stdint.h>\n\n"
            f"#define INMOOV_STORED_GESTURES {len(flash.gestures)}\n"
            f"const uint16_t INMOOV_STORED_SIZE = {len(blob)};\n"
            f"extern const uint8_t INMOOV_STORED[] PROGMEM = {{\n{data}\n}};\n\n#endif\n")
