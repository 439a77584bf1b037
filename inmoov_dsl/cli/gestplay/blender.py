"""gestplay blender: Blender Servo Animation's live mode moves the robot. Point the
add-on's live mode (method: Web Socket) at ``ws://127.0.0.1:PORT/``; as the artist
scrubs or plays, each servo's position goes through the drive loop (the limits shape
every move, the collision check refuses one into the body, Ctrl-C leaves the hand
holding its pose). The add-on's servo IDs are the servos' places on the board (pins or
channels; ``--board`` for a robot of several), or a map's (``--map``)."""

from __future__ import annotations

import argparse
import importlib.util
import sys

from ...errors import Diagnostic, GestError
from ...interchange import UNITS
from ...live.drive import Drive, library_program
from ...profiles.profile import load_profile
from .. import hand
from ..common import EXIT_OK, add_allow_contact, add_blind, add_ports, guard_for, warn
from ..options import http_address
from .puppet import Shown, Told
from .serve import add_token, token_for

PROG = "gestplay blender"
DEFAULT_LISTEN = "127.0.0.1:8765"


def run(args: argparse.Namespace) -> int:
    """Listen for Blender's commands and drive the hand with them until Ctrl-C."""
    from ...interchange.frames import place, tick_us
    from ...live.blender import Listener, reading
    from ...live.puppet import Puppet
    from ..gestc.export import boards_named
    from ..gestc.imports import read_ids

    if importlib.util.find_spec("aiohttp") is None:
        raise GestError(Diagnostic("error", "Blender's live mode needs aiohttp, which is not "
                                   "installed", hint="pip install 'inmoov-dsl[serve]'"))
    profile = load_profile(args.profile)
    boards = boards_named(profile, args.board)
    if args.map:
        ids = {k: profile.servos[profile.index(n)] for k, n in
               read_ids(args.map, profile).items()}
    else:
        if len(boards) > 1:
            names = ", ".join(f"{b.id} ({b.name})" for b in boards)
            raise GestError(Diagnostic("error", f"profile '{profile.name}' has boards "
                                       f"{names}: whose pins are Blender's servo IDs?",
                                       hint=f"--board {boards[0].id}, or --map ids.toml"))
        on = [profile.servos[profile.index(n)] for n in boards[0].servos]
        ids = {place(s): s for s in on}
    host, port = args.listen
    token = token_for(args, host, "Blender's live mode")
    guard = guard_for(profile, args.allow_contact, PROG)
    read = reading(ids, args.units, tick_us(profile, boards[0]),
                   lambda sid: warn(f"Blender sent servo ID {sid}, which is no servo here "
                                    f"(IDs {', '.join(map(str, sorted(ids)))}): left out",
                                    PROG))
    listener, shown = Listener(host, port, token), Shown()
    puppet = Puppet(listener, read, profile, shown)
    try:
        with hand.opened(PROG, profile, args.port, args.blind) as opened:
            print(f"{PROG}: Blender's live mode (Web Socket) to ws://{host}:{listener.port}/ "
                  f"drives {profile.name}{'; Ctrl-C stops' if sys.stdin.isatty() else ''}",
                  file=sys.stderr, flush=True)
            Drive(opened.links, profile, opened.pose, library_program([]), Told(PROG),
                  guard=guard.plan).run(puppet)
    finally:
        listener.close()
        shown.end()
    print(f"{PROG}: {len(puppet.samples):,} positions, {puppet.moves:,} moves",
          file=sys.stderr)
    return EXIT_OK


def add_parser(sub: argparse._SubParsersAction) -> None:
    """``gestplay blender --listen HOST:PORT --port PORT``."""
    p = sub.add_parser("blender", help="Blender Servo Animation's live mode drives the "
                       "robot (its Web Socket method)", description=__doc__)
    p.add_argument("--listen", type=http_address, default=http_address(DEFAULT_LISTEN),
                   metavar="HOST:PORT", help=f"where the add-on connects (default "
                   f"{DEFAULT_LISTEN}: this computer only; another address needs a token, "
                   "given in the add-on's path as /?token=TOKEN)")
    add_token(p)
    add_ports(p, "as for playing")
    p.add_argument("-p", "--profile", default="rhand", help="robot profile (default rhand)")
    p.add_argument("--board", help="the board whose pins are Blender's servo IDs (its ID or "
                   "name)")
    p.add_argument("--map", metavar="IDS.toml", help="Blender's servo IDs to servos, when "
                   "they are not the servos' pins: [ids] with 0 = \"index\"")
    p.add_argument("--units", choices=UNITS, default="us",
                   help="what the add-on's positions are (its bones' position range; "
                   "default us)")
    add_blind(p)
    add_allow_contact(p)
    p.set_defaults(func=run)
