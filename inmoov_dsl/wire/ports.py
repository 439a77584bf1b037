"""Serial ports: opening one by name or URL, with errors people can act on.

Ports are pyserial URLs: a device (``COM3``, ``/dev/ttyUSB0``), ``loop://``,
``socket://host:port``, ``rfc2217://``, ``spy://`` (hex-dumps the traffic), or
``sim://``, the built-in virtual board.
"""

from __future__ import annotations

import errno
import os
import sys
from collections.abc import Callable
from dataclasses import dataclass

import serial
from serial.tools import list_ports

from ..boards import claimed
from ..errors import Diagnostic, GestError
from ..hardware import Board, Profile

HANDLERS = "inmoov_dsl.wire.urlhandler"
if HANDLERS not in serial.protocol_handler_packages:
    serial.protocol_handler_packages.append(HANDLERS)


#: USB vendor:product IDs of the boards (and the USB-serial chips of their clones) the
#: hand runs on: (vendor, product or None for any) -> what it probably is.
ARDUINO_USB: dict[tuple[int, int | None], str] = {
    (0x2341, None): "an Arduino",
    (0x2A03, None): "an Arduino",
    (0x1A86, 0x7523): "a CH340: most Nano and Uno clones",
    (0x0403, 0x6001): "an FTDI FT232R: older Nanos and clones",
    (0x10C4, 0xEA60): "a CP2102: some clones",
    # Pololu's Maestros: two ports each, the Command Port first (docs/controllers.md)
    (0x1FFB, 0x0089): "a Pololu Micro Maestro 6 (profile kind maestro, model micro6)",
    (0x1FFB, 0x008A): "a Pololu Mini Maestro 12 (profile kind maestro)",
    (0x1FFB, 0x008B): "a Pololu Mini Maestro 18 (profile kind maestro, model mini18)",
    (0x1FFB, 0x008C): "a Pololu Mini Maestro 24 (profile kind maestro, model mini24)",
}


@dataclass(frozen=True)
class PortInfo:
    """A serial port of this machine, as ``gestplay ports`` shows it."""

    device: str
    description: str
    vid: int | None = None
    pid: int | None = None

    @property
    def usb(self) -> str | None:
        """``VID:PID`` in hex, for a USB port."""
        return None if self.vid is None else f"{self.vid:04X}:{self.pid or 0:04X}"

    @property
    def likely(self) -> str | None:
        """What board this probably is, when its USB IDs are those of an Arduino."""
        if self.vid is None:
            return None
        return ARDUINO_USB.get((self.vid, self.pid)) or ARDUINO_USB.get((self.vid, None))


def available() -> list[PortInfo]:
    """The serial ports on this machine, likely Arduinos first, then by name."""
    found = [PortInfo(p.device, p.description, p.vid, p.pid) for p in list_ports.comports()]
    return sorted(found, key=lambda p: (p.likely is None, p.device))


def _names() -> str:
    ports = [p.device for p in available()]
    return ", ".join(ports) if ports else "none"


def name_hint(name: str) -> str | None:
    """A hint when ``name`` is not how this system names a port: another system's kind
    of name (``COM3`` on Linux or macOS, ``/dev/...`` on Windows), or a device without
    its ``/dev/``."""
    windows = name.upper().startswith("COM") and name[3:].isdigit()
    if windows and sys.platform != "win32":
        return ("COM ports are Windows names; here an Arduino is /dev/ttyACM0 (Uno, "
                "Leonardo) or /dev/ttyUSB0 (Nano, clones)" if sys.platform.startswith("linux")
                else "COM ports are Windows names; here an Arduino is /dev/cu.usbmodem... or "
                "/dev/cu.usbserial-...")
    if name.startswith("/dev/") and sys.platform == "win32":
        return "/dev/... names are Linux and macOS ones; on Windows a board is COM3, COM4..."
    if sys.platform != "win32" and name.startswith(("tty", "cu.")) and "/" not in name:
        return f"a port is named by its path: /dev/{name}"
    return None


def not_found(name: str, virtual: bool = True) -> Diagnostic:
    """The one message for a port that is not there, whichever command named it: the
    ports this machine has, and a hint about the name (``name_hint``) or where to look.
    ``virtual``: the command also takes ``sim://``, the virtual board."""
    where = ("'gestplay ports' lists them (and marks the likely Arduinos)"
             + ("; sim:// is the virtual board" if virtual else ""))
    return Diagnostic("error", f"port {name} not found; ports on this machine: {_names()}",
                      hint=name_hint(name) or where)


def not_of_another_kind(spec: str, profile: Profile, board: Board) -> None:
    """A port only another kind of board is on (an I2C bus, for a rig board) is an
    error that says so, and which shipped profiles have a board of that kind."""
    found = claimed(spec)
    if found is None or found[0] == board.kind:
        return
    kind, what = found
    have = shipped(lambda p: any(b.kind == kind for b in p.boards))
    raise GestError(Diagnostic(
        "error", f"port {spec} is {what}: board {board.id} ({board.name}) of profile "
        f"'{profile.name}' is a {board.kind} board, on a serial port",
        hint=f"a profile whose board is a {kind} plays there"
        + (f": --profile {' or '.join(have)}" if have else "")
        + f"; for board {board.id}, give its serial port ('gestplay ports' lists them)"))


