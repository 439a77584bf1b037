"""gestc upload: build boards' firmware from their profile and flash it (avrdude)."""

from __future__ import annotations

import argparse
import shlex
import sys
import tempfile
from dataclasses import replace
from pathlib import Path

from ...errors import Diagnostic, GestError
from ...firmware.upload import Loader
from ...hardware import Profile
from ...profiles.profile import load_profile
from ..common import EXIT_OK, report
from .firmware import BAUDS
from .target import PROG


def run(args: argparse.Namespace) -> int:
    """Build boards' firmware from their profile and flash it through the bootloader."""
    from ...firmware.upload import build, loader
    from .storing import one_board, stored_sets, wants_store

    profile, names = _boards(args.profile, args.board)
    targets = [args.board] if args.board else list(names)
    ports = upload_ports(args.port, profile, targets, names)
    if args.hex and len(targets) > 1:
        raise GestError(Diagnostic("error", "--hex is one board's firmware",
                                   hint="name the board: gestc upload BOARD --hex FILE"))
    if args.hex and wants_store(args):
        raise GestError(Diagnostic("error", "--hex flashes an image built elsewhere: its "
                                   "stored gestures are the ones it was built with",
                                   hint="leave out --hex to build one with --store"))
    check_ports([ports[name] for name in targets], args.dry_run)
    stored = stored_sets(args, profile, one_board(profile, args.board, PROG), PROG) \
        if wants_store(args) else {}
    boots = {name: loader(profile, names[name], args.old_bootloader) for name in targets}
    if args.dry_run:
        print("\n".join(dry_run(args, profile, targets, ports, boots)))
    elif args.hex:
        _flash({targets[0]: Path(args.hex)}, ports, boots, args)
    elif args.build_dir:
        _flash(build(profile, targets, Path(args.build_dir), args.baud, stored), ports,
               boots, args)
    else:
        with tempfile.TemporaryDirectory(prefix="inmoov-upload-") as tmp:
            _flash(build(profile, targets, Path(tmp), args.baud, stored), ports, boots, args)
    return EXIT_OK


def check_ports(ports: list[str], dry_run: bool) -> None:
    """Each port avrdude will open is there, before anything is built: the message
    every command gives for that port name (``ports.not_found``). With ``--dry-run``,
    which flashes nothing, a warning."""
    from ...wire.ports import device_problem

    for port in ports:
        problem = device_problem(port)
        if problem is not None and not dry_run:
            raise GestError(problem)
        if problem is not None:
            report([replace(problem, severity="warning")], PROG)


def dry_run(args: argparse.Namespace, profile: Profile, targets: list[str],
            ports: dict[str, str], boots: dict[str, Loader]) -> list[str]:
    """The commands that do what ``gestc upload`` would, to run as they are: write the
    sketchbook (``--build-dir``, default ./firmware, which stays), build it, flash
    each board; with ``--hex``, only the flashing."""
    from ...firmware.upload import avrdude_command

    if args.hex:
        hexes = {targets[0]: Path(args.hex)}
        lines = []
    else:
        where = Path(args.build_dir or "firmware")
        hexes = {name: where / "build" / f"{name}.hex" for name in targets}
        baud_option = ["--baud", str(args.baud)] if args.baud else []
        lines = [shlex.join([PROG, "firmware", args.profile or profile.name, "-o",
                             str(where), *baud_option, *store_options(args)]),
                 shlex.join(["make", "-C", str(where), *targets])]
    return lines + [shlex.join(avrdude_command(hexes[name], ports[name], boots[name],
                                               args.avrdude, args.avrdude_option))
                    for name in targets]


def store_options(args: argparse.Namespace) -> list[str]:
    """The ``gestc firmware`` options that store what ``args`` asks to store."""
    out = [f"--store={','.join(args.store)}"] if args.store else []
    out += [f"--on-boot={args.on_boot}"] if args.on_boot else []
    out += [f"--button={b}" for b in args.button]
    out += [f"--idle={args.idle}", f"--idle-after={args.idle_after}"] if args.idle else []
    out += [f"--lib={d}" for d in args.lib]
    if out and args.board:
        out.append(f"--board={args.board}")
    return out


