"""gestplay: play gestures on the hand, and the bench tools (dump, ports, send)."""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Callable

import serial

from ..compiled import Compiled, check_profile, read_compiled, to_timed
from ..compiler import compile_program, load
from ..errors import Diagnostic, GestError
from ..library import find_gesture, library_dirs
from ..player import Link, ask_dump, cancel_all, drain, play, relax_all, wait_ready
from ..ports import available, open_port
from ..profile import Profile, load_profile
from ..protocol import Signal
from ..urlhandler import protocol_sim
from . import calibrate, repl, teach
from .common import (
    EXIT_INTERRUPTED,
    EXIT_OK,
    Stopped,
    add_blind,
    add_lib,
    add_version,
    number,
    parse_args,
    report,
    run,
    status_of,
    why,
)

PROG = "gestplay"
TOOLS = ("dump", "ports", "send", "relax", "calibrate", "repl", "teach")
RELAX_WINDOW = 1.5  #: s after a Ctrl-C at a terminal in which a second one relaxes the hand


# -- playing -------------------------------------------------------------------------
class Target:
    """What to play: a compiled file, or a gesture to compile from the pose the hand is in."""

    def __init__(self, args: argparse.Namespace):
        self.args = args
        self.compiled: Compiled | None = None
        self.program = None
        name = args.target
        if name.endswith(".gestc"):
            self.compiled = read_compiled(name)
            self.profile = load_profile(args.profile or self.compiled.profile)
            check_profile(self.compiled, self.profile)
            return
        dirs = library_dirs(args.lib)
        path, self.gesture = find_gesture(name, args.gesture, dirs,
                                          lambda d: report([d], PROG))
        self.program = load(path, search=dirs)
        self.profile = load_profile(args.profile or "rhand")

    def build(self, start: dict[str, int] | None) -> Compiled:
        """The streams, planned from ``start`` (servo name -> value) when given."""
        if self.program is None:
            return self.compiled
        compiled, _ = compile_program(self.program, self.gesture, self.profile, start,
                                      self.args.strict)
        report(compiled.warnings, PROG)
        return compiled


def parse_ports(specs: list[str], profile: Profile) -> dict[int, str]:
    """``--port COM3`` (a one-board profile) or ``--port 181=COM3 --port 183=COM4``;
    a bare ``--port sim://`` is a virtual board for every board of the profile."""
    boards = [b.id for b in profile.boards]
    ports: dict[int, str] = {}
    for spec in specs:
        board, sep, name = spec.partition("=")
        if sep and board.isdigit():
            if int(board) not in boards:
                raise GestError(Diagnostic("error", f"--port {spec}: profile '{profile.name}' "
                                           f"has no board {board} (boards: {_ids(boards)})"))
            ports[int(board)] = protocol_sim.complete(name, profile, int(board))
        elif len(boards) == 1 or (len(specs) == 1 and protocol_sim.bare(spec)):
            ports.update({b: protocol_sim.complete(spec, profile, b) for b in boards})
        else:
            raise GestError(Diagnostic(
                "error", f"profile '{profile.name}' has {len(boards)} boards: give a port for "
                f"each", hint=" ".join(f"--port {b}=PORT" for b in boards)))
    missing = [b for b in boards if b not in ports]
    if missing:
        raise GestError(Diagnostic("error", f"no port for board {_ids(missing)}",
                                   hint=f"add --port {missing[0]}=PORT"))
    return ports


def _ids(ids: list[int]) -> str:
    return ", ".join(map(str, ids))


def connect(ports: dict[int, str], profile: Profile) -> list[Link]:
    links = []
    try:
        for board in profile.boards:
            links.append(Link(board.id, open_port(ports[board.id], board.baud), ports[board.id]))
    except GestError:
        close(links)
        raise
    return links


def close(links: list[Link]) -> None:
    for link in links:
        link.port.close()


def board_pose(links: list[Link], profile: Profile, blind: bool = False) -> dict[str, int]:
    """Each board's pose (``reach``), by servo name; a board that did not say it is
    planned from the profile's rest pose."""
    names = {s.id: s.name for s in profile.servos}
    pose: dict[str, int] = {}
    for link in links:
        values = reach(link, profile, blind, "starting from the profile's rest pose")
        pose.update({names[sid]: v for sid, v in (values or {}).items() if sid in names})
    return pose


