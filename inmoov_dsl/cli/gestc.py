"""gestc: compile, check, show and list gestures."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from ..compiled import Compiled, to_json, to_timed
from ..compiler import compile_program, load
from ..errors import Diagnostic, GestError
from ..library import Entry, find_gesture, library_dirs, scan
from ..plan import Plan
from ..profile import load_profile
from ..resolve import Program
from . import record
from .common import EXIT_ERROR, EXIT_OK, add_lib, add_version, number, parse_args, report, run

if TYPE_CHECKING:
    from .. import metrics

PROG = "gestc"


def _compile(args: argparse.Namespace) -> tuple[Compiled, Plan]:
    dirs = library_dirs(args.lib)
    path, gesture = find_gesture(args.target, args.gesture, dirs, _warn)
    return _compile_one(load(path, search=dirs), gesture, args, args.start)


def _compile_one(program: Program, gesture: str | None, args: argparse.Namespace,
                 start: str | None) -> tuple[Compiled, Plan]:
    """Compile one gesture and report its warnings; with --strict, a link that cannot
    keep up is an error too."""
    compiled, plan = compile_program(program, gesture, args.profile, start, args.strict)
    report(compiled.warnings, PROG)
    if args.strict:
        _link_keeps_up(program, compiled, plan)
    return compiled, plan


def _link_keeps_up(program: Program, compiled: Compiled, plan: Plan) -> None:
    """With --strict, a link that cannot send every value the plan needs (frame coverage
    below 100%) is an error at the gesture's name."""
    from ..metrics import measure

    node = program.gestures[compiled.gesture]
    errors = [program.sources.error(
        f"gesture '{compiled.gesture}': the link to board {r.board} carries "
        f"{100 * r.coverage:.1f}% of the values the plan needs ({r.covered:,} of "
        f"{r.needed:,} servo-frames at {r.baud} baud)", node.name.pos,
        hint="slow the moves down, stagger them, raise the baud or split the servos over "
        f"more boards; gestc show {compiled.gesture} gives the figures")
        for r in measure(plan, compiled.streams) if r.coverage < 1]
    if errors:
        raise GestError(errors)


def output_path(output: str | None, gesture: str, suffixes: tuple[str, ...],
                any_suffix: bool = False) -> str:
    """Where a command writes: ``-o FILE``; into ``-o DIR`` (an existing directory, or a
    name ending in /) as GESTURE plus the first suffix; GESTURE plus it by default.
    A file whose suffix is none of ``suffixes`` is refused unless ``any_suffix``."""
    if output is None or output == "-":
        return output or f"{gesture}{suffixes[0]}"
    path = Path(output)
    if path.is_dir() or output.endswith(("/", "\\")):
        if not path.is_dir():
            raise GestError(Diagnostic("error", f"-o {output}: no such directory",
                                       hint=f"create it first: mkdir {output}"))
        return str(path / f"{gesture}{suffixes[0]}")
    if not any_suffix and path.suffix.lower() not in suffixes:
        kinds = " or ".join(", ".join(suffixes).rsplit(", ", 1))
        raise GestError(Diagnostic("error", f"-o {output}: write a {kinds} file, or into a "
                                   f"directory", hint=f"-o {path.with_suffix(suffixes[0])}"))
    return output


def cmd_compile(args: argparse.Namespace) -> int:
    compiled, _ = _compile(args)
    if args.format == "timed":
        text = to_timed(compiled.stream(args.board))
        out = output_path(args.output, compiled.gesture, (".timed",), True)
    else:
        text = to_json(compiled)
        out = output_path(args.output, compiled.gesture, (".gestc",), True)
    if out == "-":
        sys.stdout.write(text)
        sys.stdout.flush()
        return EXIT_OK
    Path(out).write_text(text, encoding="utf-8")
    sizes = ", ".join(f"board {s.board}: {len(s.data):,} bytes" for s in compiled.streams)
    print(f"wrote {out}: {compiled.gesture}, {compiled.duration:.2f} s, {sizes}",
          file=sys.stderr)
    return EXIT_OK


