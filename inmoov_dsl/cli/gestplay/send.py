"""gestplay send: send raw bytes to a board and show its reply."""

from __future__ import annotations

import argparse

from ... import clock
from ...boards import controller
from ...errors import Diagnostic, GestError
from ...profiles.profile import load_profile
from ...protocol import MAX_VALUE, Signal
from ...wire.link import open_board
from ...wire.ready import drain, wait_ready
from ..common import EXIT_OK, note, number

SIGNAL_NAMES = {int(s): s.name for s in Signal}
SIGNAL_BYTES = {s.name.lower(): int(s) for s in Signal}


def to_bytes(words: list[str]) -> bytes:
    """Numbers 0..255 and signal names (cancel, dump...) as bytes."""
    data = []
    for word in words:
        number = int(word) if word.isascii() and word.isdigit() else -1
        value = SIGNAL_BYTES.get(word.lower(), number)
        if not 0 <= value <= 255:
            raise GestError(Diagnostic("error", f"'{word}' is not a byte",
                                       hint="give numbers 0..255 or signal names "
                                       "(cancel, dump, ...)"))
        data.append(value)
    return bytes(data)


def shown(reply: bytes) -> str:
    """A reply as numbers, its signals by name."""
    return " ".join(SIGNAL_NAMES.get(b, str(b)) if b > MAX_VALUE else str(b) for b in reply)


def run(args: argparse.Namespace) -> int:
    """Send the bytes once the board is ready; print what comes back in --listen s."""
    data = to_bytes(args.bytes)
    profile = load_profile(args.profile or "rhand")
    port = open_board(args.port, profile)
    board = profile.boards[0]
    try:  # an Uno or Nano resets when its port opens; another kind answers its probe
        wait_ready(port, controller=controller(profile, board),
                   say=lambda text: note(f"{args.port}: {text}", "gestplay"))
        port.write(data)
        clock.sleep(args.listen)
        reply = drain(port)
    finally:
        port.close()
    print(shown(reply))
    return EXIT_OK


def add_parser(sub: argparse._SubParsersAction) -> None:
    """``gestplay send --port PORT BYTE...``."""
    p = sub.add_parser("send", help="send raw bytes and show the reply")
    p.add_argument("--port", required=True)
    p.add_argument("-p", "--profile", help="for the baud (default rhand)")
    p.add_argument("--listen", type=number(0, 60), default=0.3,
                   help="seconds to wait for a reply (default 0.3)")
    p.add_argument("bytes", nargs="+", metavar="BYTE",
                   help="0..255, or a signal name: cancel, dump, relax")
    p.set_defaults(func=run)
