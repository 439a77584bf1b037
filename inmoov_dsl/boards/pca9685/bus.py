"""The edge of a PCA9685: its I2C bus as a port the player writes transactions to.

``--port i2c:1`` is ``/dev/i2c-1`` at address 0x40 (``i2c:1@0x41`` another address),
through ``smbus2``. The port reads the framed transactions it is written
(``transactions.py``), makes each a block write or a read, and keeps what reads answer
for ``read``: the player, the drive loop and the tools use it as they use a serial
port. (``sim://`` is the virtual chip on a virtual board's link, as every kind's twin
is: ``wire/urlhandler/protocol_sim.py``.)
"""

from __future__ import annotations

import glob
import os
import re
from collections.abc import Callable

from ...errors import Diagnostic, GestError
from . import transactions as tx

ADDRESS = 0x40  #: a PCA9685's address with no jumper closed
DEVICE = "/dev/i2c-"  #: a bus's device, before its number
SPEC = re.compile(r"i2c:(\d+)(?:@(0x[0-9a-fA-F]+|\d+))?")
#: the addresses a PCA9685 may be given: its six address pins give 0x40..0x7F, of which
#: the I2C bus reserves 0x78..0x7F and 0x70 is the All Call address every PCA9685
#: answers from power-up (a write there moves each chip on the bus)
ADDRESSES = "0x40..0x77 except 0x70"


class I2CPort:
    """A PCA9685 on ``bus`` at ``address``, written to and read as a port."""

    def __init__(self, bus, address: int, name: str):
        self.bus, self.address, self.name = bus, address, name
        self._out = bytearray()  # a transaction not yet whole
        self._in = bytearray()  # what reads answered
        self.is_open = True

    def write(self, data: bytes) -> int:
        """Carry out every whole transaction of what was written so far."""
        self._out += data
        out = self._out
        whole = [(a, b) for a, b in tx.commands(bytes(out))
                 if b - a >= 3 and (out[a] != tx.WRITE or b - a == 3 + out[a + 2])]
        end = whole[-1][1] if whole else 0
        done, self._out = bytes(self._out[:end]), self._out[end:]
        for kind, register, arg in tx.parse(done):
            self._do(lambda k=kind, r=register, a=arg: self._in.extend(
                self.bus.read_i2c_block_data(self.address, r, a)) if k == tx.READ else
                self.bus.write_i2c_block_data(self.address, r, list(a)))
        return len(data)

    def _do(self, call: Callable[[], object]) -> None:
        try:
            call()
        except OSError as exc:
            raise OSError(f"{self.name}: the PCA9685 at 0x{self.address:02x} did not "
                          f"answer ({exc.strerror or exc})") from None

    def read(self, size: int = 1) -> bytes:
        """Up to ``size`` bytes of what reads answered."""
        out, self._in = bytes(self._in[:size]), self._in[size:]
        return out

    @property
    def in_waiting(self) -> int:
        """Bytes read and not yet taken."""
        return len(self._in)

    def reset_input_buffer(self) -> None:
        """Drop what reads answered."""
        self._in.clear()

    def close(self) -> None:
        """Release the bus."""
        if self.is_open:
            self.bus.close()
        self.is_open = False


def open_bus(spec: str) -> I2CPort:
    """The PCA9685 that ``spec`` names, ``i2c:N[@ADDRESS]``, through smbus2."""
    found = SPEC.fullmatch(spec)
    if found is None:
        raise GestError(Diagnostic("error", f"cannot open port {spec}: a PCA9685 is on an "
                                   "I2C bus", hint="--port i2c:1 (/dev/i2c-1, address "
                                   "0x40) or i2c:1@0x41"))
    number, address = int(found[1]), bus_address(spec, found[2])
    if not os.path.exists(f"{DEVICE}{number}"):
        raise GestError(Diagnostic("error", f"cannot open port {spec}: there is no I2C bus "
                                   f"{number} ({DEVICE}{number}); buses on this machine: "
                                   f"{', '.join(buses()) or 'none'}", hint=ENABLE))
    try:
        from smbus2 import SMBus
    except ImportError:
        raise GestError(Diagnostic("error", f"cannot open port {spec}: smbus2 is not "
                                   "installed", hint="pip install 'inmoov-dsl[pca9685]'")
                        ) from None
    try:
        return I2CPort(SMBus(number), address, spec)
    except OSError as exc:
        raise GestError(Diagnostic("error", f"cannot open port {spec}: {DEVICE}{number}: "
                                   f"{exc.strerror or exc}", hint=GROUP if isinstance(
                                       exc, PermissionError) else ENABLE)) from None


def bus_address(spec: str, text: str | None) -> int:
    """The address ``text`` of port ``spec`` writes (None: ADDRESS): hex after ``0x``,
    else decimal, in ADDRESSES. A leading zero is refused rather than guessed at:
    i2c-tools (C's strtol) read ``010`` as octal 8, Python refuses it, a person may
    mean decimal 10, or hex 0x10 as i2cdetect shows addresses; a wrong guess drives
    another chip, so the error names the readings a PCA9685 may have instead."""
    if text is None:
        return ADDRESS
    if len(text) > 1 and text[0] == "0" and not text.startswith("0x"):
        raise GestError(Diagnostic(
            "error", f"cannot open port {spec}: the address {text} has a leading zero, "
            "which some tools read as octal, others as decimal",
            hint=_readings(spec.partition("@")[0], text.lstrip("0") or "0")))
    address = int(text, 16) if text.startswith("0x") else int(text)
    if not usable(address):
        said = text if text.startswith("0x") else f"{text} (decimal: 0x{address:02x})"
        raise GestError(Diagnostic("error", f"cannot open port {spec}: {said} is not a "
                                   f"PCA9685's address, which is {ADDRESSES}",
                                   hint="its six address pins give 0x40..0x7F; the I2C bus "
                                   "reserves 0x78..0x7F, and 0x70 is the All Call address "
                                   "every PCA9685 answers; with no pin bridged it is 0x40: "
                                   f"--port {spec.partition('@')[0]}"))
    return address


def usable(address: int) -> bool:
    """Is ``address`` one a PCA9685 may be given (ADDRESSES)?"""
    return 0x40 <= address <= 0x77 and address != 0x70


def _readings(bus: str, digits: str) -> str:
    """How to write an address given as ``digits`` after a leading zero: its readings
    as hex and as decimal that a PCA9685 may have."""
    ways = [f"{bus}@0x{a:02x}" + (f" for decimal {digits}" if base == 10 else "")
            for base, a in ((16, int(digits, 16)), (10, int(digits))) if usable(a)]
    return "write it in hex with 0x, as i2cdetect shows addresses" + \
        (f": {' or '.join(ways)}" if ways else f"; a PCA9685's address is {ADDRESSES}")


ENABLE = "on a Raspberry Pi, enable I2C (sudo raspi-config, Interface Options): its bus is " \
    "then /dev/i2c-1, --port i2c:1"
GROUP = "add yourself to the i2c group: sudo usermod -a -G i2c $USER, then log out and in again"


def buses() -> list[str]:
    """This machine's I2C buses (``/dev/i2c-N``), by number."""
    numbers = (path.removeprefix(DEVICE) for path in glob.glob(f"{DEVICE}*"))
    return [f"{DEVICE}{n}" for n in sorted((n for n in numbers if n.isdigit()), key=int)]
