"""gestc urdf: the robot's model, for rviz, robot_state_publisher or a browser view."""

from __future__ import annotations

import argparse

from ...profiles.profile import load_profile
from ..common import EXIT_OK, write_out


def run(args: argparse.Namespace) -> int:
    """Write the URDF of the profile's robot (``-o``: to a file)."""
    from ...model.urdf import model

    write_out(args.output, model(load_profile(args.profile)))
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