def reach(link: Link, profile: Profile, blind: bool, going_on: str) -> dict[int, int] | None:
    """Wait for the board to boot, sync it with CANCEL and ask its pose with DUMP: its
    values (servo ID -> value), or None. Nothing answering (no WAIT and no DUMP reply)
    is an error before any gesture byte goes out, unless ``blind`` (a link that cannot
    answer); a board that answered only in part is a warning ending in ``going_on``."""
    ready = wait_ready(link.port)
    values = ask_dump(link.port, link.board)
    where = f"board {link.board} on {link.name}"
    if values is None and not ready:
        if not blind:
            raise GestError(no_answer(link, profile))
        _warn(f"{where} did not answer (--blind): {going_on}")
    elif values is None:
        _warn(f"{where} did not answer DUMP: {going_on}")
    elif not ready:
        _warn(f"{where} sent no WAIT, but answered DUMP")
    return values


def no_answer(link: Link, profile: Profile) -> Diagnostic:
    """What to say when nothing answers on a link (no WAIT, no DUMP reply)."""
    from ..firmware import sketch_names

    board = next(b for b in profile.boards if b.id == link.board)
    sketch = next(n for n, i in sketch_names(profile).items() if i == board.id)
    return Diagnostic(
        "error", f"no board answered on {link.name} (board {link.board}, {board.baud} baud)",
        hint=f"try another port ('gestplay ports' lists them and marks the likely "
        f"Arduinos), check that the board's sketch uses {board.baud} baud, or flash it: "
        f"gestc upload {sketch} --port {link.name}; --blind plays anyway on a link "
        f"that cannot answer")


def _warn(message: str) -> None:
    print(f"{PROG}: warning: {message}", file=sys.stderr)


def cmd_play(args: argparse.Namespace) -> int:
    target = Target(args)
    profile = target.profile
    if args.dry_run:
        compiled = target.build(None)
        for stream in compiled.streams:
            if len(compiled.streams) > 1:
                print(f"# board {stream.board}")
            times = stream.times / args.speed
            sys.stdout.write(to_timed(type(stream)(stream.board, stream.baud, times,
                                                   stream.data)))
        return EXIT_OK
    if not args.port:
        raise GestError(Diagnostic("error", "no port given", hint="--port COM3, "
                                   "--port /dev/ttyUSB0, or --port sim:// for the virtual "
                                   "board (--dry-run prints the schedule)"))
    links = connect(parse_ports(args.port, profile), profile)
    return on_the_hand(PROG, links, lambda: _play_loop(args, target, links))


def _play_loop(args: argparse.Namespace, target: Target, links: list[Link]) -> int:
    pose = board_pose(links, target.profile, args.blind)
    seconds, sent, worst = 0.0, 0, 0.0
    for _ in range(args.loop):
        compiled = target.build(pose)
        if target.program is None and pose and pose != dict(zip(compiled.servos,
                                                                compiled.start, strict=True)):
            _warn("the hand is not in the pose this compiled gesture starts from: it will "
                  "jump to it")
        show = _progress(compiled, args.speed) if sys.stderr.isatty() else None
        worst = max(worst, play(compiled, links, args.speed, progress=show))
        if show:
            print(file=sys.stderr)
        pose = dict(zip(compiled.servos, compiled.final, strict=True))
        seconds += compiled.duration / args.speed
        sent += sum(len(s.data) for s in compiled.streams)
    times = f" {args.loop} times" if args.loop > 1 else ""
    print(f"played {compiled.gesture}{times}: {seconds:.2f} s, {sent:,} bytes, worst "
          f"lateness {worst * 1000:.2f} ms", file=sys.stderr)
    return EXIT_OK


