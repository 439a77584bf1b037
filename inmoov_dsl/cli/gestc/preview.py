"""gestc preview: an animated drawing of the gesture (Pillow): the hand of a hand
profile, the whole robot in 3-D on a profile with arms, a head or a torso; with
``--live``, a page on this computer that follows the file as it is saved: the robot in
3-D, the gesture's timeline, its steps (``views.livepage``)."""

from __future__ import annotations

import argparse
import sys

from ..common import EXIT_OK
from ..options import http_address
from .target import add_arguments, compile_target, output_path


def run(args: argparse.Namespace) -> int:
    """Write the GIF, or serve the live page."""
    if args.live:
        from .preview_live import live

        return live(args)
    from ...views.film import write_gif

    compiled, plan = compile_target(args)
    out = output_path(args.output, compiled.gesture, (".gif",))
    frames, ms = write_gif(plan, compiled, out)
    print(f"wrote {out}: {frames} frames, {ms / 1000:.2f} s", file=sys.stderr)
    return EXIT_OK


def add_parser(sub: argparse._SubParsersAction) -> None:
    """``gestc preview GESTURE``."""
    p = sub.add_parser("preview", help="an animated drawing of the gesture: the hand, or "
                       "the whole robot in 3-D (needs Pillow); --live: a page that follows "
                       "the file as it changes (needs the web extra)")
    add_arguments(p)
    p.add_argument("-o", "--output", help="the GIF to write (default GESTURE.gif)")
    live = p.add_argument_group("the live page (--live)")
    live.add_argument("--live", action="store_true",
                      help="serve a page on 127.0.0.1 that shows FILE's gesture (--gesture, "
                      "else its first) as the file is saved: the robot in 3-D, the "
                      "timeline, the steps; Ctrl-C stops")
    live.add_argument("--http", type=http_address, default=("127.0.0.1", 0),
                      metavar="PORT", help="the page's port (default 0: any free one); "
                      "127.0.0.1 only")
    live.add_argument("--no-open", action="store_true",
                      help="do not open the page in a browser (print its address only)")
    live.add_argument("--serve", metavar="URL",
                      help="a running gestplay serve (http://127.0.0.1:8180): the page's "
                      "'Play on the robot' button plays the gesture there")
    live.add_argument("--token", help="the token that gestplay serve asks for")
    p.set_defaults(func=run)
