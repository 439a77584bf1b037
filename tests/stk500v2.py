"""A simulated Arduino Mega 2560 bootloader on a pseudo-terminal, for the upload tests.

``MegaBootloader`` answers STK500v2 (Atmel's AVR068: each message ``0x1B, sequence,
size (2 bytes, big-endian), 0x0E, body, XOR checksum``, each answer the same framing with
the same sequence number) as the Mega's bootloader (Arduino's stk500v2 ``stk500boot``)
does: it signs on as ``AVRISP_2``, takes word addresses (bit 31: the extended address of
a flash above 128 KB), writes and reads flash pages, reads the ATmega2560's signature,
fuses and lock bits. It keeps a 256 KB flash (0xFF when new) and a 4 KB EEPROM, and, as
``stk500.Bootloader`` does, hears nothing at any speed but its own (115200).
"""

from __future__ import annotations

from stk500 import Bootloader

FLASH_SIZE = 256 * 1024
EEPROM_SIZE = 4 * 1024
SIGNATURE = bytes([0x1E, 0x98, 0x01])  # ATmega2560
FUSES = {0x50: 0xFF, 0x58: 0xD8, 0x5008: 0xFD}  # low, high, extended: an Arduino Mega's
LOCK = 0xCF

START, TOKEN = 0x1B, 0x0E
OK, FAILED, UNKNOWN = 0x00, 0xC0, 0xC9
SIGN_ON, SET_PARAMETER, GET_PARAMETER, LOAD_ADDRESS = 0x01, 0x02, 0x03, 0x06
ENTER_PROGMODE, LEAVE_PROGMODE, CHIP_ERASE = 0x10, 0x11, 0x12
PROGRAM_FLASH, READ_FLASH, PROGRAM_EEPROM, READ_EEPROM = 0x13, 0x14, 0x15, 0x16
READ_FUSE, READ_LOCK, READ_SIGNATURE, SPI_MULTI = 0x18, 0x1A, 0x1B, 0x1D
# stk500boot's answers: hardware version 15, software 2.10
PARAMETERS = {0x90: 0x0F, 0x91: 0x02, 0x92: 0x0A}


class MegaBootloader(Bootloader):
    """An ATmega2560 waiting in its bootloader, on a pseudo-terminal."""

    def __init__(self, baud: int = 115200, silent: bool = False):
        self.messages: list[int] = []  #: the command of every message answered
        self.bad: int = 0  #: messages whose checksum was wrong (not answered)
        self._word = 0  # the loaded address, in words
        super().__init__(baud, silent)
        self.flash = bytearray(b"\xff" * FLASH_SIZE)
        self.eeprom = bytearray(b"\xff" * EEPROM_SIZE)

    def _serve(self) -> None:
        while True:
            head = self._take(1)
            if head is None:
                return
            if head[0] != START:
                continue  # noise before a message: the bootloader waits for its start
            rest = self._take(4)
            if rest is None:
                return
            sequence, size, token = rest[0], rest[1] << 8 | rest[2], rest[3]
            if token != TOKEN:
                continue
            body = self._take(size + 1)
            if body is None:
                return
            body, check = body[:-1], body[-1]
            frame = bytes([START, sequence, size >> 8, size & 0xFF, TOKEN]) + body
            if _xor(frame) != check or not body:
                self.bad += 1
                continue
            answer = self._answer(body)
            out = bytes([START, sequence, len(answer) >> 8, len(answer) & 0xFF, TOKEN])
            out += answer
            self._send(out + bytes([_xor(out)]))

    def _answer(self, body: bytes) -> bytes:  # noqa: C901, PLR0911 - one branch a command
        cmd = body[0]
        self.messages.append(cmd)
        self.commands.append(cmd)
        if cmd == SIGN_ON:
            return bytes([cmd, OK, 8]) + b"AVRISP_2"
        if cmd == GET_PARAMETER:
            return bytes([cmd, OK, PARAMETERS.get(body[1], 0)])
        if cmd in (SET_PARAMETER, ENTER_PROGMODE, CHIP_ERASE):
            return bytes([cmd, OK])
        if cmd == LEAVE_PROGMODE:
            self.left = True
            return bytes([cmd, OK])
        if cmd == LOAD_ADDRESS:
            self._word = int.from_bytes(body[1:5], "big") & 0x7FFFFFFF
            return bytes([cmd, OK])
        if cmd in (PROGRAM_FLASH, PROGRAM_EEPROM):
            length = body[1] << 8 | body[2]
            data = body[10:10 + length]
            flash = cmd == PROGRAM_FLASH
            target, at = (self.flash, 2 * self._word) if flash else (self.eeprom, self._word)
            if len(data) != length or at + length > len(target):
                return bytes([cmd, FAILED])
            target[at:at + length] = data
            if flash:
                self.pages.append((at, length))
            self._word += length // 2 if flash else length
            return bytes([cmd, OK])
        if cmd in (READ_FLASH, READ_EEPROM):
            length = body[1] << 8 | body[2]
            flash = cmd == READ_FLASH
            source, at = (self.flash, 2 * self._word) if flash else (self.eeprom, self._word)
            data = bytes(source[at:at + length]).ljust(length, b"\xff")
            self._word += length // 2 if flash else length
            return bytes([cmd, OK]) + data + bytes([OK])
        if cmd == READ_SIGNATURE:
            return bytes([cmd, OK, SIGNATURE[body[4] % 3], OK])
        if cmd == READ_FUSE:
            return bytes([cmd, OK, FUSES.get(body[2] << 8 | body[3], 0xFF)
                          if body[2] == 0x50 else FUSES.get(body[2], 0xFF), OK])
        if cmd == READ_LOCK:
            return bytes([cmd, OK, LOCK, OK])
        if cmd == SPI_MULTI:  # a universal command: the signature's and fuses' reads
            rx, tx = body[2], body[4:]
            value = SIGNATURE[tx[2] % 3] if tx[:1] == b"\x30" else 0
            return bytes([cmd, OK]) + bytes([0] * (rx - 1) + [value])[:rx] + bytes([OK])
        return bytes([cmd, UNKNOWN])


def _xor(data: bytes) -> int:
    out = 0
    for b in data:
        out ^= b
    return out
