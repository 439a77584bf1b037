"""``--store``, ``--on-boot``, ``--button``, ``--idle``: the gestures a board keeps in
its flash, for ``gestc firmware``, ``gestc upload`` and ``gestsim``; compiled, checked
to fit, before anything is built."""

from __future__ import annotations

import argparse
import sys

from ...boards import arduino
from ...compiling.compiler import compile_program, pick_gesture, plan_checks
from ...errors import Diagnostic, GestError
from ...firmware.store import Request, parse_pin, room, stored_gesture
from ...firmware.store import stored_set as make_set
from ...hardware import Board, Profile
from ...language.library import find_gesture, library_dirs, scan_library
from ...language.load import load
from ...language.program import Program
from ...model import collisions
from ...wire.stored import DEFAULT_IDLE_AFTER, StoredSet
from ..common import number, report

ALL = "all"  #: ``--store all``: every library gesture that plays on the board


def add_store_options(p: argparse.ArgumentParser, what: str = "the image") -> None:
    """The options that choose the gestures a board stores, and what starts them."""
    p.add_argument("--store", action="append", default=[], metavar="GESTURE,...",
                   help=f"store these gestures in {what}'s flash, numbered 0, 1, ... in this "
                   "order (library names, .gest files: all of a file's gestures, "
                   "FILE.gest:NAME: one of them; 'all': every library gesture for the "
                   "board); the board plays them itself; every option names a stored "
                   "gesture the same way")
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


def request(args: argparse.Namespace, board: Board) -> Request:
    """What the options ask for, by gesture name (a button's pin as ``board``'s
    Arduino names it: A0 is 14 on an Uno, 54 on a Mega)."""
    names = tuple(n.strip() for spec in args.store for n in spec.split(",") if n.strip())
    buttons, written = [], []
    for spec in args.button:
        pin, sep, gesture = spec.partition("=")
        if not sep or not gesture.strip():
            raise GestError(Diagnostic("error", f"--button {spec}: expected PIN=GESTURE",
                                       hint="--button D8=wave"))
        buttons.append((parse_pin(pin, arduino.of(board.options)[3]), gesture.strip()))
        written.append((buttons[-1][0], pin.strip()))
    return Request(names, args.on_boot, args.idle, args.idle_after, tuple(buttons),
                   tuple(written))


def stored_sets(args: argparse.Namespace, profile: Profile, board: Board, prog: str
                ) -> dict[int, StoredSet]:
    """Board ID -> the gestures the options store in ``board`` (none asked: empty),
    compiled for ``profile`` and checked to fit; what is stored is said on stderr."""
    if not wants_store(args):
        return {}
    asked = request(args, board)
    dirs = library_dirs(args.lib)
    found = _Found(dirs, prog)
    for ref in asked.names:  # --store's first: the triggers may name their files' gestures
        for name in _all(profile, board, dirs) if ref == ALL else [ref]:
            found.add(name, store=True)
    for ref in dict.fromkeys([asked.boot, asked.idle, *(g for _, g in asked.buttons)]):
        if ref is not None:  # a trigger's gesture: stored too, after --store's
            found.add(ref)
    gestures = []
    for path, name in found.order:
        with plan_checks(collisions):  # a board plays what it stores with no host to ask
            compiled, _ = compile_program(found.programs[path], name, profile)
        report(compiled.warnings, prog)
        gestures.append(stored_gesture(compiled, profile, board))
    named = {ref: found.refs[ref, False][0][1] for ref, store in found.refs if not store}
    asked = Request(tuple(name for _, name in found.order), named.get(asked.boot),
                    named.get(asked.idle), asked.idle_after,
                    tuple((p, named[g]) for p, g in asked.buttons), asked.written)
    flash = make_set(gestures, asked, profile, board)
    size = len(flash.to_bytes())
    print(f"{prog}: board {board.id} stores {len(gestures)} gesture"
          f"{'s' if len(gestures) != 1 else ''} in {size:,} bytes of flash (of the "
          f"{room(board)[0]:,} it has for them)", file=sys.stderr)
    return {board.id: flash}


class _Found:
    """The gestures the options name, each option's words read the same way: a gesture's
    name (one of the files given to --store, else the library's), a .gest file (every
    gesture it defines, for --store; its only one, or the one named like it, elsewhere)
    or FILE.gest:NAME (that gesture of the file)."""

    def __init__(self, dirs, prog: str):
        self.dirs, self.prog = dirs, prog
        self.programs: dict[str, Program] = {}  #: path -> its program
        #: (words, for --store) -> their (path, gesture)s
        self.refs: dict[tuple[str, bool], list[tuple[str, str]]] = {}
        self.order: list[tuple[str, str]] = []  #: what is stored, numbered in this order

    def add(self, ref: str, store: bool = False) -> None:
        """Store what ``ref`` names (``store``: all the gestures of a file)."""
        if (ref, store) not in self.refs:
            self.refs[ref, store] = self._resolve(ref, store)
        for path, name in self.refs[ref, store]:
            clash = next((p for p, n in self.order if n == name and p != path), None)
            if clash is not None:
                raise GestError(Diagnostic(
                    "error", f"two gestures named '{name}' to store: in {clash} and {path}",
                    hint="a board names its gestures: rename one"))
            if (path, name) not in self.order:
                self.order.append((path, name))

    def _resolve(self, ref: str, store: bool) -> list[tuple[str, str]]:
        file, sep, name = ref.rpartition(":")
        if sep and file.endswith(".gest"):
            program = self._load(find_gesture(file, None, self.dirs, self._warn)[0])
            return [(program.root, pick_gesture(program, name))]
        for path, program in self.programs.items():  # a gesture of a file given to --store
            if ref in program.own:
                return [(path, ref)]
        path, picked = find_gesture(ref, None, self.dirs, self._warn)
        program = self._load(path)
        if store and picked is None and len(program.own) > 1:
            return [(path, name) for name in program.own]
        try:
            return [(path, pick_gesture(program, picked))]
        except GestError as exc:
            if len(program.own) < 2:
                raise
            raise GestError(Diagnostic("error", exc.first.message, hint=f"name one: {ref}:"
                                       f"{program.own[0]}, or store them all: --store "
                                       f"{ref}")) from None

    def _load(self, path: str) -> Program:
        if path not in self.programs:
            self.programs[path] = load(path, search=self.dirs)
        return self.programs[path]

    def _warn(self, diagnostic: Diagnostic) -> None:
        report([diagnostic], self.prog)


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
