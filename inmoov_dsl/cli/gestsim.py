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
import select
import sys
from collections.abc import Callable
from typing import TextIO

from .. import clock
from ..board import BoardCore
from ..errors import Diagnostic, GestError
from ..glove import VirtualGlove
from ..profile import load_profile
from ..sim import DtrLine, VirtualBoard
from .common import EXIT_OK, add_version, number, parse_args, report, run

PROG = "gestsim"
FRAME = 0.05  #: s between redraws of the live view


def serve(args: argparse.Namespace) -> int:
    """Open a pseudo-terminal, print its path, and be the board on it until stopped."""
    if not hasattr(os, "openpty"):
        raise GestError(Diagnostic("error", "gestsim needs a POSIX system (Linux, macOS)",
                                   hint="on Windows, play to --port sim:// instead"))
    profile = load_profile(args.profile)
    board_cfg = next((b for b in profile.boards if args.board in (None, b.id)), None)
    if board_cfg is None:
        raise GestError(Diagnostic("error", f"profile '{profile.name}' has no board "
                                   f"{args.board}"))
    # what can fail does before the pty; the log is there before the path is printed
    glove = _glove(args, profile) if args.glove else None
    views: list = []
    if glove is None and args.view:
        views.append(_HandView(profile, board_cfg))
    elif glove is None and sys.stderr.isatty() and not args.quiet:
        views.append(_View(profile, board_cfg))
    web = _web(args, profile, board_cfg)
    views += [web] if web is not None else []
    try:
        return _serve(args, profile, board_cfg, glove, views, web)
    finally:
        if web is not None:
            web.close()


def _serve(args: argparse.Namespace, profile, board_cfg, glove, views: list, web) -> int:
    """The pty, its path printed, the board on it until stopped."""
    import tty

    log = open(args.log, "w", encoding="utf-8") if args.log else None  # noqa: SIM115
    master, slave = os.openpty()
    try:
        path = os.ttyname(slave)
        tty.setraw(slave)
        os.close(slave)
        print(f"{path}", flush=True)
        print(f"{PROG}: board {board_cfg.id} ({board_cfg.name}) of profile "
              f"'{profile.name}' on {path} at {board_cfg.baud} baud; Ctrl-C stops",
              file=sys.stderr, flush=True)
        if glove is not None:
            print(f"{PROG}: a glove performing '{args.glove}' from the moment the port "
                  f"opens", file=sys.stderr, flush=True)
        if web is not None:
            busy = (f" (port {args.http_port} is busy)"
                    if args.http_port not in (0, web.port) else "")
            print(f"{PROG}: the hand in 3-D at {web.url}{busy}", file=sys.stderr, flush=True)
        _Pty(master, args.boot, glove, views, log, lambda ready_at: VirtualBoard(
            BoardCore.from_profile(profile, board_cfg), board_cfg.baud, ready_at=ready_at)
             ).serve()
    except KeyboardInterrupt:
        return EXIT_OK
    finally:
        os.close(master)
        if log is not None:
            log.close()
    return EXIT_OK


class _Pty:
    """The board's side of the pseudo-terminal: bytes in, replies out, resets as the
    program on the other side raises DTR."""

    def __init__(self, master: int, boot: float, glove: list[tuple[float, bytes]] | None,
                 views: list, log: TextIO | None,
                 new_board: Callable[[float], VirtualBoard]):
        self.master, self.boot, self.glove, self.views, self.log = master, boot, glove, views, log
        self.new_board = new_board
        self.board: VirtualBoard | VirtualGlove | None = None
        self.line = DtrLine()  # no program has the port open yet

    def serve(self) -> None:
        """Forever: wait up to 5 ms for bytes, then let the board read and answer."""
        poller = select.poll()
        poller.register(self.master, select.POLLIN)
        while True:
            flags = dict(poller.poll(5)).get(self.master, 0)
            self.tick(flags, clock.now())

    def tick(self, flags: int, now: float) -> None:
        """One turn: read what came, notice a close or an open, let the board answer."""
        data = b""
        if flags & select.POLLIN:  # read first: the last bytes may come with the hang-up
            try:
                data = os.read(self.master, 4096)
            except OSError:  # EIO: the other side has closed
                data = b""
        if data and self.log is not None:
            self.log.write("".join(f"{now:.6f} {b}\n" for b in data))
            self.log.flush()
        if flags & select.POLLHUP and not data:
            self.line.closed()  # the bytes already on the wire still arrive
            if self.board is not None:
                self.board.read(now)
                self._draw(now)
            clock.sleep(0.01)
            return
        if not self.line.is_open:  # a program opened the port: if DTR rises, a reset
            self._opened(now)
        self.line.hupcl = _hupcl(self.master)
        if data:
            self.board.write(data, now)
        out = self.board.read(now)
        if out:
            try:
                os.write(self.master, out)
            except OSError:  # the other side closed meanwhile
                self.line.closed()
        self._draw(now)

    def _opened(self, now: float) -> None:
        rose = self.line.opened()
        if self.glove is not None:
            self.board = VirtualGlove(self.glove, now + self.boot)
        elif self.board is None:
            self.board = self.new_board(now + self.boot)
        elif rose:
            self.board.reset(now, self.boot)

    def _draw(self, now: float) -> None:
        for view in self.views:
            view.draw(self.board, now)


