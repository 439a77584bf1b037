"""gestc import: another tool's animation (Blender Servo Animation's JSON or header,
Bottango's curve commands, a CSV of ours) as a short gesture, reduced by the recorder
that records a glove or a MIDI take."""

from __future__ import annotations

import argparse
from pathlib import Path

from ...errors import Diagnostic, GestError
from ...interchange import FORMATS_IN, UNITS
from ..common import EXIT_OK, gesture_name, number, warn

PROG = "gestc import"


def run(args: argparse.Namespace) -> int:
    """Read each of ``args.files`` (a board's each), map its servos, reduce them together
    into one gesture, write ``--output``."""
    from ...profiles.profile import load_profile
    from .record import write_take

    profile = load_profile(args.profile)
    ids = read_ids(args.map, profile) if args.map else None
    if len(args.files) > 1 and (args.board or ids is not None):
        raise GestError(Diagnostic("error", "--board and --map are for one file; files of "
                                   "several boards are named FILE-BOARD, as gestc export "
                                   "writes them", hint="gestc import hello-right.json "
                                   "hello-left.json -p inmoov -o hello.gest"))
    samples, formats = [], []
    for file in args.files:
        got, fmt = _one_file(args, profile, file, ids)
        samples += got
        formats.append(fmt)
    samples.sort(key=lambda s: s[0])
    name = gesture_name(args.name, args.output)
    files = ", ".join(Path(f).name for f in args.files)
    write_take(samples, profile, args.output, name, args.tolerance,
               f"from {files} ({', '.join(dict.fromkeys(formats))})", prog=PROG)
    return EXIT_OK


def _one_file(args: argparse.Namespace, profile, file: str, ids: dict[int, str] | None
              ) -> tuple[list[tuple[float, int, int]], str]:
    """One file's samples, and its format; its board: ``--board``, the one its name
    ends with (``-right``), or the profile's only one."""
    from ...interchange import importing
    from ...interchange.frames import tick_us
    from ...language.load import read_text
    from .export import board_slug, boards_named

    text = read_text(file)
    fmt = args.format or importing.detect(file, text)
    boards = boards_named(profile, args.board)
    if len(boards) > 1:
        stem = Path(file).stem.lower()
        boards = [b for b in boards if stem.endswith("-" + board_slug(b))] or boards
    if ids is None and len(boards) > 1 and fmt != "csv":
        names = ", ".join(f"{b.id} ({b.name})" for b in boards)
        raise GestError(Diagnostic("error", f"{file}: profile '{profile.name}' has boards "
                                   f"{names}: whose pins are the animation's IDs?",
                                   hint=f"--board {boards[0].id}, or name the file "
                                   f"NAME-{board_slug(boards[0])}, or --map ids.toml"))
    animation = importing.read(text, file, fmt, args.units, tick_us(profile, boards[0]))
    samples, told = importing.samples(animation, profile, boards[0], ids, file)
    for line in told:
        warn(line, PROG)
    return samples, fmt


def read_ids(path: str, profile) -> dict[int, str]:
    """A map's ``[ids]``: the animation's servo ID -> a servo of the profile."""
    from ...language.load import read_text
    from ...profiles import fields as check
    from ...profiles.keys import Report
    from ...profiles.profile import read_toml

    text = read_text(path)
    data = read_toml(text, path)
    report = Report(text, path)
    check.Fields(report, (), data, ("ids",))
    table = data.get("ids")
    if not isinstance(table, dict) or not table:
        report.error(() if "ids" not in data else ("ids",), "the map has no [ids] table",
                     '[ids] with 0 = "index": the animation\'s ID 0 turns the index')
        report.stop()
    out: dict[int, str] = {}
    for key, name in table.items():
        if not key.isdigit() or int(key) > 255:
            report.error(("ids", key), f"'{key}' is not a servo ID (0..255)")
        elif not isinstance(name, str) or name not in profile.names:
            from ...errors import did_you_mean
            report.error(("ids", key), f"unknown servo {check.shown(name)}",
                         did_you_mean(str(name), profile.names) or
                         "one of " + ", ".join(profile.names[:12]))
        elif name in out.values():
            report.error(("ids", key), f"servo '{name}' is mapped twice")
        else:
            out[int(key)] = name
    report.stop()
    return out


def add_parser(sub: argparse._SubParsersAction) -> None:
    """``gestc import FILE -p PROFILE -o OUT.gest``."""
    p = sub.add_parser("import", help="another tool's animation (Blender Servo Animation, "
                       "Bottango, a CSV) as a gesture")
    p.add_argument("files", nargs="+", metavar="FILE", help="the animation: .json or .h "
                   "(Blender Servo Animation), Bottango's commands, or a .csv of gestc "
                   "export's; for a robot of several boards, a file each named FILE-BOARD")
    p.add_argument("-p", "--profile", default="rhand", help="robot profile (default rhand)")
    p.add_argument("-o", "--output", required=True, help="the .gest file to write")
    p.add_argument("--name", help="the gesture's name (default: the file's name)")
    p.add_argument("--format", choices=FORMATS_IN,
                   help="the file's format (default: by its suffix and its text)")
    p.add_argument("--board", help="the board whose pins the animation's IDs are (its ID "
                   "or name; needed for a robot of several boards)")
    p.add_argument("--map", metavar="IDS.toml", help="the animation's IDs to servos, when "
                   "they are not the servos' pins: [ids] with 0 = \"index\"")
    p.add_argument("--units", choices=UNITS, default="us",
                   help="what Blender Servo Animation's positions are (default us)")
    p.add_argument("--tolerance", type=number(0, 90, above=True),
                   help="degrees the gesture may stray from the animation (default 3)")
    p.set_defaults(func=run)
