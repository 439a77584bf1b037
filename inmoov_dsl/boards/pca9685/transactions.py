"""A PCA9685's bus transactions as a stream of bytes: how the plan's writes are timed,
queued and read back like any board's commands (one framing, used by the encoder, the
I2C port and the model).

``W reg n data*n``: a block write of n bytes (at most 32, what ``smbus2`` carries) from
register ``reg``; ``R reg n``: read n bytes from ``reg`` (the answer: those bytes).
"""

from __future__ import annotations

from collections.abc import Iterator

from ..frames import split

WRITE, READ = 0x57, 0x52  #: "W", "R"
MOST = 32  #: bytes a block write carries


def write(register: int, data: bytes) -> bytes:
    """Block writes of ``data`` from ``register``, 32 bytes at most each."""
    out = bytearray()
    for k in range(0, len(data), MOST):
        chunk = data[k:k + MOST]
        out += bytes([WRITE, register + k, len(chunk)]) + chunk
    return bytes(out)


def read(register: int, count: int) -> bytes:
    """A read of ``count`` bytes from ``register``."""
    return bytes([READ, register, count])


def length(data: bytes, i: int) -> int:
    """The bytes the transaction at ``data[i]`` takes (what there is of one cut short)."""
    n = 3 + data[i + 2] if data[i] == WRITE and i + 2 < len(data) else 3
    return min(n, len(data) - i)


def commands(data: bytes) -> list[tuple[int, int]]:
    """(first, end) index of each transaction of ``data``."""
    return split(data, length)


def parse(data: bytes) -> Iterator[tuple[int, int, bytes | int]]:
    """(kind, register, data written or count read) of each whole transaction."""
    for first, stop in commands(data):
        t = data[first:stop]
        if len(t) < 3 or t[0] not in (WRITE, READ):
            continue
        if t[0] == WRITE and len(t) == 3 + t[2] and t[2] <= MOST:
            yield WRITE, t[1], bytes(t[3:])
        elif t[0] == READ:
            yield READ, t[1], t[2]


def fault(data: bytes) -> str | None:
    """What in ``data`` is not a whole transaction, or None."""
    for first, stop in commands(data):
        t = data[first:stop]
        if t[0] not in (WRITE, READ):
            return f"byte {first}: {t[0]} starts no transaction"
        if len(t) < 3 or (t[0] == WRITE and (len(t) != 3 + t[2] or t[2] > MOST)):
            return f"byte {first}: a transaction cut short"
    return None


def channels(data: bytes) -> set[int]:
    """The LED channels whose registers the writes of ``data`` touch."""
    found = set()
    for kind, register, written in parse(data):
        if kind == WRITE:
            found |= {(r - 6) // 4 for r in range(register, register + len(written))
                      if 6 <= r < 6 + 4 * 16}
    return found