def _hupcl(master: int) -> bool:
    """Does the program that has the pty open leave HUPCL set (DTR drops when it
    closes)? A pty's settings are the ones the program set on its side."""
    import termios  # POSIX only, as gestsim is

    try:
        return bool(termios.tcgetattr(master)[2] & termios.HUPCL)
    except termios.error:
        return True


def _web(args: argparse.Namespace, profile, board_cfg):
    """With --web, the page where the hand moves in 3-D (webview.py), serving."""
    if not args.web:
        return None
    if args.glove:
        raise GestError(Diagnostic("error", "--web shows a board's pose; with --glove "
                                   "gestsim is a glove", hint="leave out --web or --glove"))
    from ..webview import WebView

    return WebView(profile, board_cfg, args.http_port)


def _glove(args: argparse.Namespace, profile) -> list[tuple[float, bytes]]:
    """The stream of a glove performing a gesture, untidy as asked."""
    from ..compiler import compile_program, load
    from ..glove import Imperfections, glove_stream
    from ..library import find_gesture

    if not profile.gloves:
        raise GestError(Diagnostic("error", f"profile '{profile.name}' has no glove",
                                   hint="a [[glove]] table describes one (rhand has it)"))
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
    return glove_stream(plan, profile.gloves[0], Imperfections(
        args.noise, args.drop, tuple(gaps), seed=args.seed))


class _View:
    """The board's values in the terminal, redrawn in place when they change (at most
    every FRAME): a bar per servo."""

    def __init__(self, profile, board_cfg):
        self.names = board_cfg.servos
        self.next = 0.0
        self.shown: list[int] | None = None
        self.height = 0  # lines drawn last time

    def lines(self, values: list[int]) -> list[str]:
        """A line per servo: its name, value and a bar."""
        return [f"  {name:<10} {value:>3}  {'#' * (value * 30 // 180)}"
                for name, value in zip(self.names, values, strict=True)]

    def draw(self, board: VirtualBoard, now: float) -> None:
        """Redraw if the values changed and a frame has passed."""
        if now < self.next or board.core.values == self.shown:
            return
        self.next = now + FRAME
        self.shown = list(board.core.values)
        lines = self.lines(self.shown)
        out = sys.stderr
        if self.height:
            out.write(f"\x1b[{self.height}F")
        out.write("".join(f"\x1b[2K{line}\n" for line in lines))
        out.flush()
        self.height = len(lines)


class _HandView(_View):
    """The hand drawn in the terminal (gestc preview's picture)."""

    def __init__(self, profile, board_cfg):
        from ..preview import draw_hand, hand_servos, pose_of, to_terminal

        super().__init__(profile, board_cfg)
        hand_servos(profile)  # a profile without a hand is an error now, not later
        self.profile, self.ids = profile, [profile.servos[profile.index(n)].id
                                           for n in board_cfg.servos]
        self.draw_hand, self.pose_of, self.to_terminal = draw_hand, pose_of, to_terminal
        draw_hand({})  # Pillow is there

    def lines(self, values: list[int]) -> list[str]:
        """The hand in that pose, as coloured half-block characters."""
        pose = self.pose_of(self.profile, values, self.ids)
        return self.to_terminal(self.draw_hand(pose), columns=48)


def main(argv: list[str] | None = None) -> int:
    """The console script."""
    ap = argparse.ArgumentParser(prog=PROG, description=__doc__.splitlines()[0])
    add_version(ap)
    ap.add_argument("-p", "--profile", default="rhand", help="robot profile (default rhand)")
    ap.add_argument("--board", type=int, help="which board of the profile (default the first)")
    ap.add_argument("--boot", type=number(0, 10), default=0.5,
                    help="seconds the board ignores bytes after a reset (default 0.5)")
    ap.add_argument("--log", help="write every byte received to this file, as it "
                    "arrives: '<seconds> <byte>' per line (monotonic clock)")
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
    ap.add_argument("--http-port", type=number(0, 65535, whole=True), default=8080,
                    metavar="N", help="with --web: the page's port (default 8080; 0: any "
                    "free one; a busy one: the next free)")
    args = parse_args(ap, argv)
    return run(PROG, lambda: serve(args))


if __name__ == "__main__":
    sys.exit(main())
