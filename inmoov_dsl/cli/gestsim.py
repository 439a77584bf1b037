"""gestsim: the virtual board on a pseudo-terminal, for any program that talks serial.

It prints the device path, then serves until stopped; on a profile of several boards
(inmoov's two Megas), every board, each on its own pty, unless --board names one: it
prints what --port takes then, 181=PATH,183=PATH. Like an Uno or a Nano, a board
resets when a program opening the port raises DTR: at the first open, and at any open
after a program closed the port with HUPCL set (the default; gestplay clears it, so
DTR stays up and the board does not reset). After a reset it starts from the pose it
had stored (the last pose that held for a second), ignores bytes for the boot time,
then sends WAIT. With a terminal, it shows every servo's value live (--view: the robot
drawn); with --web, the robot in 3-D on a page of its own (webview.py), every board's
servos on one page. POSIX only (Linux, macOS).
"""

from __future__ import annotations

import argparse
import os
import sys
from dataclasses import dataclass

from ..boards import controller
from ..errors import Diagnostic, GestError
from ..hardware import Board, Glove
from ..profiles.profile import load_profile
from ..wire.sim import VirtualBoard
from .common import EXIT_OK, add_version, number, parse_args, report, run
from .gestsim_pty import Pty, open_pty
from .gestsim_pty import serve as serve_ptys
from .gestsim_views import BarsView, Feed, HandView, RobotView
from .options import LOCAL, Renamed, http_address, shown_address

PROG = "gestsim"


def serve(args: argparse.Namespace) -> int:
    """Open a pseudo-terminal per board (every board of the profile unless ``--board``
    names one), print where, and be the boards on them until stopped."""
    if not hasattr(os, "openpty"):
        raise GestError(Diagnostic("error", "gestsim needs a POSIX system (Linux, macOS)",
                                   hint="on Windows, play to --port sim:// instead"))
    profile = load_profile(args.profile)
    # what can fail does before the pty; the log is there before the path is printed
    glove = _glove(args, profile) if args.glove else None
    boards = [glove.config] if glove else _boards(args, profile)
    views = [] if glove else _views(args, profile, boards)
    web = _web(args, profile, boards)
    views += [web] if web is not None else []
    flash = None if glove else _stored(args, profile, boards[0])
    try:
        return _serve(args, profile, boards, glove, views, web, flash)
    finally:
        if web is not None:
            web.close()


def _boards(args: argparse.Namespace, profile) -> list:
    """The boards to be: the one ``--board`` names, else every board of the profile;
    what only one board can have (``--log``, ``--flash``, ``--store``...) needs
    ``--board`` on a profile of several."""
    if args.board is not None or len(profile.boards) == 1:
        return [_board(profile, args.board)]
    from .gestc.storing import wants_store

    one = [o for o, asked in (("--log", args.log), ("--flash", args.flash),
                              ("--store", wants_store(args))) if asked]
    if one:
        raise GestError(Diagnostic(
            "error", f"{one[0]} is for one board, and profile '{profile.name}' has "
            f"{len(profile.boards)}: gestsim is all of them unless --board names one",
            hint=f"add --board {profile.boards[0].id} (or {profile.boards[0].name!r})"))
    return [_board(profile, str(b.id)) for b in profile.boards]


def _views(args: argparse.Namespace, profile, boards: list) -> list:
    """The live view in the terminal: with --view the robot drawn (its whole model on a
    profile with arms, a head or a torso; the hand of a hand profile), else on a
    terminal the servos' bars, unless --quiet."""
    if args.view:
        from ..views.film import whole_robot

        return [(RobotView if whole_robot(profile) else HandView)(profile, boards)]
    if sys.stderr.isatty() and not args.quiet:
        return [BarsView(profile, boards)]
    return []


def _stored(args: argparse.Namespace, profile, board_cfg):
    """The gestures the board stores: a built sketch's (--flash), or those the options
    ask for (--store...), compiled as ``gestc firmware`` does; None if neither."""
    from ..wire.stored import read_blob, read_set
    from .gestc.storing import stored_sets, wants_store

    if args.flash:
        return read_set(read_blob(args.flash))
    return stored_sets(args, profile, board_cfg, PROG).get(board_cfg.id) \
        if wants_store(args) else None


