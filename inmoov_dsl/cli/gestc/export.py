"""gestc export: a gesture for another tool: Blender Servo Animation's JSON or Arduino
header, Bottango's curve commands, a CSV of the servos' values, or joint states for a
ROS (URDF) model."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ...compiling.compiled import Compiled
from ...compiling.plan import Plan
from ...errors import Diagnostic, GestError
from ...hardware import Board, Profile
from ...interchange import SUFFIXES, UNITS
from ..common import EXIT_OK, number, write_out
from .target import add_arguments, compile_target

PER_BOARD = ("bsa-json", "bsa-h", "bottango")  #: formats that address one board's servos


def run(args: argparse.Namespace) -> int:
    """Write the gesture in ``--format`` (``-o -``: to standard output)."""
    if args.joint_states is not None:
        print("gestc export: --joint-states is now --format joint-states -o CSV (it still "
              "works)", file=sys.stderr)
        args.format, args.output = "joint-states", args.joint_states
    if args.format is None:
        raise GestError(Diagnostic("error", "which format? --format " + "|".join(SUFFIXES),
                                   hint="gestc export wave --format bsa-json -o wave.json"))
    compiled, plan = compile_target(args)
    output = args.output or f"{compiled.gesture}{SUFFIXES[args.format]}"
    if args.format not in PER_BOARD:
        text = _whole(args, plan, compiled)
        write_out(output, text, f": {text.count(chr(10)) - 1} rows")
        return EXIT_OK
    boards = boards_named(plan.profile, args.board)
    for board in boards:
        path = output if len(boards) == 1 or output == "-" else \
            str(Path(output).with_name(f"{Path(output).stem}-{board_slug(board)}"
                                       f"{Path(output).suffix}"))
        text, about = _one_board(args, plan, compiled, board)
        write_out(path, text, about)
    return EXIT_OK


def _whole(args: argparse.Namespace, plan: Plan, compiled: Compiled) -> str:
    """The CSV formats, the whole robot in one table."""
    if args.format == "csv":
        from ...interchange.table import write
        return write(plan, args.fps)
    from ...model.export import joint_states, to_csv
    return to_csv(*joint_states(plan, compiled, 1 / args.fps))


def _one_board(args: argparse.Namespace, plan: Plan, compiled: Compiled, board: Board
               ) -> tuple[str, str]:
    """(the file, what to say of it) for one board."""
    from ...interchange import bottango, bsa
    from ...interchange.frames import board_frames, tick_us, to_units

    frames = board_frames(plan, board, args.fps)
    if args.format == "bottango":
        lines = [bottango.setup(s, plan.start[plan.profile.index(s.name)]).line()
                 for s in frames.servos]
        found = [c for s in frames.servos for c in bottango.curves(
            s, plan.tracks[plan.profile.index(s.name)], compiled.duration)]
        lines += [c.line() for c in found]
        return "\n".join(lines) + "\n", f": {len(frames.servos)} servos, {len(found)} curves"
    units = to_units(frames.widths, args.units, tick_us(plan.profile, board))
    file = Path(args.target).name if args.target.endswith(".gest") else args.target
    found = bsa.positions(frames, units, safe=args.format == "bsa-h")
    about = f": {len(found)} frames at {args.fps:g} fps, {len(frames.servos)} servos " \
        f"(IDs {', '.join(map(str, frames.places))}) in {args.units}"
    if args.format == "bsa-json":
        return bsa.to_json(frames, found, file, compiled.gesture) + "\n", about
    return bsa.to_header(frames, bsa.commands(found), file, compiled.gesture), about


def boards_named(profile: Profile, chosen: str | None) -> list[Board]:
    """The board ``--board`` names (its ID or name), or every board of the profile."""
    if chosen is None:
        return list(profile.boards)
    for board in profile.boards:
        if chosen in (str(board.id), board.name):
            return [board]
    names = ", ".join(f"{b.id} ({b.name})" for b in profile.boards)
    raise GestError(Diagnostic("error", f"--board {chosen}: profile '{profile.name}' has "
                               f"boards {names}", hint=f"--board {profile.boards[0].id}"))


def board_slug(board: Board) -> str:
    """A board's name as a file's name ends with it (``right``)."""
    return "".join(c if c.isalnum() else "-" for c in board.name.lower()).strip("-") or \
        str(board.id)


def add_parser(sub: argparse._SubParsersAction) -> None:
    """``gestc export GESTURE --format F -o OUT``."""
    p = sub.add_parser("export", help="a gesture for another tool: Blender Servo "
                       "Animation, Bottango, a CSV, ROS joint states")
    add_arguments(p)
    p.add_argument("--format", choices=list(SUFFIXES),
                   help="bsa-json, bsa-h: Blender Servo Animation's JSON or Arduino header; "
                   "bottango: its curve commands; csv: time and each servo's value; "
                   "joint-states: each joint in radians")
    p.add_argument("-o", "--output", metavar="OUT", help="the file to write ('-': standard "
                   "output; default GESTURE and the format's suffix); for a robot of several "
                   "boards, a file a board named OUT-BOARD unless --board")
    p.add_argument("--board", help="the board whose servos to write (its ID or name)")
    p.add_argument("--fps", type=number(0, 1000, above=True), default=50.0,
                   help="frames (rows) per second (default 50: one per servo frame)")
    p.add_argument("--rate", dest="fps", type=number(0, 1000, above=True),
                   help=argparse.SUPPRESS)  # joint states' name for it
    p.add_argument("--units", choices=UNITS, default="us",
                   help="Blender Servo Animation's positions: pulse widths in us (default), "
                   "the Servo library's degrees, or PCA9685 ticks")
    p.add_argument("--joint-states", metavar="CSV", help=argparse.SUPPRESS)
    p.set_defaults(func=run)
