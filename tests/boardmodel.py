"""A servo board as facts.md describes it, written for the tests from the protocol
alone (not from the encoder): bytes in, (arrival time, servo ID, value) out."""

from __future__ import annotations

CANCEL, DUMP = 255, 253


def read_stream(times, data, baud, owned=None):
    """Decode a timed byte stream the way a board reads it.

    Each byte is complete one byte-time (10 bits at ``baud``) after it starts. A
    pair is (ID, value); CANCEL drops a half-read pair; DUMP is answered, not a
    command; a value above 180 is clamped; a pair for an ID the board does not own
    is read and ignored.
    """
    tau = 10 / baud
    out = []
    pending = None
    for t, b in zip(times, data, strict=True):
        if b == CANCEL:
            pending = None
        elif b == DUMP:
            pass
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
