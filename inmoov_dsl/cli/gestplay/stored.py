"""gestplay stored: the gestures a board keeps in its flash; and ``gestplay GESTURE
--stored``, which has the board play the one it keeps (``PLAY N``) instead of streaming
it."""

from __future__ import annotations

import argparse
from pathlib import Path

from ... import clock
from ...boards import controller
from ...errors import Diagnostic, GestError, did_you_mean
from ...profiles.profile import load_profile
from ...protocol import CANCEL_PENDING, CATALOG, PLAY, Signal, byte_time
from ...wire.player import Link
from ...wire.ready import ask_dump, drain
from ...wire.stored import Catalog, find_catalog
from .. import hand
from ..common import EXIT_OK, add_blind, add_ports

PROG = "gestplay"
QUIET = 0.5  #: s without a byte that ends the wait for a catalog
APPROACH_MAX = 15.0  #: s a board may take to bring the hand to a gesture's start


def ask_catalog(link: Link, baud: int) -> Catalog | None:
    """CANCEL PLAY CATALOG: what the board on ``link`` stores, or None if it answers
    nothing (a board built without stored gestures, or the original firmware)."""
    drain(link.port)
    link.port.write(CANCEL_PENDING + bytes([PLAY, CATALOG]))
    data = bytearray()
    last = clock.now() + 3 * byte_time(baud)
    while clock.now() < last + QUIET:
        came = drain(link.port)
        if came:
            data += came
            last = clock.now()
            found = find_catalog(bytes(data), link.board)
            if found is not None:
                return found
        clock.sleep(0.005)
    return None


def _rig_only(profile) -> None:
    """Only our firmware stores gestures: another kind of board is an error."""
    other = next((b for b in profile.boards if not controller(profile, b).ours), None)
    if other is not None:
        raise GestError(Diagnostic(
            "error", f"board {other.id} of profile '{profile.name}' is a {other.kind}: it "
            "stores no gestures of ours", hint="play them from the computer: gestplay "
            f"GESTURE --profile {profile.name} --port PORT"))


def run(args: argparse.Namespace) -> int:
    """List what each board stores: number, name, duration, what starts it."""
    profile = load_profile(args.profile or "rhand")
    _rig_only(profile)
    with hand.opened(PROG, profile, args.port, args.blind, "listing anyway") as on:
        for link in on.links:
            board = next(b for b in profile.boards if b.id == link.board)
            catalog = ask_catalog(link, board.baud)
            where = f"board {board.id} ({board.name}) on {link.name}"
            if catalog is None:
                print(f"{where}: no stored gestures")
                continue
            count = len(catalog.names)
            print(f"{where}: {count} stored gesture{'s' if count != 1 else ''}")
            print(f"  {'number':>6}  {'gesture':<16}{'duration':>9}  started by")
            for k, (name, seconds) in enumerate(zip(catalog.names, catalog.durations,
                                                    strict=True)):
                why = "; ".join(["the host", *catalog.triggers(k)])
                print(f"  {k:>6}  {name:<16}{seconds:>7.2f} s  {why}")
    return EXIT_OK


def play_stored(args: argparse.Namespace) -> int:
    """``gestplay GESTURE --stored``: the board that stores GESTURE plays it (``--loop``
    times), from wherever the hand is; Ctrl-C stops it where it is."""
    if args.dry_run or args.speed != 1 or args.hand:
        option = "--dry-run" if args.dry_run else "--speed" if args.speed != 1 else "--hand"
        raise GestError(Diagnostic("error", f"{option} is for a streamed gesture: a stored "
                                   "one plays as it was built", hint="leave out --stored"))
    name = args.gesture or (Path(args.target).stem if args.target.endswith(".gest")
                            else args.target)
    profile = load_profile(args.profile or "rhand")
    _rig_only(profile)
    if not args.port:
        raise GestError(Diagnostic("error", "no port given", hint="--port COM3, or "
                                   "--port 'sim://?flash=DIR/servo_rhand' for a virtual board"))
    with hand.opened(PROG, profile, args.port, args.blind) as on:
        link, number, catalog = _holder(on, name)
        passes = 0
        while args.loop == 0 or passes < args.loop:
            took = _play_once(link, number, catalog.durations[number])
            passes += 1
        values = ask_dump(link.port, link.board)
        times = f" {passes} times" if passes > 1 else ""
        print(f"played {name}{times} (stored gesture {number} of board {link.board}): "
              f"{took:.2f} s, the approach to its start included", flush=True)
        if values is not None and link.name.startswith("sim://"):
            from ...views.posebars import bar_lines

            names = {s.id: s.name for s in profile.servos}
            print(f"{link.name} now holds (board {link.board}):")
            print("\n".join(bar_lines([(names[i], v) for i, v in values.items()])),
                  flush=True)
    return EXIT_OK


def _holder(on: hand.Hand, name: str) -> tuple[Link, int, Catalog]:
    """The link to the board that stores ``name``, its number there, that board's
    catalog; an error naming what the boards hold if none does."""
    held: list[str] = []
    for link in on.links:
        board = next(b for b in on.profile.boards if b.id == link.board)
        catalog = ask_catalog(link, board.baud)
        if catalog is not None and name in catalog.names:
            return link, catalog.names.index(name), catalog
        held += catalog.names if catalog is not None else []
    where = ", ".join(f"board {k.board} on {k.name}" for k in on.links)
    from ...firmware.sketches import sketch_names

    sketch = next(iter(sketch_names(on.profile)))
    port = on.links[0].name
    build = (f"gestc firmware {on.profile.name} --store {name} -o DIR, then "
             f"--port 'sim://?flash=DIR/{sketch}'" if port.startswith("sim://") else
             f"gestc upload {sketch} --port {port} --store {name}")
    hint = (did_you_mean(name, held) or f"it stores: {', '.join(held)}") if held else \
        f"build it in: {build}"
    raise GestError(Diagnostic("error", f"{where} stores no gesture '{name}'" if held else
                               f"{where} stores no gestures", hint=hint))


def _play_once(link: Link, number: int, duration: float) -> float:
    """PLAY N, then wait for the WAIT the board sends when the gesture ends: the
    seconds it took."""
    drain(link.port)
    start = clock.now()
    link.port.write(bytes([PLAY, number]))
    deadline = start + duration + APPROACH_MAX
    while clock.now() < deadline:
        if Signal.WAIT in drain(link.port):
            return clock.now() - start
        clock.sleep(0.005)
    raise GestError(Diagnostic("error", f"board {link.board} on {link.name} did not say "
                               f"that stored gesture {number} ended",
                               hint="is a button or another program driving it?"))


def add_parser(sub: argparse._SubParsersAction) -> None:
    """``gestplay stored --port PORT``."""
    p = sub.add_parser("stored", help="the gestures a board keeps in its flash (gestc "
                       "upload --store), and what starts each")
    add_ports(p)
    p.add_argument("-p", "--profile", help="robot profile (default rhand)")
    add_blind(p)
    p.set_defaults(func=run)
