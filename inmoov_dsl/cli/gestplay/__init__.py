"""gestplay: play gestures on the hand, and the bench tools.

``gestplay GESTURE`` plays a gesture; ``gestplay play NAME`` plays one whatever its
name (a gesture called ``dump``, say); ``gestplay TOOL`` runs a bench tool. Every
subcommand is a module of this package with ``add_parser(sub)``; a command line that
names its tool imports that tool's module alone.
"""

from __future__ import annotations

import argparse
import importlib
import sys

from ..common import add_version, parse_args, run
from ..options import Commands

PROG = "gestplay"
#: each tool (``play`` for a gesture) -> its module, in the order ``--help`` lists them
TOOLS = {"play": "play", "ports": "ports", "dump": "dump", "send": "send", "relax": "relax",
         "calibrate": "calibrate", "repl": "repl", "teach": "teach", "serve": "serve",
         "stored": "stored", "puppet": "puppet", "blender": "blender"}


def parser(tool: str | None = None) -> argparse.ArgumentParser:
    """gestplay's arguments (a tool and its arguments: ``play`` for a gesture); only
    ``tool``'s, when given."""
    ap = argparse.ArgumentParser(
        prog=PROG, usage="%(prog)s GESTURE [options]\n       %(prog)s TOOL [options]",
        description="Play a gesture on the InMoov hand: gestplay GESTURE --port PORT "
        "(gestplay play --help for the options; gestplay play NAME plays a gesture "
        "whatever its name). The bench tools: gestplay TOOL --help.")
    add_version(ap)
    sub = ap.add_subparsers(dest="command", required=True, metavar="GESTURE|TOOL", prog=PROG,
                         action=Commands)
    for name in [tool] if tool in TOOLS else TOOLS:
        importlib.import_module(f".{TOOLS[name]}", __name__).add_parser(sub)
    return ap


def playing_by_default(argv: list[str]) -> list[str]:
    """``gestplay GESTURE ...`` is ``gestplay play GESTURE ...``: a first word that is
    neither an option nor a tool is the gesture."""
    if argv and argv[0] not in TOOLS and not argv[0].startswith("-"):
        return ["play", *argv]
    return argv


def main(argv: list[str] | None = None) -> int:
    """The console script."""
    argv = playing_by_default(sys.argv[1:] if argv is None else argv)
    args = parse_args(parser(argv[0] if argv else None), argv)
    return run(PROG, lambda: args.func(args))


if __name__ == "__main__":
    sys.exit(main())
