"""gestc compile: write a compiled gesture (JSON for the player, or a timed listing)."""

from __future__ import annotations

import argparse

from ...compiled import to_json, to_timed
from ..common import EXIT_OK, write_out
from .target import add_arguments, compile_target, output_path


def run(args: argparse.Namespace) -> int:
    """Compile the gesture and write it (``-o -``: to standard output)."""
    compiled, _ = compile_target(args)
    if args.format == "timed":
        text = to_timed(compiled.stream(args.board))
        out = output_path(args.output, compiled.gesture, (".timed",), True)
    else:
        text = to_json(compiled)
        out = output_path(args.output, compiled.gesture, (".gestc",), True)
    sizes = ", ".join(f"board {s.board}: {len(s.data):,} bytes" for s in compiled.streams)
    write_out(out, text, f": {compiled.gesture}, {compiled.duration:.2f} s, {sizes}")
    return EXIT_OK


def add_parser(sub: argparse._SubParsersAction) -> None:
    """``gestc compile GESTURE``."""
    p = sub.add_parser("compile", help="write a compiled gesture")
    add_arguments(p)
    p.add_argument("-o", "--output", help="output file, '-' for stdout "
                   "(default GESTURE.gestc, or GESTURE.timed)")
    p.add_argument("-f", "--format", choices=("gestc", "timed"), default="gestc",
                   help="gestc: JSON for the player; timed: '<seconds> <byte>' per line")
    p.add_argument("--board", type=int, help="with --format timed: the board's stream")
    p.set_defaults(func=run)
