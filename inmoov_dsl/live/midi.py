"""A MIDI take read from a ``.mid`` file (the edge: a file; mido, the ``midi`` extra): its
control changes, each with its time in seconds from the file's start and its channel
1..16, as ``controls.samples`` takes them. A take recorded in a DAW, or written by a test."""

from __future__ import annotations

import os

from ..errors import Diagnostic, GestError, Pos
from .controls import Message

INSTALL = "pip install 'inmoov-dsl[midi]' (mido)"
MAX_FILE = 16 * 1024 * 1024  #: bytes of one .mid file read
MAX_MESSAGES = 1_000_000  #: control changes of one take


def read_take(path: str) -> list[Message]:
    """The control changes of the MIDI file ``path``; a GestError naming the file when
    it cannot be read as one (missing, too large, not MIDI, mido missing)."""
    try:
        import mido
    except ImportError:
        raise GestError(Diagnostic("error", "reading a MIDI take needs mido, which is not "
                                   "installed", hint=INSTALL)) from None
    try:
        size = os.path.getsize(path)
    except OSError as exc:
        raise GestError(Diagnostic("error", f"cannot read '{path}': {exc.strerror}",
                                   Pos(path, 1, 1))) from None
    if size > MAX_FILE:
        raise GestError(Diagnostic("error", f"'{path}' is {size:,} bytes: a MIDI take is "
                                   f"read up to {MAX_FILE:,}", Pos(path, 1, 1)))
    try:
        take = mido.MidiFile(path)
        found, now = [], 0.0
        for message in take:  # each with the seconds since the one before
            now += message.time
            if message.type == "control_change":
                found.append((now, message.channel + 1, message.control, message.value))
                if len(found) > MAX_MESSAGES:
                    raise ValueError(f"more than {MAX_MESSAGES:,} control changes")
    except Exception as exc:  # noqa: BLE001 (mido's many ways of refusing a file)
        raise GestError(Diagnostic("error", f"'{path}' is not a MIDI take that can be read: "
                                   f"{exc}", Pos(path, 1, 1),
                                   "a standard MIDI file (.mid) of control changes, as a "
                                   "DAW or mido writes it")) from None
    return found