def cmd_check(args: argparse.Namespace) -> int:
    status = EXIT_OK
    dirs = library_dirs(args.lib)
    for file in args.files:
        try:
            program = load(file, search=dirs)
            for name in program.own:
                _compile_one(program, name, args, None)
            count = len(program.own)
            print(f"{file}: ok ({count} gesture{'' if count == 1 else 's'})")
        except GestError as exc:
            report(exc.diagnostics, PROG)
            status = EXIT_ERROR
    return status


def cmd_show(args: argparse.Namespace) -> int:
    from ..metrics import measure

    compiled, plan = _compile(args)
    print(f"{compiled.gesture}: {compiled.duration:.3f} s on profile '{compiled.profile}'")
    print()
    print(f"  {'#':>3}  {'step':<24} {'source':<18} {'kind':<5} {'start':>7} {'end':>7} "
          f"{'asked':>7} {'planned':>7}")
    for n, s in enumerate(plan.steps, 1):
        source = f"{Path(s.pos.file).name}:{s.pos.line}" if s.pos else ""
        asked = f"{s.asked:7.3f}" if s.asked is not None else "      -"
        flag = "  stretched" if s.stretched else ""
        print(f"  {n:>3}  {s.where:<24} {source:<18} {s.kind:<5} {s.start:7.3f} "
              f"{s.end:7.3f} {asked} {s.end - s.start:7.3f}{flag}")
    for link in measure(plan, compiled.streams):
        print()
        print(_link_text(link))
    return EXIT_OK


def _link_text(r: metrics.LinkReport) -> str:
    saved = 100 * (1 - r.bytes / r.naive_bytes) if r.naive_bytes else 0.0
    lag = (f"{r.worst_lag:.2f} deg ({r.worst_lag_servo} at {r.worst_lag_time:.3f} s)"
           if r.worst_lag_servo else "0.00 deg")
    rows = [
        f"board {r.board} at {r.baud} baud, {r.servos} servos",
        f"  bytes        {r.bytes:,} (every servo every frame: {r.naive_bytes:,}; "
        f"{saved:.0f}% fewer)",
        f"  link use     {100 * r.utilisation:.0f}% over the gesture, "
        f"{100 * r.peak_utilisation:.0f}% in the busiest frame",
        f"  coverage     {100 * r.coverage:.1f}% ({r.covered:,} of {r.needed:,} servo-frames "
        f"that needed a value)",
        f"  worst lag    {lag}",
        f"  max error    {r.max_error:.2f} deg (value sent vs plan at arrival)",
    ]
    if r.coverage < 1:
        rows.append("  the link is the bottleneck: raise the baud or split the servos "
                    "over more boards")
    return "\n".join(rows)


def cmd_plot(args: argparse.Namespace) -> int:
    from ..plot import plot

    compiled, plan = _compile(args)
    out = output_path(args.output, compiled.gesture, (".png", ".svg", ".pdf"))
    plot(plan, compiled, out)
    print(f"wrote {out}", file=sys.stderr)
    return EXIT_OK


def cmd_preview(args: argparse.Namespace) -> int:
    from ..preview import write_gif

    compiled, plan = _compile(args)
    out = output_path(args.output, compiled.gesture, (".gif",))
    frames, ms = write_gif(plan, compiled, out)
    print(f"wrote {out}: {frames} frames, {ms / 1000:.2f} s", file=sys.stderr)
    return EXIT_OK


def cmd_export(args: argparse.Namespace) -> int:
    from ..export import joint_states, to_csv

    compiled, plan = _compile(args)
    text = to_csv(*joint_states(plan, compiled, 1 / args.rate))
    if args.joint_states == "-":
        sys.stdout.write(text)
    else:
        Path(args.joint_states).write_text(text, encoding="utf-8")
        print(f"wrote {args.joint_states}: {text.count(chr(10)) - 1} rows", file=sys.stderr)
    return EXIT_OK