def shipped(has: Callable[[Profile], bool]) -> list[str]:
    """The shipped profiles that ``has`` is true of, by name."""
    from ..profiles.profile import builtin_profiles, load_profile

    found = []
    for name in builtin_profiles():
        try:
            if has(load_profile(name)):
                found.append(name)
        except GestError:
            continue
    return found


def permission_denied(name: str) -> Diagnostic:
    """The one message for a port this user may not open, with this system's remedy."""
    if sys.platform.startswith("linux"):
        hint = ("add yourself to the dialout group: sudo usermod -a -G dialout $USER, "
                "then log out and in again")
    elif sys.platform == "win32":
        hint = "another program (the Arduino IDE's serial monitor?) has the port open"
    else:
        hint = "check the port's permissions, or whether another program has it open"
    return Diagnostic("error", f"permission denied on port {name}", hint=hint)


def device_problem(name: str) -> Diagnostic | None:
    """For a command that hands ``name`` to another program (avrdude), which opens
    only devices: what is wrong with it before anything is built, or None. A URL is
    refused; a device path that is not there is ``not_found``; on Windows only a
    ``/dev/`` name is known to be wrong (COM ports are not files)."""
    if "://" in name:
        return Diagnostic("error", f"port {name}: avrdude opens a serial device, not a URL",
                          hint="give the board's device ('gestplay ports' lists them); the "
                          "virtual board (sim://, gestsim) needs no firmware")
    if sys.platform == "win32":
        return not_found(name, virtual=False) if name.startswith("/dev/") else None
    if name.startswith("net:") or os.path.exists(name):
        return None
    return not_found(name, virtual=False)


def open_port(name: str, baud: int, timeout: float = 0) -> serial.SerialBase:
    """Open ``name`` at ``baud``; any failure is a GestError saying what to do.

    Reads do not block by default (``timeout=0``): the player polls, and a read on a
    link that has gone away raises at once. DTR stays up when the port closes, where
    the OS allows it (``leave_dtr_up``)."""
    try:
        port = serial.serial_for_url(name, baudrate=baud, timeout=timeout, write_timeout=2)
    except serial.SerialException as exc:
        raise GestError(_explain(name, exc)) from None
    except (ValueError, OSError) as exc:
        raise GestError(Diagnostic("error", f"cannot open {name}: {exc}")) from None
    port.reset_on_open = dtr_rose(port)
    leave_dtr_up(port)
    return port


def reset_on_open(port) -> bool | None:
    """Did opening ``port`` (with ``open_port``) reset the board behind it? None: the
    port has no DTR line (``dtr_rose``), or was not opened by ``open_port``."""
    return getattr(port, "reset_on_open", None)


def dtr_rose(port: serial.SerialBase) -> bool | None:
    """Did opening ``port`` raise DTR, which resets an Arduino? On POSIX DTR was down
    if the last program to close the port left HUPCL set (a serial device's default:
    closing dropped DTR); one that cleared it (``leave_dtr_up``) left DTR up, and the
    open made no edge. The virtual board (``sim://``) says itself. On Windows every
    open raises DTR (a close drops it). None: a port that is no terminal
    (``socket://``, ``loop://``) has no DTR line."""
    said = getattr(port, "dtr_rose", None)
    if said is not None:
        return bool(said)
    try:
        import termios
    except ImportError:  # Windows
        return True
    try:
        return bool(termios.tcgetattr(port.fileno())[2] & termios.HUPCL)
    except (AttributeError, OSError, ValueError, termios.error, serial.SerialException):
        return None


def leave_dtr_up(port: serial.SerialBase) -> bool:
    """Keep DTR raised after ``port`` closes, so that the next open makes no DTR edge
    and does not reset an Uno or a Nano: on POSIX, clear HUPCL (``stty -hupcl``); the
    virtual board (``sim://``) models the same flag. False where the OS cannot
    (Windows drops DTR on closing) or the port is no terminal (``socket://``...)."""
    if hasattr(port, "hupcl"):
        port.hupcl = False
        return True
    try:
        import termios
    except ImportError:  # Windows
        return False
    try:
        fd = port.fileno()
        attrs = termios.tcgetattr(fd)
        attrs[2] &= ~termios.HUPCL
        termios.tcsetattr(fd, termios.TCSANOW, attrs)
    except (AttributeError, OSError, ValueError, termios.error, serial.SerialException):
        return False
    return True


def _explain(name: str, exc: serial.SerialException) -> Diagnostic:
    said = getattr(exc, "diagnostic", None)  # a handler that words its own (sim://)
    if isinstance(said, Diagnostic):
        return said
    code = exc.errno
    text = str(exc)
    if code == errno.ENOENT or "FileNotFoundError" in text or "could not open port" in text \
            and ("No such file" in text or "cannot find" in text.lower()):
        return not_found(name)
    if code in (errno.EACCES, errno.EPERM) or "PermissionError" in text \
            or "Access is denied" in text:
        return permission_denied(name)
    return Diagnostic("error", f"cannot open port {name}: {text}")
