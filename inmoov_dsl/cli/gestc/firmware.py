"""gestc firmware: write the Arduino sketch of every board of a profile."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ...profiles.profile import load_profile
from ...protocol import DEFAULT_BAUD
from ..common import EXIT_ERROR, EXIT_OK

PROG = "gestc"

BAUDS = (DEFAULT_BAUD, 19200, 38400, 57600, 115200)  #: the link speeds a sketch may use


def run(args: argparse.Namespace) -> int:
    """Write (or, with --check, compare) the sketch folders of a profile's boards."""
    from ...firmware.upload import stale_files, write_sketchbook
    from .storing import one_board, stored_sets, wants_store

    profile = load_profile(args.profile_name)
    out = Path(args.output)
    stored = stored_sets(args, profile, one_board(profile, args.board, PROG), PROG) \
        if wants_store(args) else {}
    if args.check:
        stale = stale_files(profile, out, args.baud, stored)
        for path in stale:
            print(f"{path}: out of date (gestc firmware {args.profile_name} -o {out})")
        return EXIT_ERROR if stale else EXIT_OK
    for path in write_sketchbook(profile, out, args.baud, stored):
        print(f"{'removed' if not path.exists() else 'wrote'} {path}", file=sys.stderr)
    print(f"{out}: {profile.name}'s sketches are up to date; build them with make -C {out}",
          file=sys.stderr)
    return EXIT_OK


def add_parser(sub: argparse._SubParsersAction) -> None:
    """``gestc firmware PROFILE``."""
    p = sub.add_parser("firmware", help="write the Arduino sketch of every board of a profile")
    p.add_argument("profile_name", metavar="PROFILE", help="a built-in name or a .toml path")
    p.add_argument("-o", "--output", default="firmware",
                   help="the sketchbook to write into (default ./firmware)")
    p.add_argument("--baud", type=int, choices=BAUDS,
                   help="the boards' link speed (default: the profile's)")
    p.add_argument("--check", action="store_true",
                   help="change nothing; list the files that are out of date, exit 1 if any")
    p.add_argument("--board", metavar="SKETCH", help="with --store and a profile of several "
                   "servo boards: the one that stores the gestures (servo_inmoov_head...)")
    from .storing import add_store_options

    add_store_options(p, "the servo board")
    p.set_defaults(func=run)
