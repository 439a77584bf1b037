"""Single key presses from the terminal (arrows, Enter, letters) on POSIX and Windows."""

from __future__ import annotations

import contextlib
import os
import select
import sys
from collections.abc import Iterator

_ESCAPES = {"[A": "up", "[B": "down", "[C": "right", "[D": "left",
            "OA": "up", "OB": "down", "OC": "right", "OD": "left",
            "[5~": "pageup", "[6~": "pagedown",
            "[1;2A": "shift-up", "[1;2B": "shift-down", "[a": "shift-up", "[b": "shift-down"}
_WINDOWS = {"H": "up", "P": "down", "M": "right", "K": "left", "I": "pageup", "Q": "pagedown"}


@contextlib.contextmanager
def key_reader() -> Iterator[Iterator[str]]:
    """The terminal in key-at-a-time mode (no echo, Ctrl-C still interrupts), and the
    keys pressed: 'up', 'down', 'left', 'right', 'pageup', 'pagedown', 'shift-up',
    'shift-down', 'enter', 'esc', or the character typed, until the input ends. Other
    keys that send a sequence (Home, F1, Alt+letter) are skipped, never taken for Esc.
    Enter it before saying "press a key", so that no early key is lost or echoed."""
    if sys.platform == "win32":  # pragma: no cover - Windows only
        yield _windows_keys()
        return
    fd = sys.stdin.fileno()
    with _cbreak(fd):
        yield _posix_keys(fd)


def _windows_keys() -> Iterator[str]:  # pragma: no cover - Windows only
    import msvcrt

    while True:
        ch = msvcrt.getwch()
        if ch in ("\x00", "\xe0"):
            name = _WINDOWS.get(msvcrt.getwch())
            if name:
                yield name
        elif ch == "\x03":
            raise KeyboardInterrupt
        else:
            yield _plain(ch)


def _posix_keys(fd: int) -> Iterator[str]:
    while True:
        ch = _read(fd)
        if not ch or ch == "\x04":
            return
        if ch != "\x1b":
            yield _plain(ch)
            continue
        seq = _sequence(fd)
        if not seq:
            yield "esc"
        elif seq in _ESCAPES:
            yield _ESCAPES[seq]


def _sequence(fd: int) -> str:
    """What follows an ESC at once: "" for the Esc key alone, else a key's sequence read
    whole ('[' and its parameters up to the final letter or '~', 'O' and one letter, or
    the one character of Alt+key), so none of it is left over as keys typed."""
    if not _ready(fd):
        return ""
    seq = _read(fd)
    if seq == "O" and _ready(fd):
        seq += _read(fd)
    elif seq == "[":
        while len(seq) < 8 and _ready(fd):
            seq += _read(fd)
            if "@" <= seq[-1] <= "~" and seq != "[[":  # the final byte ([[A: Linux F1)
                break
    return seq


def _ready(fd: int) -> bool:
    return bool(select.select([fd], [], [], 0.05)[0])


def _plain(ch: str) -> str:
    return "enter" if ch in ("\r", "\n") else ch


def _read(fd: int) -> str:
    return os.read(fd, 1).decode("latin-1")


@contextlib.contextmanager
def _cbreak(fd: int):
    """Keys without Enter and without echo; Ctrl-C still interrupts."""
    if not os.isatty(fd):
        yield
        return
    import termios
    import tty

    saved = termios.tcgetattr(fd)
    try:
        tty.setcbreak(fd, termios.TCSANOW)  # keys typed already are kept
        yield
    finally:
        termios.tcsetattr(fd, termios.TCSADRAIN, saved)
