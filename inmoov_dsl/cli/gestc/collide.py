"""gestc collide: which pairs of the robot's parts are checked against each other,
and the file that keeps the pairs never checked beside the profile (docs/collisions.md)."""

from __future__ import annotations

import argparse
import sys
from collections import Counter

from ...errors import Diagnostic, GestError
from ...profiles.profile import load_profile
from ..common import EXIT_OK


def run(args: argparse.Namespace) -> int:
    """Say what is checked; with ``--write``, make the allowed pairs again and keep them
    (``-o``: in that file; by default beside the profile)."""
    from ...model import allowed

    profile = load_profile(args.profile)
    path = args.output or allowed.path_for(profile)
    if args.write:
        if path is None:
            raise GestError(Diagnostic("error", f"profile '{profile.name}' has no file to keep "
                                       "its pairs beside", hint="-o FILE"))
        made = allowed.allowed_pairs(profile)
        try:
            allowed.save(made, path)
        except OSError as exc:
            raise GestError(Diagnostic("error", f"cannot write {path}: {exc.strerror or exc}",
                                       hint="-o FILE: somewhere you may write")) from None
        print(f"wrote {path}", file=sys.stderr)
    else:
        made = allowed.allowed_for(profile)
    from ...model.collide import checker_for

    checker = checker_for(profile)
    why = Counter(made.pairs.values())
    print(f"{profile.name}: {len(checker.pairs) if checker else 0} pairs of parts checked, "
          f"closer than {profile.clearance_mm:g} mm is touching; never checked: "
          + ", ".join(f"{n} {reason}" for reason, n in sorted(why.items())))
    if checker is None:
        print("nothing to check: the robot's parts cannot meet (a hand alone)")
    return EXIT_OK


def add_parser(sub: argparse._SubParsersAction) -> None:
    """``gestc collide [--profile NAME] [--write] [-o FILE]``."""
    p = sub.add_parser("collide", help="which of the robot's parts are checked against "
                       "each other (needs python-fcl)")
    p.add_argument("-p", "--profile", default="inmoov",
                   help="robot profile: a built-in name or a .toml file (default inmoov)")
    p.add_argument("--write", action="store_true",
                   help="make the pairs never checked again (10,000 random poses) and keep "
                   "them beside the profile, as NAME.collisions.json")
    p.add_argument("-o", "--output", metavar="FILE", help="keep them in FILE instead")
    p.set_defaults(func=run)