def _serve(args: argparse.Namespace, profile, boards: list, glove, views: list, web,
           flash=None) -> int:
    """The ptys, where they are printed, the boards on them until stopped."""
    log = open(args.log, "w", encoding="utf-8") if args.log else None  # noqa: SIM115
    masters: list[int] = []
    try:
        paths = [open_pty(masters) for _ in boards]
        _said(args, profile, boards, paths, glove, web)
        ptys = [Pty(master, args.boot, glove and glove.stream,
                    [Feed(view, board) for view in views], log, _maker(profile, board, flash))
                for master, board in zip(masters, boards, strict=True)]
        serve_ptys(ptys)
    except KeyboardInterrupt:
        return EXIT_OK
    finally:
        for master in masters:
            os.close(master)
        if log is not None:
            log.close()
    return EXIT_OK


def _maker(profile, board_cfg, flash):
    """What makes the board's virtual twin, at each reset (None for a glove)."""
    kind = controller(profile, board_cfg) if isinstance(board_cfg, Board) else None
    if kind is None:
        return None
    return lambda ready_at: VirtualBoard(kind.twin(), board_cfg.baud, ready_at=ready_at,
                                         flash=flash, chatty=kind.ours, hello=kind.hello())


def _said(args: argparse.Namespace, profile, boards: list, paths: list[str], glove,
          web) -> None:
    """Where the boards are: on standard output the path of the one (or ``ID=PATH,...``:
    what ``--port`` takes), on standard error each board, the glove's gesture, the page."""
    several = len(boards) > 1
    ports = ",".join(f"{b.id}={p}" for b, p in zip(boards, paths, strict=True))
    print(ports if several else paths[0], flush=True)
    for board, path in zip(boards, paths, strict=True):
        print(f"{PROG}: {'glove' if glove else 'board'} {board.id} ({board.name}) of "
              f"profile '{profile.name}' on {path} at {board.baud} baud"
              f"{'' if several else '; Ctrl-C stops'}", file=sys.stderr, flush=True)
    if several:
        print(f"{PROG}: play to them all with --port {ports}; Ctrl-C stops",
              file=sys.stderr, flush=True)
    if glove is not None:
        print(f"{PROG}: its fingers perform '{args.glove}' from the moment the port "
              f"opens", file=sys.stderr, flush=True)
    if web is not None:
        asked = args.http[1]
        busy = f" (port {asked} is busy)" if asked not in (0, web.port) else ""  # the
        # address last on its line: a terminal that makes it a link takes nothing after it
        from ..views.film import whole_robot

        what = "robot" if whole_robot(profile) else "hand"
        print(f"{PROG}: the {what} in 3-D{busy} at {web.url}", file=sys.stderr, flush=True)


def _web(args: argparse.Namespace, profile, boards: list):
    """With --web, the page where the robot moves in 3-D (webview.py), serving."""
    if not args.web:
        return None
    if args.glove:
        raise GestError(Diagnostic("error", "--web shows a board's pose; with --glove "
                                   "gestsim is a glove", hint="leave out --web or --glove"))
    host, port = args.http
    if host not in (LOCAL, "localhost"):
        raise GestError(Diagnostic(
            "error", f"--http {shown_address(host, port)}: gestsim's page is for this "
            f"computer only ({LOCAL})", hint=f"--http {port}; gestplay serve serves the "
            "hand to other computers (docs/service.md)"))
    from ..views.webview import WebView

    return WebView(profile, boards, port)


def _board(profile, key: str | None):
    """The board ``--board`` names, by its ID or its name, as ``--port BOARD=PORT``
    names it (default the profile's first)."""
    from ..wire.link import board_named

    board_cfg = profile.boards[0] if key is None else board_named(key, profile)
    if not controller(profile, board_cfg).serial:
        raise GestError(Diagnostic("error", f"board {board_cfg.id} of profile "
                                   f"'{profile.name}' is a {board_cfg.kind}, on a bus, not a "
                                   "serial port", hint=f"play on its virtual twin: gestplay "
                                   f"GESTURE --profile {profile.name} --port sim://"))
    return board_cfg


@dataclass(frozen=True)
class _Glove:
    """The glove gestsim is: its table in the profile, and what it sends."""

    config: Glove
    stream: list[tuple[float, bytes]]


