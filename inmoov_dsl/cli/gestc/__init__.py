"""gestc: compile, check, show and list gestures, and build and flash the firmware.

Every subcommand is a module of this package with ``add_parser(sub)``; the heavy
libraries (matplotlib, Pillow, the metrics) are imported when a command runs.
"""

from __future__ import annotations

import argparse
import sys

from ..common import add_version, parse_args, run
from . import check, export, firmware, fmt, listing, plot, preview, record, show, upload, urdf
from . import compile as compile_cmd
from .target import PROG


def parser() -> argparse.ArgumentParser:
    """gestc's arguments: a command and its own."""
    ap = argparse.ArgumentParser(
        prog=PROG, description="Compile .gest gestures into timed byte streams for the "
        "InMoov servo boards.")
    add_version(ap)
    sub = ap.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for module in (compile_cmd, check, show, plot, preview, export, urdf, fmt, firmware, upload,
                   record, listing):
        module.add_parser(sub)
    return ap


def main(argv: list[str] | None = None) -> int:
    """The console script."""
    args = parse_args(parser(), argv)
    return run(PROG, lambda: args.func(args))


if __name__ == "__main__":
    sys.exit(main())
