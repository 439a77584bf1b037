"""The Pololu Maestro's serial commands, as Pololu's documentation gives them.

Compact protocol: a command byte (top bit set), then data bytes (7 bits each). The
Pololu protocol puts 0xAA and the device number first and the command byte's top bit
cleared. A target is in quarter-microseconds, sent as its low and high 7 bits
(1500 us = 6000 = ``0x70 0x2E``); 0 stops the channel's pulses.
"""

from __future__ import annotations

from collections.abc import Sequence

from ..frames import split

SET_TARGET = 0x84  #: channel, target (lo7, hi7)
SET_SPEED = 0x87  #: channel, speed (lo7, hi7): 0.25 us per 10 ms; 0 = no limit
SET_ACCELERATION = 0x89  #: channel, acceleration (lo7, hi7): 0..255; 0 = no limit
SET_PWM = 0x8A  #: (Minis) on time, period
GET_POSITION = 0x90  #: channel -> 2 bytes, little-endian: the pulse it sends now
GET_MOVING_STATE = 0x93  #: -> 1 byte: 1 while a servo is still moving to its target
SET_MULTIPLE_TARGETS = 0x9F  #: (Minis) count, first channel, count targets
GET_ERRORS = 0xA1  #: -> 2 bytes, little-endian; reading clears them
GO_HOME = 0xA2
POLOLU = 0xAA  #: then the device number and the command with its top bit cleared
DEFAULT_DEVICE = 12  #: a Maestro's device number as it leaves the factory
MINI_SSC = 0xFF  #: channel + offset, 0..254

#: data bytes after each command byte (Set Multiple Targets: 2 + 2 x its count)
DATA = {SET_TARGET: 3, SET_SPEED: 3, SET_ACCELERATION: 3, SET_PWM: 4, GET_POSITION: 1,
        GET_MOVING_STATE: 0, GET_ERRORS: 0, GO_HOME: 0, MINI_SSC: 2}
#: what each bit of the error register means (Pololu's user's guide, "Errors")
ERRORS = ("serial signal error", "serial overrun error", "serial buffer full",
          "serial CRC error", "serial protocol error", "serial timeout",
          "script stack error", "script call stack error", "script program counter error")
PROTOCOL_ERROR = 1 << 4
ERROR_BITS = (1 << len(ERRORS)) - 1  #: the bits Get Errors may answer (0x01FF)
QUARTERS = 4  #: a target's unit: a quarter of a microsecond


def seven(value: int) -> list[int]:
    """``value`` (0..16383) as its low and high 7 bits."""
    return [value & 0x7F, (value >> 7) & 0x7F]


def command(code: int, data: Sequence[int], device: int | None = None) -> bytes:
    """Command ``code`` with its data: compact, or the Pololu protocol for ``device``."""
    if device is None:
        return bytes([code, *data])
    return bytes([POLOLU, device, code & 0x7F, *data])


def set_target(channel: int, quarters: int, device: int | None = None) -> bytes:
    """Set Target: ``channel`` to ``quarters`` quarter-microseconds (0: no pulses)."""
    return command(SET_TARGET, [channel, *seven(quarters)], device)


def set_targets(first: int, quarters: Sequence[int], device: int | None = None) -> bytes:
    """Set Multiple Targets: channels ``first``.. to ``quarters``."""
    data = [len(quarters), first]
    for q in quarters:
        data += seven(q)
    return command(SET_MULTIPLE_TARGETS, data, device)


def length(data: bytes, i: int) -> int:
    """How many bytes the command starting at ``data[i]`` takes (what is there of a
    command cut short; 1 for a byte that starts none)."""
    head = 0
    code = data[i]
    if code == POLOLU:
        if i + 2 >= len(data):
            return len(data) - i
        head, code = 2, data[i + 2] | 0x80
    if code == SET_MULTIPLE_TARGETS:
        n = 2 + 2 * data[i + head + 1] if i + head + 1 < len(data) else 0
    else:
        n = DATA.get(code, 0)
    return min(len(data) - i, head + 1 + n)


def commands(data: bytes) -> list[tuple[int, int]]:
    """(first, end) index of each command of ``data``."""
    return split(data, length)


def targets(data: bytes) -> list[tuple[int, int]]:
    """(channel, quarters) of every Set Target and Set Multiple Targets of ``data``."""
    out = []
    for first, stop in commands(data):
        cmd = data[first:stop]
        if cmd[0] == POLOLU:
            cmd = bytes([cmd[2] | 0x80]) + cmd[3:]
        if cmd[0] == SET_TARGET and len(cmd) == 4:
            out.append((cmd[1], cmd[2] | cmd[3] << 7))
        elif cmd[0] == SET_MULTIPLE_TARGETS and len(cmd) >= 3:
            pairs = cmd[3:]
            out += [(cmd[2] + k, pairs[2 * k] | pairs[2 * k + 1] << 7)
                    for k in range(len(pairs) // 2)]
    return out


def describe(errors: int) -> str:
    """The error register's set bits in words."""
    found = [name for bit, name in enumerate(ERRORS) if errors >> bit & 1]
    return ", ".join(found) or f"error bits 0x{errors:04x}"


def fault(data: bytes) -> str | None:
    """What in ``data`` is not a whole command of Pololu's table (that a Maestro would
    flag as a protocol error), or None."""
    for first, stop in commands(data):
        cmd = data[first:stop]
        code = cmd[2] | 0x80 if cmd[0] == POLOLU and len(cmd) > 2 else cmd[0]
        body = cmd[3:] if cmd[0] == POLOLU else cmd[1:]
        if not cmd[0] & 0x80 or (code not in DATA and code != SET_MULTIPLE_TARGETS):
            return f"byte {first + 1}: {cmd[0]} starts no Maestro command"
        if stop - first != length(data + bytes(300), first) or any(b & 0x80 for b in body):
            return f"byte {first + 1}: a Maestro command cut short"
    return None


def channels(data: bytes) -> set[int]:
    """The channels the targets of ``data`` set."""
    return {ch for ch, _ in targets(data)}
