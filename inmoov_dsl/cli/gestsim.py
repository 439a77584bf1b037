"""gestsim: the virtual board on a pseudo-terminal, for any program that talks serial.

It prints the device path, then serves until stopped. Like an Uno or a Nano, the board
resets when a program opening the port raises DTR: at the first open, and at any open
after a program closed the port with HUPCL set (the default; gestplay clears it, so
DTR stays up and the board does not reset). After a reset it starts from the pose it
had stored (the last pose that held for a second), ignores bytes for the boot time,
then sends WAIT. With a terminal, it shows every servo's value live; with --web, the
hand in 3-D on a page of its own (webview.py). POSIX only (Linux, macOS).
"""

from __future__ import annotations

import argparse
import os
import sys
from dataclasses import dataclass

from ..boards import controller
from ..errors import Diagnostic, GestError
from ..hardware import Glove
from ..profiles.profile import load_profile
from ..wire.sim import VirtualBoard
from .common import EXIT_OK, add_version, number, parse_args, report, run
from .gestsim_pty import Pty
from .gestsim_views import BarsView, HandView
from .options import LOCAL, Renamed, http_address, shown_address

PROG = "gestsim"


def _as_a_serial_device(slave: int) -> None:
    """Give the pty a serial device's default: HUPCL set (the last close drops DTR), so
    a program that reads it right after opening the port knows the open reset the
    board, as it knows of a real one (``ports.dtr_rose``)."""
    import termios

    attrs = termios.tcgetattr(slave)
    attrs[2] |= termios.HUPCL
    termios.tcsetattr(slave, termios.TCSANOW, attrs)


def serve(args: argparse.Namespace) -> int:
    """Open a pseudo-terminal, print its path, and be the board on it until stopped."""
    if not hasattr(os, "openpty"):
        raise GestError(Diagnostic("error", "gestsim needs a POSIX system (Linux, macOS)",
                                   hint="on Windows, play to --port sim:// instead"))
    profile = load_profile(args.profile)
    # what can fail does before the pty; the log is there before the path is printed
    glove = _glove(args, profile) if args.glove else None
    board_cfg = glove.config if glove else _board(profile, args.board)
    views: list = []
    if glove is None and args.view:
        views.append(HandView(profile, board_cfg))
    elif glove is None and sys.stderr.isatty() and not args.quiet:
        views.append(BarsView(profile, board_cfg))
    web = _web(args, profile, board_cfg)
    views += [web] if web is not None else []
    flash = None if glove else _stored(args, profile, board_cfg)
    try:
        return _serve(args, profile, board_cfg, glove, views, web, flash)
    finally:
        if web is not None:
            web.close()


def _stored(args: argparse.Namespace, profile, board_cfg):
    """The gestures the board stores: a built sketch's (--flash), or those the options
    ask for (--store...), compiled as ``gestc firmware`` does; None if neither."""
    from ..wire.stored import read_blob, read_set
    from .gestc.storing import stored_sets, wants_store

    if args.flash:
        return read_set(read_blob(args.flash))
    return stored_sets(args, profile, board_cfg, PROG).get(board_cfg.id) \
        if wants_store(args) else None


def _serve(args: argparse.Namespace, profile, board_cfg, glove, views: list, web,
           flash=None) -> int:
    """The pty, its path printed, the board on it until stopped."""
    import tty

    log = open(args.log, "w", encoding="utf-8") if args.log else None  # noqa: SIM115
    master, slave = os.openpty()
    try:
        path = os.ttyname(slave)
        tty.setraw(slave)
        _as_a_serial_device(slave)
        os.close(slave)
        print(f"{path}", flush=True)
        print(f"{PROG}: {'glove' if glove else 'board'} {board_cfg.id} ({board_cfg.name}) "
              f"of profile '{profile.name}' on {path} at {board_cfg.baud} baud; Ctrl-C "
              f"stops", file=sys.stderr, flush=True)
        if glove is not None:
            print(f"{PROG}: its fingers perform '{args.glove}' from the moment the port "
                  f"opens", file=sys.stderr, flush=True)
        if web is not None:
            asked = args.http[1]
            busy = f" (port {asked} is busy)" if asked not in (0, web.port) else ""
            print(f"{PROG}: the hand in 3-D at {web.url}{busy}", file=sys.stderr, flush=True)
        kind = None if glove else controller(profile, board_cfg)  # (a glove: no board)
        Pty(master, args.boot, glove and glove.stream, views, log,
             lambda ready_at: VirtualBoard(kind.twin(), board_cfg.baud, ready_at=ready_at,
                                           flash=flash, chatty=kind.ours,
                                           hello=kind.hello())).serve()
    except KeyboardInterrupt:
        return EXIT_OK
    finally:
        os.close(master)
        if log is not None:
            log.close()
    return EXIT_OK


def _web(args: argparse.Namespace, profile, board_cfg):
    """With --web, the page where the hand moves in 3-D (webview.py), serving."""
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
    from ..model.webview import WebView

    return WebView(profile, board_cfg, port)


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