def _flash(hexes: dict[str, Path], ports: dict[str, str], boots: dict[str, Loader],
           args: argparse.Namespace) -> None:
    """Flash each board its .hex, saying what goes where."""
    from ...firmware.upload import flash, read_hex

    for name, hex_file in hexes.items():
        size = len(read_hex(hex_file))
        print(f"{PROG}: flashing {name} ({size:,} bytes) through the bootloader on "
              f"{ports[name]} at {boots[name].baud} baud", file=sys.stderr, flush=True)
        flash(hex_file, ports[name], boots[name], args.avrdude, args.avrdude_option)
        print(f"{PROG}: uploaded {name} to {ports[name]}", file=sys.stderr)


def _boards(profile_name: str | None, board: str | None) -> tuple[Profile, dict[str, int]]:
    """The profile to build from, and its sketches (name -> board ID)."""
    from ...firmware.sketches import sketch_names
    from ...firmware.upload import find_sketch

    if profile_name:
        profile = load_profile(profile_name)
        names = sketch_names(profile)
        if board and board not in names:
            raise GestError(Diagnostic("error", f"profile '{profile.name}' has no board "
                                       f"'{board}'", hint=f"its boards: {', '.join(names)}"))
        return profile, names
    if board:
        profile = find_sketch(board)
        return profile, sketch_names(profile)
    raise GestError(Diagnostic("error", "which board?", hint="name one (gestc upload "
                               "servo_rhand --port COM3), or give --profile for all "
                               "of a profile's"))


def upload_ports(specs: list[str], profile: Profile, targets: list[str],
                 names: dict[str, int]) -> dict[str, str]:
    """Sketch name -> its port: ``--port COM3`` for one board, ``--port NAME=PORT`` or
    ``--port ID=PORT`` for each (``link.board_ports``)."""
    from ...wire.link import board_ports

    by_id = {i: n for n, i in names.items()}
    ports = board_ports(specs, profile, [names[n] for n in targets], by_id)
    return {by_id[i]: port for i, port in ports.items()}


def add_parser(sub: argparse._SubParsersAction) -> None:
    """``gestc upload BOARD --port PORT``."""
    p = sub.add_parser("upload", help="build a board's firmware and flash it (avrdude)")
    p.add_argument("board", nargs="?", metavar="BOARD",
                   help="a sketch name: servo_rhand, glove_rhand, servo_inmoov_left... "
                   "(default with --profile: every board of the profile)")
    p.add_argument("--port", action="append", required=True, metavar="PORT",
                   help="the board's port; with several boards, one per board, by its "
                   "sketch name, its name or its ID: right=COM3,left=COM4 (or --port "
                   "servo_inmoov_right=COM3 --port servo_inmoov_left=COM4)")
    p.add_argument("-p", "--profile", help="the profile the boards are built from (a "
                   "built-in name or a .toml path; default: the one with BOARD)")
    p.add_argument("--old-bootloader", action="store_true",
                   help="a Nano with the old bootloader (57600 baud instead of 115200; a "
                   "Mega's speaks STK500v2 at 115200, which its profile says)")
    p.add_argument("--baud", type=int, choices=BAUDS,
                   help="the link speed the firmware will use (default: the profile's)")
    p.add_argument("--hex", metavar="FILE",
                   help="flash this .hex (built in the Arduino IDE, say) instead of building")
    p.add_argument("--build-dir", metavar="DIR",
                   help="build in this sketchbook and keep it (default: a temporary one, "
                   "removed after)")
    p.add_argument("--dry-run", action="store_true",
                   help="print the commands that do it, to run as they are (the sketchbook "
                   "in --build-dir, default ./firmware); build and flash nothing")
    p.add_argument("--avrdude", default="avrdude", metavar="PATH",
                   help="the avrdude to run (default: avrdude on the PATH)")
    p.add_argument("--avrdude-option", action="append", default=[], metavar="ARG",
                   help="pass ARG to avrdude (e.g. -v, or -x attempts=1); may be repeated")
    from .storing import add_store_options

    add_store_options(p, "the board")
    p.set_defaults(func=run)
