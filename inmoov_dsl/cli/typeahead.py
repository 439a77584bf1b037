"""What a person types while gestplay winds down is the shell's, and the terminal is
left as it was found.

After a Ctrl-C at a terminal gestplay waits a moment for a second one (it relaxes the
hand). A thread may be reading the terminal then (the repl's line editor, which also
turned echo and line mode off): keys typed meanwhile would go to it, and be lost when
gestplay exits. ``release`` puts the terminal's modes back without dropping what is
typed, and points standard input at an empty pipe, so nothing in this process reads
the terminal again: what is typed waits there for the shell, as type-ahead does.
"""

from __future__ import annotations

import contextlib
import os

#: the terminal's modes (termios attributes), as ``termios.tcgetattr`` gives them
Modes = list


def modes() -> Modes | None:
    """The modes of the terminal on standard input, to put back with ``release``; None
    when standard input is not a terminal (or the system has no termios)."""
    try:
        import termios
    except ImportError:  # Windows
        return None
    try:
        return termios.tcgetattr(0)
    except (termios.error, OSError, ValueError):
        return None


def release(saved: Modes | None) -> None:
    """Leave the terminal to the shell: its modes back to ``saved`` (now, keeping what is
    typed), and no thread of this process reading it any more. Nothing when ``saved``
    is None."""
    if saved is None:
        return
    import termios

    with contextlib.suppress(termios.error, OSError):  # a terminal that hung up
        termios.tcsetattr(0, termios.TCSANOW, saved)
    empty, _never_written = os.pipe()  # the write end stays open: a read waits forever
    os.dup2(empty, 0)
    os.close(empty)
