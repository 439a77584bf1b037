"""gestc preview: an animated drawing of the hand doing the gesture (Pillow)."""

from __future__ import annotations

import argparse
import sys

from ..common import EXIT_OK
from .target import add_arguments, compile_target, output_path


def run(args: argparse.Namespace) -> int:
    """Write the GIF."""
    from ...model.preview import write_gif

    compiled, plan = compile_target(args)
    out = output_path(args.output, compiled.gesture, (".gif",))
    frames, ms = write_gif(plan, compiled, out)
    print(f"wrote {out}: {frames} frames, {ms / 1000:.2f} s", file=sys.stderr)
    return EXIT_OK


def add_parser(sub: argparse._SubParsersAction) -> None:
    """``gestc preview GESTURE``."""
    p = sub.add_parser("preview", help="an animated drawing of the hand doing the gesture "
                       "(needs Pillow)")
    add_arguments(p)
    p.add_argument("-o", "--output", help="the GIF to write (default GESTURE.gif)")
    p.set_defaults(func=run)