def on_the_hand(prog: str, links: list[Link], body: Callable[[], int]) -> int:
    """Run ``body`` with the boards' links open, and close them after. Ctrl-C stops it,
    sends CANCEL so that no half command is pending and exits 130 with the hand holding
    its pose; at a terminal, a second Ctrl-C soon after relaxes the hand (its servos go
    limp). SIGTERM and SIGHUP do as Ctrl-C (exit 143, 129). A lost link sends CANCEL
    where it still can and is one line of error."""
    try:
        return body()
    except KeyboardInterrupt as exc:
        cancel_all(links)
        if isinstance(exc, Stopped) or not sys.stdin.isatty():
            print(f"\n{prog}: {why(exc)}: CANCEL sent, the hand holds its pose",
                  file=sys.stderr)
            return status_of(exc)
        try:  # a second Ctrl-C may come as soon as the first one is answered
            print(f"\n{prog}: interrupted: CANCEL sent, the hand holds its pose (Ctrl-C "
                  f"again to relax it)", file=sys.stderr, flush=True)
            time.sleep(RELAX_WINDOW)
        except Stopped as again:
            return status_of(again)
        except KeyboardInterrupt:
            relax_all(links)
            print(f"{prog}: relaxed: the servos are limp until the next command",
                  file=sys.stderr)
        return EXIT_INTERRUPTED
    except serial.SerialException as exc:
        cancel_all(links)
        where = ", ".join(f"board {link.board} on {link.name}" for link in links)
        raise GestError(Diagnostic("error", f"lost the link ({where}): {exc}")) from None
    finally:
        close(links)


def _progress(compiled: Compiled, speed: float):
    steps = compiled.steps

    def show(t: float) -> None:
        n = sum(1 for s in steps if s.start <= t) or 1
        sys.stderr.write(f"\r{compiled.gesture}  step {n}/{len(steps)}  "
                         f"{t / speed:6.2f} / {compiled.duration / speed:.2f} s ")
        sys.stderr.flush()

    return show


# -- bench tools -----------------------------------------------------------------------
def cmd_ports(args: argparse.Namespace) -> int:
    found = available()
    for port in found:
        usb = f"USB {port.usb}" if port.usb else "-"
        likely = f"\tlikely {port.likely}" if port.likely else ""
        print(f"{port.device}\t{port.description}\t{usb}{likely}")
    if not found:
        print("no serial ports found (sim:// is the virtual board)", file=sys.stderr)
    elif not any(p.likely for p in found):
        print("none of these looks like an Arduino: is the board plugged in, with a data "
              "cable (some USB cables only charge)?", file=sys.stderr)
    return EXIT_OK


def cmd_dump(args: argparse.Namespace) -> int:
    profile = load_profile(args.profile or "rhand")
    port = _open_first(args.port, profile)
    try:
        wait_ready(port)
        found = ((b, ask_dump(port, b.id)) for b in profile.boards)
        b, values = next(((b, v) for b, v in found if v is not None), (None, None))
        if values is None:
            raise GestError(Diagnostic("error", f"no DUMP reply from {args.port}",
                                       hint="is the board powered, and at this baud?"))
        names = {s.id: s.name for s in profile.servos}
        print(f"board {b.id} ({b.name}): {len(values)} servos")
        for sid, value in values.items():
            print(f"  {names.get(sid, f'servo {sid}'):<10} id {sid:>3}  value {value:>3}")
    finally:
        port.close()
    return EXIT_OK


def _open_first(spec: str, profile: Profile):
    """A bench tool's port, at the baud of the profile's first board."""
    first = profile.boards[0]
    return open_port(protocol_sim.complete(spec, profile, first.id), first.baud)


def cmd_relax(args: argparse.Namespace) -> int:
    """Every board of the profile stops driving its servos until its next command."""
    profile = load_profile(args.profile or "rhand")
    links = connect(parse_ports(args.port, profile), profile)

    def relax() -> int:
        for link in links:
            reach(link, profile, args.blind, "relaxing it anyway")
        relax_all(links)
        for link in links:
            drain(link.port)  # a pulled cable says so here
            print(f"board {link.board} on {link.name}: relaxed, its servos are limp until "
                  f"the next command")
        return EXIT_OK

    return on_the_hand(PROG, links, relax)


SIGNAL_NAMES = {int(s): s.name for s in Signal}
SIGNAL_BYTES = {s.name.lower(): int(s) for s in Signal}


