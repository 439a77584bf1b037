"""gestplay repl: type .gest steps and the hand does them at once.

A thread reads lines; the main thread sends bytes on time and, when a line arrives,
lets it take over the running move (live.Session). The waits between bytes are waits
on the line queue, so a typed step starts within a millisecond.
"""

from __future__ import annotations

import argparse
import contextlib
import functools
import queue
import sys
import threading
from collections.abc import Callable
from pathlib import Path
from typing import Literal

from ... import clock
from ...board import BoardCore
from ...compiler import load
from ...errors import GestError
from ...library import library_dirs, library_files, scan
from ...live import Segment, Session, line_steps
from ...player import POLL, SPIN, Link, drain
from ...profile import Profile, load_profile
from ...program import Program
from .. import hand
from ..common import EXIT_OK, add_blind, add_lib, report

PROG = "gestplay repl"
HELP = """\
Type a step and the hand does it now, from where it is:
  index 90, middle 45 over 0.5s     servos or groups with values, optional 'over'
  fingers 180 stagger 50ms          a wave across a group
  peace                             a library gesture or pose by name
  wait 1s                           a pause after the running move
A step typed while the hand moves takes over from there, without stopping.
  where    the values the board holds      help    this text
  quit     (or Ctrl-D) leave once the hand is still; Ctrl-C stops at once"""


#: a typed line, None at the end of the input, False if none came in time
Line = str | None | Literal[False]


def library_program(dirs: list[Path] | None = None) -> Program:
    """Every library gesture, pose and group, for names typed at the prompt: the first
    definition of a name along the search path, as for gestures named on the command
    line (files that do not parse are left out; ``gestplay repl`` warned of them)."""
    dirs = library_dirs() if dirs is None else dirs
    broken = scan(dirs).broken
    uses = "".join(f'use "{f.resolve()}"\n' for f in library_files(dirs) if f not in broken)
    return load("<library>", uses, search=[str(d) for d in dirs], first_wins=True)


class Mirror:
    """What each board holds, from the bytes sent to it (the board's own rules)."""

    def __init__(self, profile: Profile, links: list[Link]):
        boards = {b.id: b for b in profile.boards}
        self.cores = [BoardCore.from_profile(profile, boards[link.board]) for link in links]
        where = {}
        for k, core in enumerate(self.cores):
            for j, servo in enumerate(core.servos):
                where[servo.id] = (k, j)
        self._where = [where[s.id] for s in profile.servos]

    def set(self, pose: list[int]) -> None:
        """The boards hold ``pose`` (the profile's servo order)."""
        for (k, j), v in zip(self._where, pose, strict=True):
            self.cores[k].values[j] = v

    def feed(self, k: int, byte: int) -> None:
        """Board ``k`` reads ``byte``."""
        self.cores[k].feed(byte)

    def held(self) -> list[int]:
        """What the boards hold, in the profile's servo order."""
        return [self.cores[k].values[j] for k, j in self._where]


class Screen:
    """The terminal a person types at: the reply to a line comes before the next prompt,
    and a message that comes while the prompt waits is written above it, the prompt and
    what is typed so far redrawn below."""

    def __init__(self, prompt: str):
        self.prompt = prompt
        self.answered = threading.Event()  #: the last line is dealt with: prompt again
        self.answered.set()
        self.prompting = False

    def read_lines(self, lines: queue.Queue) -> None:
        """The reading thread: one line at a time, each once the last one is answered."""
        with contextlib.suppress(ImportError):
            import readline  # noqa: F401  (line editing and history for input())
        while True:
            self.answered.wait()
            self.answered.clear()
            self.prompting = True
            try:
                line = input(self.prompt)
            except (EOFError, KeyboardInterrupt, OSError, ValueError):
                line = None
            self.prompting = False
            lines.put(line)
            if line is None:
                return

    def aside(self, say: Callable[[], None]) -> None:
        """Run ``say`` (it prints) above the prompt, if one is waiting."""
        if not self.prompting:
            say()
            return
        sys.stdout.write("\r\x1b[2K")
        sys.stdout.flush()
        say()
        sys.stderr.flush()
        sys.stdout.write(self.prompt + _typed_so_far())
        sys.stdout.flush()


def _typed_so_far() -> str:
    try:
        import readline
    except ImportError:  # Windows: input() has no line buffer to ask
        return ""
    return readline.get_line_buffer()


def read_lines(lines: queue.Queue) -> None:
    """Lines from a program or a file: read ahead, one after another."""
    while True:
        try:
            lines.put(input())
        except (EOFError, KeyboardInterrupt, OSError, ValueError):
            lines.put(None)
            return


