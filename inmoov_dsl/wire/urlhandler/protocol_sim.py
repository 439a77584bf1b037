"""``sim://[PROFILE][?board=ID&boot=SECONDS&fresh&flash=DIR]``: the virtual board as a
pyserial port, of the board's kind (a rig, a Maestro; a PCA9685 is on a bus, not a
serial port: ``boards/pca9685/bus.py`` gives its ``sim://``).

PROFILE defaults to ``rhand``, the board to the profile's first, ``boot`` (the time
the bootloader swallows bytes after a reset, as an Uno or Nano does) to 0.2 s.
``flash`` is the folder of a sketch built with stored gestures (``gestc firmware
--store``), or its ``stored.h``: the board holds them, the same bytes, and plays them
as that image does.
A bare ``sim://`` is completed with the profile and board it is opened for (``complete``,
called by the link edge, ``wire/link.py``).
The board runs in real time on ``clock.now`` (the clock every tool reads): what the
host writes arrives at the board's baud, and replies come back the same way.

A board stays on the desk for the life of the process: opening the same URL again
finds it as it was left. Like an Uno, it resets when an open raises DTR: the first
open, and any open after a close that dropped DTR. A port drops DTR on closing unless
its ``hupcl`` was cleared, as ``ports.leave_dtr_up`` does (the termios flag of a real
port on POSIX).

Like a real board's EEPROM, its pose outlives the process: on closing, the pose it will
have stored is kept in the user's private state directory (``memory.py``), one small
file per profile and board, and the next process's board powers up in it. ``fresh``
powers up a new board instead, at the profile's rest pose.
"""

from __future__ import annotations

import math
import urllib.parse
from pathlib import Path

from serial.serialutil import PortNotOpenError, SerialBase, SerialException

from ... import clock
from ...boards import controller
from ...boards.rig.core import BoardCore
from ...errors import Diagnostic, GestError, did_you_mean
from ...hardware import Board, Profile
from ...profiles.profile import builtin_profiles, find_profile, load_profile
from ..dtr import DtrLine
from ..sim import VirtualBoard
from ..stored import StoredSet, read_blob, read_set
from . import memory

DEFAULT_BOOT = 0.2  #: s
OPTIONS = ("board", "boot", "fresh", "flash")  #: what a sim:// URL may say after its '?'


class SimError(SerialException):
    """A ``sim://`` URL that names no board: what to say (``diagnostic``, with a hint
    where there is one)."""

    def __init__(self, url: str, message: str, hint: str | None = None):
        super().__init__(f"sim://: {message}")
        self.diagnostic = Diagnostic("error", f"cannot open port {url}: {message}", hint=hint)


class _Desk:
    """The virtual boards of this process, by URL, and the DTR line to each."""

    boards: dict[str, VirtualBoard] = {}
    lines: dict[str, DtrLine] = {}
    profiles: dict[str, Profile] = {}  #: each board's profile, to keep its pose under


def power_off() -> None:
    """Take every virtual board off the desk: the next open powers up a new one."""
    _Desk.boards.clear()
    _Desk.lines.clear()
    _Desk.profiles.clear()


def bare(url: str) -> bool:
    """Is ``url`` a ``sim://`` URL that names no profile?"""
    parts = urllib.parse.urlsplit(url)
    return parts.scheme == "sim" and not parts.netloc and not parts.path


def _options(url: str) -> dict[str, list[str]]:
    """A sim:// URL's options (``fresh`` alone is an option too)."""
    return urllib.parse.parse_qs(urllib.parse.urlsplit(url).query, keep_blank_values=True)


def named(url: str) -> tuple[Profile, Board]:
    """The profile and the board a sim:// URL names; SimError for one that names none."""
    parts = urllib.parse.urlsplit(url)
    if parts.scheme != "sim":
        raise SimError(url, "expected sim://[PROFILE][?board=ID&boot=S&fresh]")
    options = _options(url)
    unknown = [k for k in options if k not in OPTIONS]
    if unknown:
        raise SimError(url, f"unknown option '{unknown[0]}'", did_you_mean(unknown[0], OPTIONS)
                       or f"options: {', '.join(OPTIONS)}")
    try:
        profile = load_profile(parts.netloc + parts.path or "rhand")
    except GestError as exc:
        raise SimError(url, exc.first.message, exc.first.hint) from None
    ids = ", ".join(str(b.id) for b in profile.boards)
    text = options.get("board", [str(profile.boards[0].id)])[0]
    if not text.isdigit():
        raise SimError(url, f"board={text}: not a board ID", f"the profile's boards: {ids}")
    board_id = int(text)
    board = next((b for b in profile.boards if b.id == board_id), None)
    if board is None:
        raise SimError(url, f"profile '{profile.name}' has no board {board_id}",
                       f"its boards: {ids}")
    return profile, board


def _board_from_url(url: str) -> tuple[VirtualBoard, Profile]:
    """The board a sim:// URL names, powered up: in the pose it last stored (``memory``),
    or at rest when it never did or the URL says ``fresh``."""
    profile, board = named(url)
    options = _options(url)
    kind = controller(profile, board)
    core = kind.twin()
    stored = None if "fresh" in options else memory.recall(profile, core)
    if "flash" in options and not kind.ours:
        raise SimError(url, f"flash: board {board.id} is a {board.kind}, which stores no "
                       "gestures", "leave flash= out")
    flash = _flash(url, options["flash"][0], core) if "flash" in options else None
    loader = kind.bootloader()
    return VirtualBoard(core, board.baud, stored=stored, flash=flash, chatty=kind.ours,
                        hello=kind.hello(), trap=loader.trap if loader else 0.0), profile


