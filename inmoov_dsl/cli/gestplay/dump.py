"""gestplay dump: ask a board its ID and every servo's value."""

from __future__ import annotations

import argparse

from ...errors import Diagnostic, GestError
from ...player import ask_dump, wait_ready
from ...profile import load_profile
from ..common import EXIT_OK
from ..hand import open_first


def run(args: argparse.Namespace) -> int:
    """Print the first of the profile's boards that answers DUMP on the port."""
    profile = load_profile(args.profile or "rhand")
    port = open_first(args.port, profile)
    try:
        wait_ready(port)
        found = ((b, ask_dump(port, b.id)) for b in profile.boards)
        b, values = next(((b, v) for b, v in found if v is not None), (None, None))
        if values is None:
            raise GestError(Diagnostic("error", f"no DUMP reply from {args.port}",
                                       hint="is the board powered, and at this baud?"))
        names = {s.id: s.name for s in profile.servos}
        print(f"board {b.id} ({b.name}): {len(values)} servos")
        for sid, value in values.items():
            print(f"  {names.get(sid, f'servo {sid}'):<10} id {sid:>3}  value {value:>3}")
    finally:
        port.close()
    return EXIT_OK


def add_parser(sub: argparse._SubParsersAction) -> None:
    """``gestplay dump --port PORT``."""
    p = sub.add_parser("dump", help="a board's ID and every servo's value")
    p.add_argument("--port", required=True)
    p.add_argument("-p", "--profile", help="to name the servos (default rhand)")
    p.set_defaults(func=run)
