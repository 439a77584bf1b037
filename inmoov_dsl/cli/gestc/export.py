"""gestc export: joint positions over time, for a ROS (URDF) model."""

from __future__ import annotations

import argparse

from ..common import EXIT_OK, number, write_out
from .target import add_arguments, compile_target


def run(args: argparse.Namespace) -> int:
    """Write the joint states as CSV (``-``: to standard output)."""
    from ...model.export import joint_states, to_csv

    compiled, plan = compile_target(args)
    text = to_csv(*joint_states(plan, compiled, 1 / args.rate))
    write_out(args.joint_states, text, f": {text.count(chr(10)) - 1} rows")
    return EXIT_OK


def add_parser(sub: argparse._SubParsersAction) -> None:
    """``gestc export GESTURE --joint-states CSV``."""
    p = sub.add_parser("export", help="joint positions over time for a ROS (URDF) model")
    add_arguments(p)
    p.add_argument("--joint-states", required=True, metavar="CSV",
                   help="the CSV file to write ('-' for standard output): time, then "
                   "each joint in radians")
    p.add_argument("--rate", type=number(0, 1000, above=True), default=50.0,
                   help="rows per second (default 50: one per servo frame)")
    p.set_defaults(func=run)
