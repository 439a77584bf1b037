"""``--store``, ``--on-boot``, ``--button``, ``--idle``: the gestures a board keeps in
its flash, for ``gestc firmware``, ``gestc upload`` and ``gestsim``; compiled, checked
to fit, before anything is built."""

from __future__ import annotations

import argparse
import sys

from ...compiling.compiler import compile_program, pick_gesture
from ...errors import Diagnostic, GestError
from ...firmware.store import FIRMWARE_FLASH, FLASH_MAX, Request, parse_pin, stored_gesture
from ...firmware.store import stored_set as make_set
from ...language.library import find_gesture, library_dirs, scan_library
from ...language.load import load
from ...profiles.data import Board, Profile
from ...wire.stored import DEFAULT_IDLE_AFTER, StoredSet
from ..common import number, report

ALL = "all"  #: ``--store all``: every library gesture that plays on the board


def add_store_options(p: argparse.ArgumentParser, what: str = "the image") -> None:
    """The options that choose the gestures a board stores, and what starts them."""
    p.add_argument("--store", action="append", default=[], metavar="GESTURE,...",
                   help=f"store these gestures in {what}'s flash, numbered 0, 1, ... in this "
                   "order (library names or .gest files; 'all': every library gesture "
                   "for the board); the board plays them itself")
    p.add_argument("--on-boot", metavar="GESTURE", help="play it at power-up (stored too)")
    p.add_argument("--button", action="append", default=[], metavar="PIN=GESTURE",
                   help="a push button from PIN (D8, A0...) to ground plays GESTURE "
                   "(stored too); may be repeated")
    p.add_argument("--idle", metavar="GESTURE", help="play it after --idle-after seconds "
                   "without a byte from the host or another gesture, again and again")
    p.add_argument("--idle-after", type=number(1, 65535, whole=True),
                   default=DEFAULT_IDLE_AFTER, metavar="S",
                   help=f"seconds of quiet before --idle plays (default {DEFAULT_IDLE_AFTER})")
    p.add_argument("--lib", action="append", default=[], metavar="DIR",
                   help="also look for gestures in DIR")


def wants_store(args: argparse.Namespace) -> bool:
    """Does the command line ask for stored gestures?"""
    return bool(args.store or args.on_boot or args.button or args.idle)


def request(args: argparse.Namespace) -> Request:
    """What the options ask for, by gesture name."""
    names = tuple(n.strip() for spec in args.store for n in spec.split(",") if n.strip())
    buttons = []
    for spec in args.button:
        pin, sep, gesture = spec.partition("=")
        if not sep or not gesture.strip():
            raise GestError(Diagnostic("error", f"--button {spec}: expected PIN=GESTURE",
                                       hint="--button D8=wave"))
        buttons.append((parse_pin(pin), gesture.strip()))
    return Request(names, args.on_boot, args.idle, args.idle_after, tuple(buttons))


def stored_sets(args: argparse.Namespace, profile: Profile, board: Board, prog: str
                ) -> dict[int, StoredSet]:
    """Board ID -> the gestures the options store in ``board`` (none asked: empty),
    compiled for ``profile`` and checked to fit; what is stored is said on stderr."""
    if not wants_store(args):
        return {}
    asked = request(args)
    dirs = library_dirs(args.lib)
    names = []
    for name in asked.every:
        names += _all(profile, board, dirs) if name == ALL else [name]
    gestures = []
    for name in dict.fromkeys(names):
        path, picked = find_gesture(name, None, dirs, lambda d: report([d], prog))
        program = load(path, search=dirs)
        compiled, _ = compile_program(program, pick_gesture(program, picked), profile)
        report(compiled.warnings, prog)
        gestures.append(stored_gesture(compiled, profile, board))
    named = {name: g.name for name, g in zip(dict.fromkeys(names), gestures, strict=True)}
    asked = Request(tuple(named.values()), named.get(asked.boot), named.get(asked.idle),
                    asked.idle_after, tuple((p, named[g]) for p, g in asked.buttons))
    flash = make_set(gestures, asked, profile, board)
    size = len(flash.to_bytes())
    print(f"{prog}: board {board.id} stores {len(gestures)} gesture"
          f"{'s' if len(gestures) != 1 else ''} in {size:,} bytes of flash (with the "
          f"firmware about {size + FIRMWARE_FLASH:,} of {FLASH_MAX:,})", file=sys.stderr)
    return {board.id: flash}


def _all(profile: Profile, board: Board, dirs) -> list[str]:
    """Every library gesture that moves only ``board``'s servos of ``profile``."""
    out = []
    for name, entry in sorted(scan_library(dirs).items()):
        try:
            compiled, _ = compile_program(load(str(entry.path), search=dirs), name, profile)
        except GestError:
            continue  # not for this profile
        if all(s.idle or s.board == board.id for s in compiled.streams):
            out.append(name)
    return out


def one_board(profile: Profile, sketch: str | None, prog: str) -> Board:
    """The servo board that stores gestures: the one named (its sketch's name) or the
    profile's only one."""
    from ...firmware.sketches import sketch_names

    names = {n: i for n, i in sketch_names(profile).items()
             if i in {b.id for b in profile.boards}}
    if sketch is None and len(names) == 1:
        return profile.boards[0]
    if sketch in names:
        return next(b for b in profile.boards if b.id == names[sketch])
    raise GestError(Diagnostic(
        "error", f"profile '{profile.name}' has {len(names)} servo boards: which one stores "
        "the gestures?" if sketch is None else f"'{sketch}' is no servo board of profile "
        f"'{profile.name}'", hint=f"{prog} ... --board {' or '.join(names)}"))
