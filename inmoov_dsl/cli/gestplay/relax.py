"""gestplay relax: the servos stop holding (they go limp) until the next command."""

from __future__ import annotations

import argparse

from ...profiles.profile import load_profile
from ...wire.player import relax_all
from ...wire.ready import drain
from .. import hand
from ..common import EXIT_OK, add_blind, add_ports

PROG = "gestplay"


def run(args: argparse.Namespace) -> int:
    """Every board of the profile stops driving its servos until its next command."""
    profile = load_profile(args.profile or "rhand")
    with hand.opened(PROG, profile, args.port, args.blind, "relaxing it anyway") as on:
        relax_all(on.links)
        for link in on.links:
            drain(link.port)  # a pulled cable says so here
            print(f"board {link.board} on {link.name}: relaxed, its servos are limp until "
                  f"the next command")
    return EXIT_OK


def add_parser(sub: argparse._SubParsersAction) -> None:
    """``gestplay relax --port PORT``."""
    p = sub.add_parser("relax", help="the servos stop holding (they go limp) until the "
                       "next command")
    add_ports(p)
    p.add_argument("-p", "--profile", help="robot profile (default rhand)")
    add_blind(p)
    p.set_defaults(func=run)
