"""A simulated Arduino bootloader on a pseudo-terminal, for the upload tests.

``Bootloader`` answers STK500v1 as Optiboot (the Uno's and the new Nano's bootloader)
does, in a thread, on the master side of a pty; avrdude opens the slave side
(``bootloader.port``) as it would open ``/dev/ttyUSB0``. It keeps a 32 KB flash image
(0xFF when new) and a 1 KB EEPROM, records every command byte it read, and answers only
while the port is set to its own speed (115200, or 57600 for the old Nano bootloader):
at any other speed a real board sees noise, so it sends nothing. ``silent=True`` is a
port with nothing answering at all.
"""

from __future__ import annotations

import contextlib
import os
import select
import termios
import threading
import time
import tty

FLASH_SIZE = 32 * 1024
EEPROM_SIZE = 1024
SIGNATURE = bytes([0x1E, 0x95, 0x0F])  # ATmega328P

INSYNC, OK, NOSYNC, EOP = 0x14, 0x10, 0x15, 0x20
GET_SYNC, GET_PARAMETER, SET_DEVICE, SET_DEVICE_EXT = 0x30, 0x41, 0x42, 0x45
ENTER_PROGMODE, LEAVE_PROGMODE, LOAD_ADDRESS, UNIVERSAL = 0x50, 0x51, 0x55, 0x56
PROG_PAGE, READ_PAGE, READ_SIGN = 0x64, 0x74, 0x75
# Optiboot 4.4 as an Uno reports it: hardware version 3, software 4.4
PARAMETERS = {0x80: 3, 0x81: 4, 0x82: 4}
# bytes between the command and its EOP, for the commands Optiboot does not implement
# (it reads them and answers INSYNC OK, as it does any command it does not know)
OTHER_ARGS = {0x40: 2, 0x60: 2, 0x61: 1, 0x62: 2, 0x63: 1, 0x65: 3}
SPEEDS = {57600: termios.B57600, 115200: termios.B115200}


class Bootloader:
    """An ATmega328P waiting in its bootloader, on a pseudo-terminal."""

    def __init__(self, baud: int = 115200, silent: bool = False,
                 unplugged_after: int | None = None):
        self.baud = baud
        self.silent = silent
        self.unplugged_after = unplugged_after  #: pages written before the cable goes
        self.flash = bytearray(b"\xff" * FLASH_SIZE)
        self.eeprom = bytearray(b"\xff" * EEPROM_SIZE)
        self.commands: list[int] = []  #: the command byte of every command answered
        self.pages: list[tuple[int, int]] = []  #: (byte address, length) of each page written
        self.left = False  #: LEAVE_PROGMODE came (the board would start the sketch)
        self.master, self.slave = os.openpty()
        tty.setraw(self.slave)
        self.port = os.ttyname(self.slave)
        self._address = 0  # bytes
        self._stop = threading.Event()
        self._buffer = bytearray()
        self._thread = threading.Thread(target=self._serve, daemon=True)
        self._thread.start()

    @property
    def path(self) -> str:
        """The port to give avrdude (the pty's slave side)."""
        return self.port

    def close(self) -> None:
        """Stop answering and close both ends of the pty."""
        if self._stop.is_set():
            return
        self._stop.set()
        self._thread.join(5)
        for fd in (self.master, self.slave):
            with contextlib.suppress(OSError):  # (unplugged: the master is gone already)
                os.close(fd)

    def __enter__(self) -> Bootloader:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    # -- the wire ---------------------------------------------------------------------
    def _speed_ok(self) -> bool:
        # the slave's settings are what avrdude gave the port (this end holds it open)
        ispeed, ospeed = termios.tcgetattr(self.slave)[4:6]
        return ispeed == ospeed == SPEEDS[self.baud]

    def _fill(self, wanted: int) -> bool:
        """Read until ``wanted`` bytes are buffered; False once stopped."""
        while len(self._buffer) < wanted:
            if self._stop.is_set():
                return False
            ready, _, _ = select.select([self.master], [], [], 0.05)
            if not ready:
                continue
            try:
                data = os.read(self.master, 4096)
            except OSError:  # EIO: nobody has the port open (this end holds it: rare)
                time.sleep(0.01)
                continue
            if not self.silent and self._speed_ok():
                self._buffer += data
        return True

    def _take(self, count: int) -> bytes | None:
        if not self._fill(count):
            return None
        data = bytes(self._buffer[:count])
        del self._buffer[:count]
        return data

    def _send(self, data: bytes) -> None:
        os.write(self.master, data)

    # -- the bootloader ---------------------------------------------------------------
    def _serve(self) -> None:
        while True:
            head = self._take(1)
            if head is None:
                return
            if not self._command(head[0]):
                return

    def _end(self, answer: bytes = b"") -> bool:
        """Read the command's EOP; answer INSYNC answer OK, or NOSYNC without it."""
        eop = self._take(1)
        if eop is None:
            return False
        if eop[0] != EOP:
            self._send(bytes([NOSYNC]))
            return True
        self._send(bytes([INSYNC]) + answer + bytes([OK]))
        return True

    def _command(self, cmd: int) -> bool:  # noqa: C901 - one branch per command
        self.commands.append(cmd)
        if cmd == GET_PARAMETER:
            args = self._take(1)
            return args is not None and self._end(bytes([PARAMETERS.get(args[0], 3)]))
        if cmd in (SET_DEVICE, SET_DEVICE_EXT):
            return self._take(20 if cmd == SET_DEVICE else 5) is not None and self._end()
        if cmd == LOAD_ADDRESS:
            args = self._take(2)
            if args is None:
                return False
            self._address = 2 * (args[0] | args[1] << 8)  # a word address
            return self._end()
        if cmd == UNIVERSAL:  # chip erase among others: Optiboot answers 0, erases nothing
            return self._take(4) is not None and self._end(b"\x00")
        if cmd == PROG_PAGE:
            args = self._take(3)
            if args is None:
                return False
            length, memory = args[0] << 8 | args[1], chr(args[2])
            data = self._take(length)
            if data is None:
                return False
            target = self.flash if memory == "F" else self.eeprom
            end = self._address + length
            if end <= len(target):
                target[self._address:end] = data
                if memory == "F":
                    self.pages.append((self._address, length))
            if len(self.pages) == self.unplugged_after:  # the cable goes: no answer, and
                os.close(self.master)  # the port's other end is gone
                return False
            return self._end()
        if cmd == READ_PAGE:
            args = self._take(3)
            if args is None:
                return False
            length, memory = args[0] << 8 | args[1], chr(args[2])
            source = self.flash if memory == "F" else self.eeprom
            data = bytes(source[self._address:self._address + length])
            return self._end(data.ljust(length, b"\xff"))
        if cmd == READ_SIGN:
            return self._end(SIGNATURE)
        if cmd == LEAVE_PROGMODE:
            self.left = True
            return self._end()
        if cmd in OTHER_ARGS and self._take(OTHER_ARGS[cmd]) is None:
            return False
        return self._end()  # GET_SYNC, ENTER_PROGMODE and anything else