def resets(board: VirtualBoard) -> bool:
    """Does ``board`` reset when DTR rises (an Arduino: a rig, an MrlComm board; not a
    Maestro, nor a PCA9685 behind its bus)?"""
    return board.chatty or bool(board.hello)


def _flash(url: str, path: str, core: BoardCore) -> StoredSet:
    """The gestures stored in the sketch at ``path``, for this board."""
    try:
        flash = read_set(read_blob(path))
    except GestError as exc:
        raise SimError(url, exc.first.message, exc.first.hint) from None
    except (ValueError, IndexError):
        raise SimError(url, f"flash={path}: its stored gestures are not of this version",
                       "build it again: gestc firmware PROFILE --store ...") from None
    if len(flash.limits) != len(core.servos):
        raise SimError(url, f"flash={path}: stored for a board of {len(flash.limits)} "
                       f"servos, and board {core.board_id} has {len(core.servos)}",
                       "give the sketch of this board")
    return flash


def complete(url: str, profile: Profile, board: int) -> str:
    """A ``sim://`` URL that names no profile, completed with ``profile`` and ``board``
    (the virtual board of what is being played); any other URL as it is."""
    if not bare(url):
        return url
    options = _options(url)
    options.setdefault("board", [str(board)])
    builtin = profile.name in builtin_profiles() and \
        find_profile(profile.name).resolve() == Path(profile.path).resolve()
    where = profile.name if builtin or not profile.path else Path(profile.path).as_posix()
    query = "&".join(k if v == "" else urllib.parse.urlencode({k: v})
                     for k, values in options.items() for v in values)
    return f"sim://{where}?{query}"


class Serial(SerialBase):
    """A pyserial port with the virtual board on the other end."""

    board: VirtualBoard | None = None
    hupcl = True  #: drop DTR on closing (the POSIX default)
    dtr_rose = False  #: the open raised DTR and the board reset (``ports.dtr_rose``)

    def open(self) -> None:
        """Connect to the board of this URL, powering it up or resetting it as DTR rises."""
        if self.is_open:
            raise SerialException("Port is already open.")
        if self._port is None:
            raise SerialException("Port must be configured before it can be used.")
        url = self.portstr
        boot = self._boot(url)
        board = _Desk.boards.get(url)
        if board is None:  # powered up: the board boots, with DTR rising
            board, _Desk.profiles[url] = _board_from_url(url)
            _Desk.boards[url] = board
            board.ready_at = clock.now() + (boot if resets(board) else 0.0)
            _Desk.lines[url] = DtrLine()
            _Desk.lines[url].opened()
            self.dtr_rose = resets(board)
        else:  # DTR rose: an Uno resets (a Maestro's USB port does not reset it)
            self.dtr_rose = _Desk.lines[url].opened() and resets(board)
            if self.dtr_rose:
                board.reset(clock.now(), boot)
        self.board = board
        self.is_open = True

    @staticmethod
    def _boot(url: str) -> float:
        text = _options(url).get("boot", [str(DEFAULT_BOOT)])[0]
        try:
            boot = float(text)
        except ValueError:
            boot = math.nan
        if not 0 <= boot <= 60:
            raise SimError(url, f"boot={text}: not a number of seconds from 0 to 60",
                           f"boot={DEFAULT_BOOT} (an Uno's or a Nano's)")
        return boot

    def close(self) -> None:
        """Disconnect; DTR drops unless ``hupcl`` was cleared."""
        if self.is_open:
            line = _Desk.lines[self.portstr]
            line.hupcl = self.hupcl
            line.closed()
            memory.keep(_Desk.profiles[self.portstr], self.board)
        self.is_open = False

    def _reconfigure_port(self) -> None:
        pass

    @property
    def in_waiting(self) -> int:
        """Bytes the board has sent and nobody has read yet."""
        self._check()
        self._pending += self.board.read(clock.now())
        return len(self._pending)

    def read(self, size: int = 1) -> bytes:
        """Up to ``size`` bytes from the board, waiting at most the port's timeout."""
        self._check()
        deadline = None if self._timeout is None else clock.now() + self._timeout
        data = bytearray(self._pending)
        self._pending.clear()
        while len(data) < size:
            data += self.board.read(clock.now())
            if len(data) >= size or (deadline is not None and clock.now() >= deadline):
                break
            clock.sleep(0.0005)
        self._pending += data[size:]
        return bytes(data[:size])

    def write(self, data: bytes) -> int:
        """Send ``data`` to the board now; returns the bytes written."""
        self._check()
        data = bytes(data)
        self.board.write(data, clock.now())
        return len(data)

    def reset_input_buffer(self) -> None:
        """Drop what the board has sent so far."""
        self._check()
        self._pending.clear()
        self.board.read(clock.now())

    def reset_output_buffer(self) -> None:
        """Drop what was written and is not yet on the wire (as a UART's buffer is
        flushed): the bytes whose transmission has not begun."""
        self._check()
        self.board.discard(clock.now())

    def flush(self) -> None:
        """Wait until what was written has been sent (as ``tcdrain``)."""
        self._check()
        clock.sleep(max(0.0, self.board.sending_until() - clock.now()))

    def _check(self) -> None:
        if not self.is_open:
            raise PortNotOpenError()
        if not hasattr(self, "_pending"):
            self._pending = bytearray()
