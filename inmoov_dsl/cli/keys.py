"""Single key presses from the terminal (arrows, Enter, letters) on POSIX and Windows."""

from __future__ import annotations

import contextlib
import os
import select
import sys
from collections.abc import Iterator

_ESCAPES = {"[A": "up", "[B": "down", "[C": "right", "[D": "left",
            "OA": "up", "OB": "down", "OC": "right", "OD": "left",
            "[5~": "pageup", "[6~": "pagedown"}
_WINDOWS = {"H": "up", "P": "down", "M": "right", "K": "left", "I": "pageup", "Q": "pagedown"}


@contextlib.contextmanager
def key_reader() -> Iterator[Iterator[str]]:
    """The terminal in key-at-a-time mode (no echo, Ctrl-C still interrupts), and the
    keys pressed: 'up', 'down', 'left', 'right', 'pageup', 'pagedown', 'enter', 'esc',
    or the character typed, until the input ends. Enter it before saying "press a
    key", so that no early key is lost or echoed."""
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
        seq = ""
        while len(seq) < 3 and select.select([fd], [], [], 0.05)[0]:
            seq += _read(fd)
            if seq in _ESCAPES:
                break
        yield _ESCAPES.get(seq, "esc")


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