def cmd_send(args: argparse.Namespace) -> int:
    data = []
    for word in args.bytes:
        word_lower = word.lower()
        if word_lower in SIGNAL_BYTES:
            number = SIGNAL_BYTES[word_lower]
        else:
            number = int(word) if word.isdigit() else -1
        if not 0 <= number <= 255:
            raise GestError(Diagnostic("error", f"'{word}' is not a byte",
                                       hint="give numbers 0..255 or signal names "
                                       "(cancel, dump, ...)"))
        data.append(number)
    profile = load_profile(args.profile or "rhand")
    port = _open_first(args.port, profile)
    try:
        wait_ready(port)  # an Uno or Nano resets when its port opens
        port.write(bytes(data))
        time.sleep(args.listen)
        reply = drain(port)
    finally:
        port.close()
    print(" ".join(SIGNAL_NAMES.get(b, str(b)) if b > 180 else str(b) for b in reply))
    return EXIT_OK


# -- arguments ---------------------------------------------------------------------------
def play_parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(
        prog=PROG, description="Play a gesture on the InMoov hand. Bench tools: "
        "gestplay dump|ports|send|relax|calibrate|repl|teach --help.")
    add_version(ap)
    ap.add_argument("target", metavar="GESTURE",
                    help="a library gesture, a .gest file or a compiled .gestc file")
    ap.add_argument("--port", action="append", default=[], metavar="PORT",
                    help="COM3, /dev/ttyUSB0, a pyserial URL (loop://, socket://...) or "
                    "sim:// (the virtual board); BOARD=PORT for each board of a profile "
                    "with several")
    ap.add_argument("-g", "--gesture", help="the gesture to play from a .gest file")
    ap.add_argument("-p", "--profile", help="robot profile (default rhand, or the "
                    "compiled file's)")
    ap.add_argument("--speed", type=number(0.01, 1), default=1.0,
                    help="play slower: 0.5 is half speed (0.01 to 1; faster than 1 would "
                    "break the servos' limits: change the gesture's timing instead)")
    ap.add_argument("--loop", type=number(1, 1_000_000, whole=True), default=1, metavar="N",
                    help="play N times")
    ap.add_argument("--dry-run", action="store_true",
                    help="print the schedule ('<seconds> <byte>') without a port")
    ap.add_argument("--strict", action="store_true", help="stretched moves are errors")
    add_blind(ap)
    add_lib(ap)
    ap.set_defaults(func=cmd_play)
    return ap


def tools_parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(prog=PROG, description="Bench tools for the boards.")
    add_version(ap)
    sub = ap.add_subparsers(dest="command", required=True, metavar="TOOL")
    p = sub.add_parser("ports", help="the serial ports on this machine")
    p.set_defaults(func=cmd_ports)
    p = sub.add_parser("dump", help="a board's ID and every servo's value")
    p.add_argument("--port", required=True)
    p.add_argument("-p", "--profile", help="to name the servos (default rhand)")
    p.set_defaults(func=cmd_dump)
    p = sub.add_parser("send", help="send raw bytes and show the reply")
    p.add_argument("--port", required=True)
    p.add_argument("-p", "--profile", help="for the baud (default rhand)")
    p.add_argument("--listen", type=number(0, 60), default=0.3,
                   help="seconds to wait for a reply (default 0.3)")
    p.add_argument("bytes", nargs="+", metavar="BYTE",
                   help="0..255, or a signal name: cancel, dump, relax")
    p.set_defaults(func=cmd_send)
    p = sub.add_parser("relax", help="the servos stop holding (they go limp) until the "
                       "next command")
    p.add_argument("--port", action="append", required=True, metavar="PORT",
                   help="the board's port; BOARD=PORT for each board of a profile with "
                   "several")
    p.add_argument("-p", "--profile", help="robot profile (default rhand)")
    add_blind(p)
    p.set_defaults(func=cmd_relax)
    calibrate.add_parser(sub)
    repl.add_parser(sub)
    teach.add_parser(sub)
    return ap


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    ap = tools_parser() if argv[:1] and argv[0] in TOOLS else play_parser()
    args = parse_args(ap, argv)
    return run(PROG, lambda: args.func(args))


if __name__ == "__main__":
    sys.exit(main())
