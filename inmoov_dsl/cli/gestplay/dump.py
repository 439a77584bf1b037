"""gestplay dump: ask the boards their IDs and every servo's value."""

from __future__ import annotations

import argparse

from ...boards import controller
from ...errors import Diagnostic, GestError
from ...hardware import Board, Profile
from ...profiles.profile import load_profile
from ...wire.link import every_board, named_boards, open_board, parse_ports
from ...wire.ready import ask_dump, wait_ready
from ..common import EXIT_OK, add_ports, note
from . import PROG


def run(args: argparse.Namespace) -> int:
    """One port: print the first of the profile's boards that answers DUMP on it. A
    port per board (``BOARD=PORT``, ``left=COM3,right=COM4``, or a bare ``sim://`` for
    every board): each board's."""
    profile = load_profile(args.profile or "rhand")
    named = named_boards(args.port, profile)  # read as play reads them (wire/link.py)
    if len(args.port) == 1 and not named and not every_board(args.port[0]):
        _dump(args.port[0], open_board(args.port[0], profile), profile, profile.boards)
        return EXIT_OK
    ports = parse_ports(args.port, profile, named or None)
    for board in (b for b in profile.boards if b.id in ports):
        _dump(ports[board.id], open_board(ports[board.id], profile, board), profile, (board,))
    return EXIT_OK


def _dump(name: str, port, profile: Profile, boards: tuple[Board, ...]) -> None:
    """Print the first of ``boards`` that answers DUMP on ``port``, and close it."""
    try:
        kinds = {b.id: controller(profile, b) for b in boards}
        first = kinds[boards[0].id]
        wait_ready(port, controller=first, say=lambda text: note(f"{name}: {text}", PROG))
        found = ((b, ask_dump(port, b.id, controller=kinds[b.id])) for b in boards)
        b, values = next(((b, v) for b, v in found if v is not None), (None, None))
        if values is None:
            raise GestError(Diagnostic("error", f"no {first.pose_reply} from {name}",
                                       hint=first.unheard))
        names = {s.id: s.name for s in profile.servos}
        print(f"board {b.id} ({b.name}): {len(values)} servos")
        for sid, value in values.items():
            print(f"  {names.get(sid, f'servo {sid}'):<10} id {sid:>3}  value {value:>3}")
    finally:
        port.close()


def add_parser(sub: argparse._SubParsersAction) -> None:
    """``gestplay dump --port PORT``."""
    p = sub.add_parser("dump", help="the boards' IDs and every servo's value")
    add_ports(p, more="; a bare sim:// is every board")
    p.add_argument("-p", "--profile", help="to name the servos (default rhand)")
    p.set_defaults(func=run)
