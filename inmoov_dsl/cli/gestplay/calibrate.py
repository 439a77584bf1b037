"""gestplay calibrate: find a servo's straight and curled angles with the bench tools'
keys (``keymap``, as in gestplay teach), and write them into the profile."""

from __future__ import annotations

import argparse
import sys
from dataclasses import replace
from pathlib import Path

from ...boards import Controller, controller
from ...boards.rig.core import BoardServo
from ...errors import Diagnostic, GestError, did_you_mean
from ...hardware import Board, Profile, Servo
from ...live.calibrate import HELP, Ends, edit_profile, found
from ...profiles.profile import find_profile, load_profile, parse_profile
from ...protocol import CANCEL_PENDING, MAX_VALUE
from ...resources import profiles_dir
from ...wire.link import open_board
from ...wire.ready import ask_dump, wait_ready
from ..common import EXIT_OK, note, send_value, status_line, status_of, warn, why
from ..keys import key_reader

PROG = "gestplay calibrate"


def _kind(profile: Profile, servo: Servo, board: Board, full_range: bool
          ) -> Controller | None:
    """The board as its kind drives it (None: a rig, whose firmware maps the values); a
    Maestro's or a PCA9685's servo with ``full_range`` is driven as if its calibration
    were 0..180, so that a value is the servo's angle."""
    if controller(profile, board).ours:
        return None
    if full_range:
        plain = replace(servo, calibration=(0, MAX_VALUE), reversed=False, pulse=None)
        profile = replace(profile, servos=tuple(plain if s.name == servo.name else s
                                                for s in profile.servos))
    return controller(profile, board)


def run(args: argparse.Namespace) -> int:
    """Calibrate one servo at the keyboard and write the result into the profile."""
    source = find_profile(args.profile or "rhand")
    profile = load_profile(str(source))
    if args.servo not in profile.names:
        raise GestError(Diagnostic("error", f"profile '{profile.name}' has no servo "
                                   f"'{args.servo}'", hint=did_you_mean(args.servo,
                                                                         profile.names)))
    servo = profile.servos[profile.index(args.servo)]
    board = next(b for b in profile.boards if b.id == servo.board)
    output = Path(args.output) if args.output else _output(source, profile.name)
    # how the board maps values to angles while we calibrate
    mapping = BoardServo(servo.id) if args.full_range else \
        BoardServo(servo.id, servo.calibration, servo.reversed)
    kind = _kind(profile, servo, board, args.full_range)
    port = open_board(args.port, profile, board)
    try:
        heard = bytearray()
        if wait_ready(port, controller=kind, heard=heard, say=lambda text: note(
                f"{args.port}: {text}", PROG)) and kind is not None:
            port.write(kind.setup(bytes(heard)))
        values = ask_dump(port, board.id, controller=kind)
        if values is None or servo.id not in values:
            warn(f"no {controller(profile, board).pose_reply} from board {board.id}: "
                 f"starting at the rest value {servo.rest}", PROG)
        ends = Ends(servo.name, values.get(servo.id, servo.rest) if values else servo.rest,
                    mapping.angle)
        with key_reader() as keys:
            print(HELP)
            send_value(port, servo.id, ends.value, kind)
            status_line(ends.line())
            for key in keys:
                action = ends.press(key)
                if action == "send":
                    send_value(port, servo.id, ends.value, kind)
                elif action == "save":
                    break
                elif action == "quit":
                    print(f"\n{PROG}: nothing written")
                    return EXIT_OK
                status_line(ends.line())
            else:
                print(f"\n{PROG}: input ended: nothing written")
                return EXIT_OK
    except KeyboardInterrupt as exc:
        port.write(kind.cancel() if kind else CANCEL_PENDING)
        print(f"\n{PROG}: {why(exc)}: nothing written", file=sys.stderr)
        return status_of(exc)
    finally:
        port.close()
    _write(source, output, servo, ends.marks())
    return EXIT_OK


def _write(source: Path, output: Path, servo: Servo, marks: dict[str, int]) -> None:
    """The marked ends as the servo's calibration, in ``source``'s text written to
    ``output``; a profile that would not load is never written."""
    new = found(servo, marks["straight"], marks["curled"])
    edited = edit_profile(source.read_text(encoding="utf-8"), servo.name, new)
    parse_profile(edited, str(output))
    output.write_text(edited, encoding="utf-8")
    print(f"\n{servo.name}: calibration {list(new.calibration)}, reversed "
          f"{str(new.reversed).lower()}, limits rescaled to the new range; written to "
          f"{output}")
    if output != source:
        print(f"use it with --profile {output}")


def _output(source: Path, name: str) -> Path:
    """A user's own profile is edited in place; a built-in one is copied here first."""
    try:
        source.resolve().relative_to(profiles_dir().resolve())
    except ValueError:
        return source
    return Path.cwd() / f"{name}.toml"


def add_parser(sub: argparse._SubParsersAction) -> None:
    """``gestplay calibrate --port PORT --servo NAME``."""
    p = sub.add_parser("calibrate", help="find a servo's ends from the keyboard and "
                       "write them into the profile", description=HELP,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--port", required=True)
    p.add_argument("--servo", required=True, help="the servo's name in the profile")
    p.add_argument("-p", "--profile", help="profile name or file (default rhand); a file "
                   "is edited in place, a built-in profile is copied to ./NAME.toml")
    p.add_argument("-o", "--output", help="write the edited profile here instead")
    p.add_argument("--full-range", action="store_true",
                   help=f"the board maps 0..{MAX_VALUE} straight onto servo angles (a "
                   "calibration sketch), not through the profile's calibration")
    p.set_defaults(func=run)
