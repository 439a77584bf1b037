"""gestplay repl: type .gest steps and the hand does them at once.

A thread reads lines; the main thread runs the drive loop (drive.py), which sends
bytes on time and, when a line arrives, lets it take over the running move. The
waits between bytes are waits on the line queue, so a typed step starts within a
millisecond.
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
from typing import Any, Literal

from ... import clock
from ...hardware import Profile
from ...language.library import library_dirs
from ...live.drive import Drive, Note, library_program
from ...live.drive import Guard as DriveGuard
from ...live.session import LINE, STDIN
from ...profiles.profile import load_profile
from ...wire.player import Link
from .. import hand
from ..common import (
    EXIT_ERROR,
    EXIT_OK,
    add_allow_contact,
    add_blind,
    add_lib,
    add_ports,
    guard_for,
    report,
)
from . import sounds

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
    """Lines from a program or a file: read ahead, one after another (without the
    byte-order mark a Windows editor puts at the start of a file)."""
    first = True
    while True:
        try:
            line = input()
            lines.put(line.removeprefix("\ufeff") if first else line)
            first = False
        except (EOFError, KeyboardInterrupt, OSError, ValueError):
            lines.put(None)
            return


def repl(links: list[Link], profile: Profile, pose: dict[str, int],
         next_line: Callable[[float], Line], take_over: bool = True,
         now: clock.Clock | None = None, sleep: clock.Sleep | None = None,
         dirs: list[Path] | None = None, screen: Screen | None = None,
         speaker: Any = None, guard: DriveGuard | None = None) -> int:
    """Run until the input ends and the hand is still. ``next_line(timeout)`` waits at
    most ``timeout`` s for a line (``waiting_on`` a queue). Each line takes over the
    running move (``take_over``, a person typing: errors say ``<repl>:N``), or waits for
    the steps before it (a script: errors say ``<stdin>:N``, and a line that failed
    makes the exit status 1, once every line has run). With a ``screen``, each line is
    answered before the next prompt. A ``speaker`` (``wire.audio.Speaker``) says what
    ``say`` steps say. A ``guard`` (``model.guard.Guard.plan``) refuses a line that
    would drive the robot into itself."""
    told = _Told(screen)
    drive = Drive(links, profile, pose, library_program(dirs), told, take_over, now, sleep,
                  LINE if take_over else STDIN, speaker, guard)
    drive.run(_Commands(next_line, drive))
    return EXIT_ERROR if told.errors and not take_over else EXIT_OK


class _Commands:
    """The next line for the drive loop; the repl's own words are answered here. In a
    script, ``where`` answers once the steps before it are done."""

    def __init__(self, next_line: Callable[[float], Line], drive: Drive):
        self.next_line, self.drive = next_line, drive
        self.where = False  #: a ``where`` waits for the steps before it

    def __call__(self, timeout: float) -> Line:
        if self.where:
            if not self.drive.settled():
                self.drive.sleep(max(timeout, 0.0))
                return False
            self.where = False
            return self._where()
        line = self.next_line(timeout)
        words = line.strip() if isinstance(line, str) else ""
        if words in ("quit", "exit"):
            return None
        if words == "help":
            print(HELP, flush=True)
            return ""
        if words == "where":
            if self.drive.take_over or self.drive.settled():
                return self._where()
            self.where = True
            return False
        return line

    def _where(self) -> str:
        """Print what the boards hold; the line, answered."""
        drive = self.drive
        print("  ".join(f"{s.name} {v}" for s, v in zip(drive.profile.servos,
                                                         drive.mirror.held(), strict=True)),
              flush=True)
        return ""


class _Told:
    """What the drive loop tells: errors and warnings to stderr (above the prompt when
    they come while it waits), and how many errors there were."""

    def __init__(self, screen: Screen | None):
        self.screen, self.errors = screen, 0

    def __call__(self, note: Note) -> None:
        screen = self.screen
        if note.kind in ("error", "warning"):
            self.errors += note.kind == "error"
            say = functools.partial(report, note.diagnostics, "gestplay")
            screen.aside(say) if screen and note.aside else say()
        elif note.kind == "answered" and screen is not None:
            screen.answered.set()


def waiting_on(lines: queue.Queue) -> Callable[[float], Line]:
    """``next_line`` for lines that a thread puts in a queue."""

    def next_line(timeout: float) -> Line:
        try:
            return lines.get(timeout=timeout) if timeout > 0 else lines.get_nowait()
        except queue.Empty:
            return False

    return next_line


def run(args: argparse.Namespace) -> int:
    """Read steps from the terminal (or a pipe) and do them on the hand."""
    profile = load_profile(args.profile or "rhand")
    speaker = sounds.speaker(args.audio, PROG, profile) if args.audio else None
    guard = guard_for(profile, args.allow_contact, PROG)
    with hand.opened(PROG, profile, args.port, args.blind) as on:
        lines: queue.Queue = queue.Queue()
        interactive = sys.stdin.isatty()
        screen = Screen("gest> ") if interactive else None
        if interactive:
            print("gestplay repl: 'help' for help, Ctrl-D to leave", file=sys.stderr)
        threading.Thread(target=screen.read_lines if screen else read_lines, args=(lines,),
                         daemon=True).start()
        try:
            return repl(on.links, profile, on.pose, waiting_on(lines), take_over=interactive,
                        dirs=library_dirs(args.lib), screen=screen, speaker=speaker,
                        guard=guard.plan)
        finally:
            if speaker is not None:
                speaker.close()


def add_parser(sub: argparse._SubParsersAction) -> None:
    """``gestplay repl --port PORT``."""
    p = sub.add_parser("repl", help="type .gest steps, the hand does them at once",
                       description=HELP, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_ports(p, "as for playing")
    p.add_argument("-p", "--profile", help="robot profile (default rhand)")
    p.add_argument("--audio", metavar="DEVICE", help="hear what 'say' steps say: 'default' "
                   "(the default output), a device's name or number; without it the mouth "
                   "moves in silence (needs: pip install 'inmoov-dsl[voice]')")
    add_blind(p)
    add_allow_contact(p)
    add_lib(p)
    p.set_defaults(func=run)
