"""gestc urdf: the robot's model, for rviz, robot_state_publisher or a browser view."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ...profile import load_profile
from ..common import EXIT_OK


def run(args: argparse.Namespace) -> int:
    """Write the URDF of the profile's robot (``-o``: to a file)."""
    from ...urdf import model

    text = model(load_profile(args.profile))
    if args.output in (None, "-"):
        sys.stdout.write(text)
    else:
        Path(args.output).write_text(text, encoding="utf-8")
        print(f"wrote {args.output}", file=sys.stderr)
    return EXIT_OK


def add_parser(sub: argparse._SubParsersAction) -> None:
    """``gestc urdf [--profile NAME] [-o FILE]``."""
    p = sub.add_parser("urdf", help="the robot's URDF model (joints and limits from the "
                       "profile)")
    p.add_argument("-p", "--profile", default="rhand",
                   help="robot profile: a built-in name or a .toml file (default rhand)")
    p.add_argument("-o", "--output", metavar="FILE",
                   help="the .urdf file to write (default: standard output)")
    p.set_defaults(func=run)