def _glove(args: argparse.Namespace, profile) -> _Glove:
    """The glove (``--board``: its ID, default the profile's first) performing a
    gesture, untidy as asked."""
    from ..compiling.compiler import compile_program
    from ..language.library import find_gesture
    from ..language.load import load
    from ..wire.glove import Imperfections, glove_stream

    if not profile.gloves:
        raise GestError(Diagnostic("error", f"profile '{profile.name}' has no glove",
                                   hint="a [[glove]] table describes one (rhand has it)"))
    glove = next((g for g in profile.gloves if args.board in (None, str(g.id), g.name)),
                 None)
    if glove is None:
        ids = ", ".join(f"{g.id} or '{g.name}'" for g in profile.gloves)
        raise GestError(Diagnostic("error", f"--board {args.board}: profile "
                                   f"'{profile.name}' has no glove {args.board}",
                                   hint=f"its gloves: {ids}"))
    path, gesture = find_gesture(args.glove, None, warn=lambda d: report([d], PROG))
    _, plan = compile_program(load(path), gesture, profile)
    gaps = []
    for spec in args.gap:
        start, _, end = spec.partition("-")
        try:
            gaps.append((float(start), float(end)))
        except ValueError:
            raise GestError(Diagnostic("error", f"--gap {spec}: give START-END in seconds",
                                       hint="--gap 1.0-1.3")) from None
    return _Glove(glove, glove_stream(plan, glove, Imperfections(
        args.noise, args.drop, tuple(gaps), seed=args.seed)))


def parser() -> argparse.ArgumentParser:
    """gestsim's arguments."""
    ap = argparse.ArgumentParser(prog=PROG, description=__doc__.splitlines()[0])
    add_version(ap)
    ap.add_argument("-p", "--profile", default="rhand", help="robot profile (default rhand)")
    ap.add_argument("--board", metavar="BOARD", help="which board of the profile, its ID "
                    "or its name (default the first; with --glove, which glove)")
    ap.add_argument("--boot", type=number(0, 10), default=0.5,
                    help="seconds the board ignores bytes after a reset (default 0.5)")
    ap.add_argument("--log", help="write every byte received to this file: '<seconds> "
                    "<byte>' per line, when it starts on the wire (monotonic clock)")
    ap.add_argument("--quiet", action="store_true", help="no live view")
    ap.add_argument("--glove", metavar="GESTURE",
                    help="be the profile's glove instead, its fingers performing GESTURE "
                    "(a library name or a .gest file): for trying gestc record")
    ap.add_argument("--noise", type=number(0, 90), default=0.0,
                    help="with --glove: noise on each reading, in degrees (std. dev.)")
    ap.add_argument("--drop", type=number(0, 1), default=0.0,
                    help="with --glove: the chance that a byte is lost (0..1)")
    ap.add_argument("--gap", action="append", default=[], metavar="START-END",
                    help="with --glove: nothing is sent between these seconds")
    ap.add_argument("--seed", type=int, default=1, help="with --glove: for the noise")
    ap.add_argument("--view", action="store_true",
                    help="draw the hand in the terminal, live (needs Pillow and a terminal "
                    "with 24-bit colour)")
    ap.add_argument("--web", action="store_true",
                    help="also serve a page on 127.0.0.1 where the hand moves in 3-D, live "
                    "(needs: pip install 'inmoov-dsl[web]')")
    ap.add_argument("--http", type=http_address, default=f"{LOCAL}:8080", metavar="PORT",
                    help="with --web: the page's port on 127.0.0.1 (default 8080; 0: any "
                    "free one; a busy one: the next free)")
    ap.add_argument("--http-port", action=Renamed, new="--http {1}", dest="http",
                    type=http_address)  # the old spelling (gestplay serve's is --http)
    ap.add_argument("--flash", metavar="DIR", help="the board stores the gestures of the "
                    "sketch in DIR, built with gestc firmware --store (or its stored.h)")
    from .gestc.storing import add_store_options

    add_store_options(ap, "the virtual board")
    return ap


def main(argv: list[str] | None = None) -> int:
    """The console script."""
    args = parse_args(parser(), argv)
    return run(PROG, lambda: serve(args))


if __name__ == "__main__":
    sys.exit(main())
