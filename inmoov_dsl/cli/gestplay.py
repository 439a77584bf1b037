"""gestplay: play gestures on the hand (the player arrives with issue 3)."""

from __future__ import annotations

import argparse
import sys

from .common import EXIT_USAGE

PROG = "gestplay"


def parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(
        prog=PROG, description="Play a gesture on the InMoov hand over a serial port. "
        "Not implemented yet in this version: compile with 'gestc compile' meanwhile.")
    ap.add_argument("target", metavar="GESTURE",
                    help="a library gesture, a .gest file or a compiled .gestc file")
    ap.add_argument("--port", help="COM3, /dev/ttyUSB0, a pyserial URL, or sim://")
    return ap


def main(argv: list[str] | None = None) -> int:
    parser().parse_args(argv)
    print(f"{PROG}: error: playing is not implemented in this version yet; "
          f"'gestc compile' writes the stream", file=sys.stderr)
    return EXIT_USAGE


if __name__ == "__main__":
    sys.exit(main())
