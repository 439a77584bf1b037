"""The original firmware's servo board as facts.md describes it (measured in simavr),
written for the tests from the protocol alone (not from the encoder, nor from our
board): bytes in, (arrival time, servo ID, value) out."""

from __future__ import annotations

CANCEL, DUMP = 255, 253


def read_stream(times, data, baud, owned=None):
    """Decode a timed byte stream the way the original board reads it.

    Each byte is complete one byte-time (10 bits at ``baud``) after it starts. A
    pair is (ID, value); CANCEL and DUMP drop a half-read pair (DUMP is answered);
    any other byte is an ID where an ID is expected and a value where a value is,
    clamped to 180; a pair for an ID the board does not own is read and ignored.
    """
    tau = 10 / baud
    out = []
    pending = None
    for t, b in zip(times, data, strict=True):
        if b in (CANCEL, DUMP):
            pending = None
        elif pending is None:
            pending = b
        else:
            if owned is None or pending in owned:
                out.append((t + tau, pending, min(b, 180)))
            pending = None
    return out


def final_values(events, start):
    """Each servo ID's last value, starting from ``start`` (ID -> value)."""
    held = dict(start)
    for _, sid, value in events:
        held[sid] = value
    return held
