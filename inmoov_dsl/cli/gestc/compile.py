"""gestc compile: write a compiled gesture (JSON for the player, or a timed listing)."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from ...compiling.compiled import to_json, to_timed
from ...errors import counted
from ..common import EXIT_OK, write_out
from .target import add_arguments, compile_target, output_path

if TYPE_CHECKING:
    from ...compiling.compiled import Compiled


def run(args: argparse.Namespace) -> int:
    """Compile the gesture and write it (``-o -``: to standard output)."""
    compiled, _ = compile_target(args)
    if args.format == "timed":
        text = to_timed(compiled.stream(args.board))
        out = output_path(args.output, compiled.gesture, (".timed",), True)
    else:
        text = to_json(compiled)
        out = output_path(args.output, compiled.gesture, (".gestc",), True)
    write_out(out, text, f": {compiled.gesture}, {compiled.duration:.2f} s, "
              f"{sizes(compiled)}")
    return EXIT_OK


def sizes(compiled: Compiled) -> str:
    """Each board's bytes, and which boards the gesture leaves idle (sent CANCEL only):
    ``board 181: 1,029 bytes, board 186: 1,323 bytes; boards 183, 185 idle``."""
    still = [s.board for s in compiled.streams if s.idle]
    text = ", ".join(f"board {s.board}: {counted(len(s.data), 'byte')}"
                     for s in compiled.streams if s.board not in still)
    if not still:
        return text
    idle_text = f"board{'s' if len(still) > 1 else ''} {', '.join(map(str, still))} idle"
    return f"{text}; {idle_text}" if text else idle_text


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
