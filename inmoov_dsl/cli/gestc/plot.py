"""gestc plot: draw each servo's planned motion and the values sent (matplotlib)."""

from __future__ import annotations

import argparse
import sys

from ..common import EXIT_OK
from .target import add_arguments, compile_target, output_path


def run(args: argparse.Namespace) -> int:
    """Write the figure (.png, .svg or .pdf)."""
    from ...model.guard import marks
    from ...views.plot import plot

    compiled, plan = compile_target(args)
    out = output_path(args.output, compiled.gesture, (".png", ".svg", ".pdf"))
    plot(plan, compiled, out, marks(plan) or [])  # where the robot meets itself, marked
    print(f"wrote {out}", file=sys.stderr)
    return EXIT_OK


def add_parser(sub: argparse._SubParsersAction) -> None:
    """``gestc plot GESTURE``."""
    p = sub.add_parser("plot", help="draw each servo's planned motion and the values sent "
                       "(needs matplotlib)")
    add_arguments(p)
    p.add_argument("-o", "--output", help="image file: .png, .svg or .pdf "
                   "(default GESTURE.png)")
    p.set_defaults(func=run)
