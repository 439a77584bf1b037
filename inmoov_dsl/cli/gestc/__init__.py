"""gestc: compile, check, show and list gestures, and build and flash the firmware.

Every subcommand is a module of this package with ``add_parser(sub)``; the heavy
libraries (matplotlib, Pillow, the metrics) are imported when a command runs, and a
command line that names its command imports that command's module alone (start-up
time: ``benchmarks/cli_startup.py``).
"""

from __future__ import annotations

import argparse
import importlib
import sys

from ..common import add_version, parse_args, run
from ..options import Commands

PROG = "gestc"  #: (the commands' modules, imported when named, are the heavy part)

#: each command -> its module, in the order ``gestc --help`` lists them
COMMANDS = {"compile": "compile", "check": "check", "show": "show", "plot": "plot",
            "preview": "preview", "export": "export", "import": "imports", "urdf": "urdf",
            "collide": "collide", "fmt": "fmt",
            "firmware": "firmware", "upload": "upload", "record": "record", "list": "listing",
            "lsp": "lsp"}


def parser(command: str | None = None) -> argparse.ArgumentParser:
    """gestc's arguments: a command and its own (only ``command``'s, when given)."""
    ap = argparse.ArgumentParser(
        prog=PROG, description="Compile .gest gestures into timed byte streams for the "
        "InMoov servo boards.")
    add_version(ap)
    sub = ap.add_subparsers(dest="command", required=True, metavar="COMMAND", action=Commands)
    for name in [command] if command in COMMANDS else COMMANDS:
        importlib.import_module(f".{COMMANDS[name]}", __name__).add_parser(sub)
    return ap


def main(argv: list[str] | None = None) -> int:
    """The console script."""
    argv = sys.argv[1:] if argv is None else argv
    args = parse_args(parser(argv[0] if argv else None), argv)
    return run(PROG, lambda: args.func(args))


if __name__ == "__main__":
    sys.exit(main())