def cmd_fmt(args: argparse.Namespace) -> int:
    """Rewrite files in the canonical layout (``-``: stdin to stdout)."""
    from ..fmt import format_source

    status = EXIT_OK
    for file in args.files:
        try:
            text = sys.stdin.read() if file == "-" else Path(file).read_text(encoding="utf-8")
            formatted = format_source(text, "<stdin>" if file == "-" else file)
        except GestError as exc:
            report(exc.diagnostics, PROG)
            status = EXIT_ERROR
            continue
        if file == "-":
            sys.stdout.write(formatted)
        elif formatted != text:
            if args.check:
                print(f"{file}: would be reformatted")
                status = EXIT_ERROR
            else:
                Path(file).write_text(formatted, encoding="utf-8")
                print(f"{file}: reformatted", file=sys.stderr)
    return status


def cmd_firmware(args: argparse.Namespace) -> int:
    """Write (or, with --check, compare) the sketch folders of a profile's boards."""
    from ..upload import stale_files, write_sketchbook

    profile = load_profile(args.profile_name)
    out = Path(args.output)
    if args.check:
        stale = stale_files(profile, out, args.baud)
        for path in stale:
            print(f"{path}: out of date (gestc firmware {args.profile_name} -o {out})")
        return EXIT_ERROR if stale else EXIT_OK
    for path in write_sketchbook(profile, out, args.baud):
        print(f"wrote {path}", file=sys.stderr)
    print(f"{out}: {profile.name}'s sketches are up to date; build them with make -C {out}",
          file=sys.stderr)
    return EXIT_OK


def cmd_upload(args: argparse.Namespace) -> int:
    """Build boards' firmware from their profile and flash it through the bootloader."""
    import tempfile

    from ..firmware import sketch_names
    from ..upload import OLD_NANO_BAUD, UNO_BAUD, build, find_sketch, flash, read_hex
    from ..upload import avrdude_command as command

    if args.profile:
        profile = load_profile(args.profile)
        names = sketch_names(profile)
        if args.board and args.board not in names:
            raise GestError(Diagnostic("error", f"profile '{profile.name}' has no board "
                                       f"'{args.board}'", hint=f"its boards: "
                                       f"{', '.join(names)}"))
    elif args.board:
        profile = find_sketch(args.board)
        names = sketch_names(profile)
    else:
        raise GestError(Diagnostic("error", "which board?", hint="name one (gestc upload "
                                   "servo_rhand --port COM3), or give --profile for all "
                                   "of a profile's"))
    targets = [args.board] if args.board else list(names)
    ports = _upload_ports(args.port, targets, names)
    if args.hex and len(targets) > 1:
        raise GestError(Diagnostic("error", "--hex is one board's firmware",
                                   hint="name the board: gestc upload BOARD --hex FILE"))
    baud = OLD_NANO_BAUD if args.old_bootloader else UNO_BAUD
    with tempfile.TemporaryDirectory(prefix="inmoov-upload-") as tmp:
        if args.hex:
            hexes = {targets[0]: Path(args.hex)}
        elif args.dry_run:
            hexes = {name: Path(tmp) / "build" / f"{name}.hex" for name in targets}
            print(f"make -C {tmp} {' '.join(targets)}")
        else:
            hexes = build(profile, targets, Path(tmp), args.baud)
        for name in targets:
            if args.dry_run:
                print(" ".join(command(hexes[name], ports[name], baud, args.avrdude,
                                       args.avrdude_option)))
                continue
            size = len(read_hex(hexes[name]))
            print(f"{PROG}: flashing {name} ({size:,} bytes) through the bootloader on "
                  f"{ports[name]} at {baud} baud", file=sys.stderr, flush=True)
            flash(hexes[name], ports[name], baud, args.avrdude, args.avrdude_option)
            print(f"{PROG}: uploaded {name} to {ports[name]}", file=sys.stderr)
    return EXIT_OK


