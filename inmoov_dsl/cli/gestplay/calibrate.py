"""gestplay calibrate: find a servo's straight and curled angles with the arrow keys,
and write them into the profile."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ...board import BoardServo
from ...calibrate import edit_profile, found
from ...errors import Diagnostic, GestError, did_you_mean
from ...player import ask_dump, wait_ready
from ...ports import open_port
from ...profile import Servo, find_profile, load_profile, parse_profile
from ...protocol import MAX_VALUE, Signal
from ...resources import profiles_dir
from ...urlhandler import protocol_sim
from ..common import EXIT_OK, send_value, status_line, status_of, warn, why
from ..keys import key_reader

PROG = "gestplay calibrate"
HELP = """\
Move the servo until the finger is straight, press s; until it is curled, press c.
  left/right  -1/+1      down/up  -10/+10
  s  mark straight       c  mark curled
  Enter  write both into the profile      q or Esc  leave without writing"""
STEPS = {"left": -1, "right": 1, "down": -10, "up": 10, "pagedown": -30, "pageup": 30}


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
    port = open_port(protocol_sim.complete(args.port, profile, board.id), board.baud)
    try:
        wait_ready(port)
        values = ask_dump(port, board.id)
        if values is None or servo.id not in values:
            warn(f"no DUMP reply from board {board.id}: starting at the rest value "
                 f"{servo.rest}", PROG)
        value = values.get(servo.id, servo.rest) if values else servo.rest
        marks: dict[str, int] = {}
        with key_reader() as keys:
            print(HELP)
            send_value(port, servo.id, value)
            _show(servo.name, value, mapping, marks)
            for key in keys:
                if key in STEPS:
                    value = max(0, min(MAX_VALUE, value + STEPS[key]))
                    send_value(port, servo.id, value)
                elif key in ("s", "c"):
                    marks["straight" if key == "s" else "curled"] = mapping.angle(value)
                elif key == "enter":
                    if len(marks) == 2:
                        break
                    print(f"\n{PROG}: mark both ends first (s and c)", file=sys.stderr)
                elif key in ("q", "esc"):
                    print(f"\n{PROG}: nothing written")
                    return EXIT_OK
                _show(servo.name, value, mapping, marks)
            else:
                print(f"\n{PROG}: input ended: nothing written")
                return EXIT_OK
    except KeyboardInterrupt as exc:
        port.write(bytes([Signal.CANCEL]))
        print(f"\n{PROG}: {why(exc)}: nothing written", file=sys.stderr)
        return status_of(exc)
    finally:
        port.close()
    _write(source, output, servo, marks)
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


def _show(name: str, value: int, mapping: BoardServo, marks: dict[str, int]) -> None:
    mark = "  ".join(f"{k} {v}" for k, v in marks.items()) or "no ends marked"
    status_line(f"{name}: value {value:>3}  angle {mapping.angle(value):>3}  |  {mark}")


def add_parser(sub: argparse._SubParsersAction) -> None:
    """``gestplay calibrate --port PORT --servo NAME``."""
    p = sub.add_parser("calibrate", help="find a servo's ends with the arrow keys and "
                       "write them into the profile", description=HELP,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--port", required=True)
    p.add_argument("--servo", required=True, help="the servo's name in the profile")
    p.add_argument("-p", "--profile", help="profile name or file (default rhand); a file "
                   "is edited in place, a built-in profile is copied to ./NAME.toml")
    p.add_argument("-o", "--output", help="write the edited profile here instead")
    p.add_argument("--full-range", action="store_true",
                   help="the board maps 0..180 straight onto servo angles (a calibration "
                   "sketch), not through the profile's calibration")
    p.set_defaults(func=run)
