"""gestplay: play gestures on the hand, and the bench tools.

``gestplay GESTURE`` plays a gesture; ``gestplay play NAME`` plays one whatever its
name (a gesture called ``dump``, say); ``gestplay TOOL`` runs a bench tool. Every
subcommand is a module of this package with ``add_parser(sub)``.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Collection

from ..common import add_version, parse_args, run
from . import calibrate, dump, play, ports, relax, repl, send, teach

PROG = "gestplay"
TOOLS = (play, ports, dump, send, relax, calibrate, repl, teach)  #: each with add_parser


def parser() -> tuple[argparse.ArgumentParser, Collection[str]]:
    """gestplay's arguments (a tool and its arguments: ``play`` for a gesture), and the
    tools' names."""
    ap = argparse.ArgumentParser(
        prog=PROG, usage="%(prog)s GESTURE [options]\n       %(prog)s TOOL [options]",
        description="Play a gesture on the InMoov hand: gestplay GESTURE --port PORT "
        "(gestplay play --help for the options; gestplay play NAME plays a gesture "
        "whatever its name). The bench tools: gestplay TOOL --help.")
    add_version(ap)
    sub = ap.add_subparsers(dest="command", required=True, metavar="GESTURE|TOOL", prog=PROG)
    for module in TOOLS:
        module.add_parser(sub)
    return ap, sub.choices


def playing_by_default(argv: list[str], tools: Collection[str]) -> list[str]:
    """``gestplay GESTURE ...`` is ``gestplay play GESTURE ...``: a first word that is
    neither an option nor a tool is the gesture."""
    if argv and argv[0] not in tools and not argv[0].startswith("-"):
        return ["play", *argv]
    return argv


def main(argv: list[str] | None = None) -> int:
    """The console script."""
    ap, tools = parser()
    args = parse_args(ap, playing_by_default(sys.argv[1:] if argv is None else argv, tools))
    return run(PROG, lambda: args.func(args))


if __name__ == "__main__":
    sys.exit(main())