def _upload_ports(specs: list[str], targets: list[str], names: dict[str, int]
                  ) -> dict[str, str]:
    """``--port COM3`` for one board; ``--port NAME=PORT`` or ``--port ID=PORT`` each."""
    by_key = {**{n: n for n in names}, **{str(i): n for n, i in names.items()}}
    ports: dict[str, str] = {}
    for spec in specs:
        key, sep, port = spec.partition("=")
        if sep and key in by_key:
            ports[by_key[key]] = port
        elif len(targets) == 1 and len(specs) == 1:
            ports[targets[0]] = spec
        else:
            raise GestError(Diagnostic("error", f"--port {spec}: which board?",
                                       hint=" ".join(f"--port {n}=PORT" for n in targets)))
    missing = [n for n in targets if n not in ports]
    if missing:
        raise GestError(Diagnostic("error", f"no port for {', '.join(missing)}",
                                   hint=f"add --port {missing[0]}=PORT"))
    return ports


def _warn(diagnostic: Diagnostic) -> None:
    report([diagnostic], PROG)


def cmd_list(args: argparse.Namespace) -> int:
    dirs = library_dirs(args.lib)
    library = scan(dirs)
    report(library.warnings(), PROG)
    entries = sorted(library.entries.values(), key=lambda e: e.name)
    needs = _profiles_needed(entries, dirs)
    width = max((len(e.name) for e in entries), default=0)
    for e in entries:
        shadows = "".join(f"  (shadows {p})" for p in e.shadows)
        if args.long:
            print(f"{e.name:<{width}}  {e.description or '-'}  ({e.path.name}:{e.line}, "
                  f"for {needs[e.name]}){shadows}")
        else:
            print(f"{e.name}\t{e.path}\t{needs[e.name]}{shadows}")
    return EXIT_OK


def _profiles_needed(entries: list[Entry], dirs: list[Path]) -> dict[str, str]:
    """Gesture name -> the built-in profile it is for: rhand (the default) if its names
    are all there, else the first profile that has them all; '-' if none has."""
    from ..profile import builtin_profiles
    from ..resolve import resolver

    names = ["rhand", *(n for n in builtin_profiles() if n != "rhand")]
    profiles = [load_profile(n) for n in names]
    programs: dict[Path, Program | None] = {}
    needs: dict[str, str] = {}
    for e in entries:
        if e.path not in programs:
            try:
                programs[e.path] = load(str(e.path), search=dirs)
            except GestError:
                programs[e.path] = None
        needs[e.name] = "-"
        for profile in profiles if programs[e.path] is not None else ():
            try:
                resolver(programs[e.path], profile).gesture(e.name)
            except GestError:
                continue
            needs[e.name] = profile.name
            break
    return needs


def parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(
        prog=PROG, description="Compile .gest gestures into timed byte streams for the "
        "InMoov servo boards.")
    add_version(ap)
    sub = ap.add_subparsers(dest="command", required=True, metavar="COMMAND")

    def common(p: argparse.ArgumentParser, target: bool = True) -> None:
        if target:
            p.add_argument("target", metavar="FILE",
                           help="a .gest file, or the name of a library gesture")
            p.add_argument("-g", "--gesture", help="the gesture to use from FILE")
            p.add_argument("--from", dest="start", metavar="POSE",
                           help="start pose: a pose name or targets such as 'fingers 90' "
                           "(default: the profile's rest pose)")
        p.add_argument("-p", "--profile", default="rhand",
                       help="robot profile: a built-in name or a .toml path (default rhand)")
        p.add_argument("--strict", action="store_true",
                       help="treat warnings as errors: a stretched move, and a link that "
                       "cannot send every value the plan needs (coverage below 100%%)")
        add_lib(p)

    p = sub.add_parser("compile", help="write a compiled gesture")
    common(p)
    p.add_argument("-o", "--output", help="output file, '-' for stdout "
                   "(default GESTURE.gestc, or GESTURE.timed)")
    p.add_argument("-f", "--format", choices=("gestc", "timed"), default="gestc",
                   help="gestc: JSON for the player; timed: '<seconds> <byte>' per line")
    p.add_argument("--board", type=int, help="with --format timed: the board's stream")
    p.set_defaults(func=cmd_compile)

    p = sub.add_parser("check", help="report errors and warnings only")
    p.add_argument("files", nargs="+", metavar="FILE")
    common(p, target=False)
    p.set_defaults(func=cmd_check)

    p = sub.add_parser("show", help="steps, bytes, link use, coverage and lag")
    common(p)
    p.set_defaults(func=cmd_show)

    p = sub.add_parser("plot", help="draw each servo's planned motion and the values sent "
                       "(needs matplotlib)")
    common(p)
    p.add_argument("-o", "--output", help="image file: .png, .svg or .pdf "
                   "(default GESTURE.png)")
    p.set_defaults(func=cmd_plot)

    p = sub.add_parser("preview", help="an animated drawing of the hand doing the gesture "
                       "(needs Pillow)")
    common(p)
    p.add_argument("-o", "--output", help="the GIF to write (default GESTURE.gif)")
    p.set_defaults(func=cmd_preview)

    p = sub.add_parser("export", help="joint positions over time for a ROS (URDF) model")
    common(p)
    p.add_argument("--joint-states", required=True, metavar="CSV",
                   help="the CSV file to write ('-' for standard output): time, then "
                   "each joint in radians")
    p.add_argument("--rate", type=number(0, 1000, above=True), default=50.0,
                   help="rows per second (default 50: one per servo frame)")
    p.set_defaults(func=cmd_export)

    p = sub.add_parser("fmt", help="rewrite .gest files in the canonical layout")
    p.add_argument("files", nargs="+", metavar="FILE", help="a .gest file, or - for stdin")
    p.add_argument("--check", action="store_true",
                   help="change nothing; list the files fmt would change, exit 1 if any")
    p.set_defaults(func=cmd_fmt)

    p = sub.add_parser("firmware", help="write the Arduino sketch of every board of a profile")
    p.add_argument("profile_name", metavar="PROFILE", help="a built-in name or a .toml path")
    p.add_argument("-o", "--output", default="firmware",
                   help="the sketchbook to write into (default ./firmware)")
    p.add_argument("--baud", type=int, choices=(9600, 19200, 38400, 57600, 115200),
                   help="the boards' link speed (default: the profile's)")
    p.add_argument("--check", action="store_true",
                   help="change nothing; list the files that are out of date, exit 1 if any")
    p.set_defaults(func=cmd_firmware)

    p = sub.add_parser("upload", help="build a board's firmware and flash it (avrdude)")
    p.add_argument("board", nargs="?", metavar="BOARD",
                   help="a sketch name: servo_rhand, glove_rhand, servo_inmoov_head... "
                   "(default with --profile: every board of the profile)")
    p.add_argument("--port", action="append", required=True, metavar="PORT",
                   help="the board's port; with several boards BOARD=PORT each (the "
                   "sketch name or the board's ID)")
    p.add_argument("-p", "--profile", help="the profile the boards are built from (a "
                   "built-in name or a .toml path; default: the one with BOARD)")
    p.add_argument("--old-bootloader", action="store_true",
                   help="a Nano with the old bootloader (57600 baud instead of 115200)")
    p.add_argument("--baud", type=int, choices=(9600, 19200, 38400, 57600, 115200),
                   help="the link speed the firmware will use (default: the profile's)")
    p.add_argument("--hex", metavar="FILE",
                   help="flash this .hex (built in the Arduino IDE, say) instead of building")
    p.add_argument("--dry-run", action="store_true",
                   help="print the commands, build and flash nothing")
    p.add_argument("--avrdude", default="avrdude", metavar="PATH",
                   help="the avrdude to run (default: avrdude on the PATH)")
    p.add_argument("--avrdude-option", action="append", default=[], metavar="ARG",
                   help="pass ARG to avrdude (e.g. -v, or -x attempts=1); may be repeated")
    p.set_defaults(func=cmd_upload)

    record.add_parser(sub)

    p = sub.add_parser("list", help="the library's gestures: NAME<TAB>FILE")
    p.add_argument("-l", "--long", action="store_true",
                   help="a table: name, what the gesture does, where it is defined")
    add_lib(p)
    p.set_defaults(func=cmd_list)
    return ap


def main(argv: list[str] | None = None) -> int:
    args = parse_args(parser(), argv)
    return run(PROG, lambda: args.func(args))


if __name__ == "__main__":
    sys.exit(main())