def repl(links: list[Link], profile: Profile, pose: dict[str, int],
         next_line: Callable[[float], Line], take_over: bool = True,
         now: clock.Clock = clock.now, sleep: clock.Sleep = clock.sleep,
         dirs: list[Path] | None = None, screen: Screen | None = None) -> int:
    """Run until the input ends and the hand is still. ``next_line(timeout)`` waits at
    most ``timeout`` s for a line (``waiting_on`` a queue). Each line takes over the
    running move (``take_over``, a person typing), or waits for the steps before it (a
    script). With a ``screen``, each line is answered before the next prompt."""
    program = library_program(dirs)
    start = [pose.get(s.name, s.rest) for s in profile.servos]
    mirror = Mirror(profile, links)
    mirror.set(start)
    session = Session(profile, start, now(), program.sources)
    events: list[tuple[float, int, int]] = []  # (clock time, link, byte), pending
    ended = False
    while True:
        t = now()
        if ended and not events and not session.busy(t):
            return EXIT_OK
        wait = _wait(events, session, t, ended)
        if ended:
            sleep(max(wait, 0))
            line = False
        else:
            line = next_line(wait)
        if not events and line is False:
            for link in links:
                drain(link.port)  # a pulled cable shows here
        t = now()
        segment = None
        if line is None or (line and line.strip() in ("quit", "exit")):
            ended = True
        elif line:
            segment = _typed(line, session, t, mirror, profile, program, take_over)
        if segment is not None:
            report(segment.warnings, "gestplay")
        elif (segment := session.next(t, mirror.held())) is not None and segment.warnings:
            say = functools.partial(report, segment.warnings, "gestplay")
            screen.aside(say) if screen else say()
        if line is not False and screen is not None:
            screen.answered.set()
        if segment is not None:
            events = _events(segment, links)
        while events and events[0][0] <= now():
            _, k, byte = events.pop(0)
            links[k].port.write(bytes([byte]))
            mirror.feed(k, byte)


def _wait(events: list, session: Session, t: float, ended: bool) -> float:
    """How long to wait for a line: until the next byte is nearly due (then spin),
    until the running step ends if another is queued, and never more than POLL."""
    if events:
        return events[0][0] - t - SPIN
    if session.queue or ended:
        return min(POLL, session.end - t)
    return POLL


def waiting_on(lines: queue.Queue) -> Callable[[float], Line]:
    """``next_line`` for lines that a thread puts in a queue."""

    def next_line(timeout: float) -> Line:
        try:
            return lines.get(timeout=timeout) if timeout > 0 else lines.get_nowait()
        except queue.Empty:
            return False

    return next_line


def _typed(line: str, session: Session, t: float, mirror: Mirror, profile: Profile,
           program: Program, take_over: bool) -> Segment | None:
    words = line.strip()
    if not words or words.startswith("#"):
        return None
    if words == "help":
        print(HELP, flush=True)
        return None
    if words == "where":
        print("  ".join(f"{s.name} {v}" for s, v in zip(profile.servos, mirror.held(),
                                                         strict=True)), flush=True)
        return None
    try:
        steps, sources = line_steps(line, program, profile)
    except GestError as exc:
        report(exc.diagnostics, "gestplay")
        return None
    run = session.submit if take_over else session.append
    return run(steps, t, mirror.held(), sources)


def _events(segment: Segment, links: list[Link]) -> list[tuple[float, int, int]]:
    by_board = {link.board: k for k, link in enumerate(links)}
    events = [(segment.origin + t, by_board[s.board], b)
              for s in segment.streams for t, b in zip(s.times.tolist(), s.data, strict=True)]
    return sorted(events)


def run(args: argparse.Namespace) -> int:
    """Read steps from the terminal (or a pipe) and do them on the hand."""
    profile = load_profile(args.profile or "rhand")
    with hand.opened(PROG, profile, args.port, args.blind) as on:
        lines: queue.Queue = queue.Queue()
        interactive = sys.stdin.isatty()
        screen = Screen("gest> ") if interactive else None
        if interactive:
            print("gestplay repl: 'help' for help, Ctrl-D to leave", file=sys.stderr)
        threading.Thread(target=screen.read_lines if screen else read_lines, args=(lines,),
                         daemon=True).start()
        return repl(on.links, profile, on.pose, waiting_on(lines), take_over=interactive,
                    dirs=library_dirs(args.lib), screen=screen)


def add_parser(sub: argparse._SubParsersAction) -> None:
    """``gestplay repl --port PORT``."""
    p = sub.add_parser("repl", help="type .gest steps, the hand does them at once",
                       description=HELP, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--port", action="append", default=[], required=True,
                   help="as for playing; BOARD=PORT for each board of a profile with several")
    p.add_argument("-p", "--profile", help="robot profile (default rhand)")
    add_blind(p)
    add_lib(p)
    p.set_defaults(func=run)
