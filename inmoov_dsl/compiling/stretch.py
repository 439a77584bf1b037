"""The words of a stretched move's warning: said once per place, with how many times
the gesture plays it."""

from __future__ import annotations

STRETCH_HINT = ("the profile's limits allow no faster move; ask for more time or raise "
                "the limits")


TIMES = " ({} times)"  #: after a warning whose place the gesture plays more than once


def without_count(message: str) -> str:
    """``message`` without the `` (3 times)`` a plan adds when it plays the warning's
    place more than once: what the warning says of its place, whichever gesture plays
    it (``gestc check`` tells each place once)."""
    head, times, tail = message.rpartition(" (")
    return head if times and tail.endswith(" times)") and tail[:-7].isdigit() else message


def stretch_message(needed: float, asked: float) -> str:
    """``move stretched: needs 0.52 s, asked 0.40 s``, with as many decimals as it takes
    (up to six) for the two numbers to differ."""
    digits = 2
    while digits < 6 and f"{needed:.{digits}f}" == f"{asked:.{digits}f}":
        digits += 1
    return f"move stretched: needs {needed:.{digits}f} s, asked {asked:.{digits}f} s"
