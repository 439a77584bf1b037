"""MyRobotLab's MrlComm messages, as its release's ``arduinoMsgs.schema`` lays them out.

A message is ``170, size, method, arguments`` (size: the bytes after it, at most 64).
Arguments: a plain byte, ``b16`` (two bytes, big-endian, signed), ``bool`` (a byte,
0 false), ``str`` and ``[]`` (a length byte, then the bytes). A method's number is the
1-based place of its line among the schema's message lines: these are the numbers of
MRLCOMM_VERSION 68 as MyRobotLab has shipped it since August 2021 (``servoAttach`` 35;
before, the same version numbered it 32).
"""

from __future__ import annotations

from collections.abc import Iterator

from ..frames import split

MAGIC = 170
MOST = 64  #: the largest size a board reads
BAUD = 115_200  #: what MrlComm runs at
VERSION = 68  #: the MRLCOMM_VERSION supported
RELEASE = "MyRobotLab 1.1 (MrlComm 68, message numbers of August 2021 and after)"
BANNER = b"MRLComm Reset." + b" " * 49  #: what a board prints as it starts

ERROR, GET_BOARD_INFO, BOARD_INFO, SOFT_RESET, ENABLE_ACK, ACK = 1, 2, 3, 7, 8, 9
DEVICE_DETACH, DEBUG = 14, 31
SERVO_ATTACH, SERVO_ATTACH_PIN, SERVO_DETACH_PIN, SERVO_SET_VELOCITY = 35, 36, 37, 38
SERVO_MOVE_TO_MICROSECONDS, SERVO_EVENT, BEGIN, SERVO_STOP = 41, 43, 58, 59
STARTED, STOPPED = 0, 1  #: a servo event's type
#: the methods a board reads (the schema's ``>`` lines); it runs any other as an
#: "unknown method N"
READS = frozenset((2, 4, 5, 6, 7, 8, 10, 12, 14, 15, 16, 17, 18, 20, 21, 22, 23, 24, 25, 26,
                   27, 28, 29, 30, 33, 34, 35, 36, 37, 38, 39, 40, 41, 42, 44, 45, 47, 48,
                   49, 51, 52, 53, 54, 55, 56, 59))

#: each modelled method's arguments, in the schema's order
ARGS: dict[int, tuple[str, ...]] = {
    ERROR: ("str",), GET_BOARD_INFO: (), SOFT_RESET: (), ENABLE_ACK: ("bool",),
    ACK: ("byte",), DEVICE_DETACH: ("byte",), DEBUG: ("str",),
    BOARD_INFO: ("byte", "byte", "b16", "b16", "byte", "[]"),
    SERVO_ATTACH: ("byte", "byte", "b16", "b16", "str"), SERVO_ATTACH_PIN: ("byte", "byte"),
    SERVO_DETACH_PIN: ("byte",), SERVO_SET_VELOCITY: ("byte", "b16"),
    SERVO_MOVE_TO_MICROSECONDS: ("byte", "b16"), SERVO_STOP: ("byte",),
    SERVO_EVENT: ("byte", "byte", "b16", "b16"), BEGIN: ("byte",),
}


def message(method: int, *args: int | bytes) -> bytes:
    """A whole message: ``method`` with ``args`` laid out by its types."""
    body = bytearray([method])
    for kind, arg in zip(ARGS[method], args, strict=True):
        if kind == "b16":
            body += (int(arg) & 0xFFFF).to_bytes(2, "big")
        elif kind in ("str", "[]"):
            body += bytes([len(arg)]) + bytes(arg)
        else:
            body.append(int(arg) & 0xFF)
    return bytes([MAGIC, len(body)]) + bytes(body)


def arguments(body: bytes) -> tuple | None:
    """The arguments of a message's body (its method first), or None when they do not
    fit its method's types (or the method is not one modelled here)."""
    kinds = ARGS.get(body[0]) if body else None
    if kinds is None:
        return None
    out: list = []
    i = 1
    for kind in kinds:
        if kind == "b16":
            if i + 2 > len(body):
                return None
            out.append(int.from_bytes(body[i:i + 2], "big", signed=True))
            i += 2
        elif kind in ("str", "[]"):
            if i >= len(body) or i + 1 + body[i] > len(body):
                return None
            out.append(bytes(body[i + 1:i + 1 + body[i]]))
            i += 1 + body[i]
        else:
            if i >= len(body):
                return None
            out.append(body[i])
            i += 1
    return tuple(out) if i == len(body) else None


def length(data: bytes, i: int) -> int:
    """The bytes the message at ``data[i]`` takes (what there is of one cut short; 1 for
    a byte that starts none)."""
    if data[i] != MAGIC or i + 1 >= len(data):
        return 1
    return min(2 + data[i + 1], len(data) - i)


def commands(data: bytes) -> list[tuple[int, int]]:
    """(first, end) index of each message of ``data``."""
    return split(data, length)


class Reader:
    """Messages from a board's bytes as they come, as MyRobotLab reads them: a byte that
    starts no message (the reset banner, noise) is skipped, a size over 64 too."""

    def __init__(self) -> None:
        self.buf = bytearray()

    def feed(self, data: bytes) -> Iterator[tuple[int, tuple]]:
        """(method, arguments) of each whole message ``data`` completes (a message whose
        arguments do not fit its method: ``(method, None)``)."""
        self.buf += data
        while self.buf:
            if self.buf[0] != MAGIC:
                del self.buf[0]
                continue
            if len(self.buf) < 2:
                return
            size = self.buf[1]
            if size == 0 or size > MOST:
                del self.buf[0]
                continue
            if len(self.buf) < 2 + size:
                return
            body = bytes(self.buf[2:2 + size])
            del self.buf[:2 + size]
            yield body[0], arguments(body)


def fault(data: bytes) -> str | None:
    """What in ``data`` is not a whole message a board reads, or None."""
    for first, stop in commands(data):
        if data[first] != MAGIC:
            return f"byte {first + 1}: {data[first]} starts no MrlComm message"
        if stop - first < 3 or stop - first != 2 + data[first + 1] or data[first + 1] > MOST:
            return f"byte {first + 1}: an MrlComm message cut short"
    return None
