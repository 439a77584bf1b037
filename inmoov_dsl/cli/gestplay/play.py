"""gestplay play: play a gesture on the hand (``gestplay GESTURE`` for short)."""

from __future__ import annotations

import argparse
import itertools
import os
import shlex
import sys
from collections.abc import Callable
from typing import TYPE_CHECKING

from ...boards import controller
from ...compiling.actions import Action
from ...compiling.compiled import Compiled, to_timed
from ...compiling.compiler import compile_program, plan_checks
from ...compiling.resolve import resolver
from ...errors import Diagnostic, GestError, counted
from ...hardware import Profile
from ...profiles.profile import profile_arg
from ...profiles.tables import SIDES
from ...views.posebars import bar_lines
from ...wire.player import play
from .. import hand
from ..common import EXIT_OK, add_allow_contact, add_blind, add_lib, guard_for, number, report, warn
from ..options import PORT_FORMS
from ..target import Target, load_target
from . import TOOLS, sounds

if TYPE_CHECKING:
    from ...model.guard import Guard

PROG = "gestplay"


class Playing:
    """What to play (``load_target``): a compiled file, or a gesture to compile from the
    pose the hand is in, its actions resolved once (the boards they drive, then every
    pass's streams)."""

    def __init__(self, target: Target, strict: bool = False, side: str | None = None,
                 guard: Guard | None = None):
        self.profile, self.gesture = target.profile, target.gesture
        self.program, self.compiled = target.program, target.compiled
        self.strict, self.side = strict, side
        self.guard = guard  #: refuses what drives the robot into itself, before a byte
        self._actions: tuple[Action, ...] | None = None
        self._guarded = False  #: the compiled file has been checked

    def actions(self) -> tuple[Action, ...]:
        """The gesture's actions on its side, resolved the first time they are asked."""
        if self._actions is None:
            self._actions = resolver(self.program, self.profile).gesture(self.gesture,
                                                                         self.side)
        return self._actions

    def boards(self) -> set[int]:
        """The boards the gesture drives: those of the servos it names (a compiled
        file's: those its streams send more than a CANCEL to)."""
        if self.program is None:
            return {s.board for s in self.compiled.streams if not s.idle}
        return {self.profile.servos[i].board for a in self.actions() for i in a.servos()}

    def build(self, start: dict[str, int] | None) -> Compiled:
        """The streams, planned from ``start`` (servo name -> value) when given; the
        guard refuses them (a GestError) if they drive the robot into itself."""
        if self.program is None:
            if self.guard is not None and not self._guarded:
                report(self.guard.compiled(self.compiled), PROG)
                self._guarded = True
            return self.compiled
        with plan_checks(*([self.guard.check] if self.guard else [])):
            compiled, _ = compile_program(self.program, self.gesture, self.profile, start,
                                          self.strict, self.side, self.actions())
        report(compiled.warnings, PROG)
        return compiled


def run(args: argparse.Namespace) -> int:
    """Play (or with --dry-run print) the gesture."""
    if args.stored:
        from .stored import play_stored

        return play_stored(args)
    loaded = load_target(args.target, args.gesture, args.profile, args.lib, PROG,
                         compiled=True, side=args.hand)
    target = Playing(loaded, args.strict, args.hand,
                     guard_for(loaded.profile, args.allow_contact, PROG))
    if args.dry_run:
        return dry_run(target.build(None), args.speed)
    if not args.port:
        raise GestError(Diagnostic("error", "no port given", hint="--port COM3, "
                                   "--port /dev/ttyUSB0, or --port sim:// for the virtual "
                                   "board (--dry-run prints the schedule)"))
    boards = target.boards()
    audio = sounds.Audio(args.audio, PROG)
    try:
        with hand.opened(PROG, target.profile, args.port, args.blind, boards=boards) as on:
            pose = play_on(on, target, args.loop, args.speed, audio)
            if all(link.name.startswith("sim://") for link in on.links):
                show_virtual(on, boards, pose)
                print(f"to watch it move: {watch(args, on.profile, boards)}",
                      file=sys.stderr)
    finally:
        audio.close()
    return EXIT_OK


def show_virtual(on: hand.Hand, boards: set[int], pose: dict[str, int]) -> None:
    """What the virtual hand holds now (a board's bars, as gestsim draws them), for
    each board the gesture drove, on standard output (a result, as 'played' is)."""
    for board in on.profile.boards:
        link = next((k for k in on.links if k.board == board.id), None)
        if board.id not in boards or link is None:
            continue
        held = [(n, pose.get(n, on.pose.get(n, 0))) for n in board.servos]
        print(f"{link.name} now holds (board {board.id}, {board.name}):")
        print("\n".join(bar_lines(held)), flush=True)


def watch(args: argparse.Namespace, profile: Profile, boards: set[int],
          posix: bool = os.name == "posix") -> str:
    """Where to watch the gesture move: the command that runs the profile's virtual
    boards, all of them, and draws the robot (gestsim --view), and the one that plays
    it there, each as it runs (POSIX: gestsim serves a pseudo-terminal per board), or
    elsewhere the one that draws it (``boards``, those the gesture drives, are all
    served). Each runs as printed: the options that choose and play the gesture are
    carried over (``again``)."""
    name = args.target
    if not posix or not all(controller(profile, b).serial for b in profile.boards):
        # gestc preview draws a gesture as written: on its own side (a PCA9685 is on a
        # bus, which gestsim cannot serve)
        draw = ["gestc", "preview", name, *again(args, preview=True), "-o", f"{name}.gif"]
        return f"'{shlex.join(draw)}' draws it"
    sim = ["gestsim", "--view"]
    if profile_arg(profile) != "rhand":  # gestsim's default
        sim += ["--profile", profile_arg(profile)]
    # a gesture named like a tool (dump) is played by its full command
    play = ["gestplay", *(["play"] if name in TOOLS else []), name, *again(args)]
    if len(profile.boards) > 1:  # one gestsim is every board: the robot played on
        ids = ",".join(f"{b.id}=PTY{b.id}" for b in profile.boards)
        return (f"run '{shlex.join(sim)}' (or --web: in 3-D, in a browser) in another "
                f"terminal: the whole robot, its {len(profile.boards)} boards; then "
                f"'{shlex.join(play)} --port PORTS' with the PORTS it prints ({ids})")
    return (f"run '{shlex.join(sim)}' (or --web: in 3-D, in a browser) in another "
            f"terminal, then '{shlex.join(play)} --port PTY' with the PTY it prints")


def again(args: argparse.Namespace, preview: bool = False) -> list[str]:
    """The options of the play that ``args`` ran which the same play elsewhere needs:
    the gesture, the profile, the library, the side, the checks, the speed and the
    passes (``preview``: those gestc preview takes, which draws the gesture as
    written)."""
    said = vars(args)
    out = ["-g", said["gesture"]] if said.get("gesture") else []
    out += ["--profile", said["profile"]] if said.get("profile") else []  # else the file's
    for lib in said.get("lib") or []:
        out += ["--lib", lib]
    out += ["--strict"] if said.get("strict") else []
    if preview:
        return out
    out += ["--hand", said["hand"]] if said.get("hand") else []
    out += ["--allow-contact"] if said.get("allow_contact") else []
    if said.get("speed", 1.0) != 1.0:
        out += ["--speed", f"{said['speed']:g}"]
    loop = said.get("loop", 1)
    out += ["--loop"] if loop == 0 else ["--loop", str(loop)] if loop != 1 else []
    out += ["--audio", said["audio"]] if said.get("audio") else []
    return out


def dry_run(compiled: Compiled, speed: float) -> int:
    """Print the schedule, '<seconds> <byte>' per line, each board's under its number."""
    for stream in compiled.streams:
        if len(compiled.streams) > 1:
            print(f"# board {stream.board}")
        times = stream.times / speed
        sys.stdout.write(to_timed(type(stream)(stream.board, stream.baud, times, stream.data)))
    return EXIT_OK


def play_on(on: hand.Hand, target: Playing, loop: int, speed: float,
            audio: sounds.Audio | None = None) -> dict[str, int]:
    """Play ``loop`` times (0: until Ctrl-C) from the pose the hand holds, each pass from
    where the last one ended; one line of figures after, interrupted or not. The pose
    the hand ends in (servo name -> value)."""
    pose, start, compiled = on.pose, None, None
    run = _Run(len(on.links) if target.boards() else 0)
    try:
        for _ in itertools.count() if loop == 0 else range(loop):
            if compiled is None or pose != start:  # a pass from the same pose: as before
                start, compiled = pose, target.build(pose)
            if target.program is None and pose and pose != dict(zip(
                    compiled.servos, compiled.start, strict=True)):
                warn("the hand is not in the pose this compiled gesture starts from: it "
                     "will jump to it", PROG)
            compiled, speaker = audio.ready(compiled, speed) if audio else (compiled, None)
            show = _progress(compiled, speed) if sys.stderr.isatty() else None
            run.worst = max(run.worst, play(compiled, on.links, speed, progress=show,
                                            speaker=speaker))
            if show:
                print(file=sys.stderr)
            pose = dict(zip(compiled.servos, compiled.final, strict=True))
            run.add(compiled, speed)
    except KeyboardInterrupt:
        if loop == 0 and compiled is not None:  # the way an endless loop ends
            if sys.stderr.isatty():
                print(file=sys.stderr)  # after the progress line
            run.say(compiled.gesture, f"{times(run.passes)}, then stopped in pass "
                    f"{run.passes + 1}")
        raise
    run.say(compiled.gesture, times(loop) if loop > 1 else "")
    return pose


def times(n: int) -> str:
    """``once``, ``twice``, ``3 times``."""
    return {1: "once", 2: "twice"}.get(n, f"{n:,} times")


class _Run:
    """The figures of the passes played: how many, their time and bytes, the worst
    lateness, and whether any moved a servo."""

    def __init__(self, boards: int = 1):
        self.passes, self.seconds, self.sent, self.worst = 0, 0.0, 0, 0.0
        self.boards = boards  #: the boards the gesture drives (0: it moves no servo)
        self.moved = False

    def add(self, compiled: Compiled, speed: float) -> None:
        """One more pass of ``compiled`` done."""
        self.passes += 1
        self.seconds += compiled.duration / speed
        self.sent += sum(len(s.data) for s in compiled.streams)
        self.moved = self.moved or not all(s.idle for s in compiled.streams)

    def say(self, gesture: str, times: str) -> None:
        """The summary line, on standard output (the result, which ``> log.txt``
        keeps): ``played GESTURE[ times]: seconds, bytes, lateness``; the bytes of a
        gesture that found its boards in its pose already say so."""
        times = f" {times}" if times else ""
        held = "" if self.moved or not self.boards else \
            f" (the {'board' if self.boards == 1 else 'boards'} already held its pose)"
        print(f"played {gesture}{times}: {self.seconds:.2f} s, {counted(self.sent, 'byte')}"
              f"{held}, worst lateness {self.worst * 1000:.2f} ms", flush=True)


def _progress(compiled: Compiled, speed: float) -> Callable[[float], None]:
    steps = compiled.steps

    def show(t: float) -> None:
        n = sum(1 for s in steps if s.start <= t) or 1
        sys.stderr.write(f"\r{compiled.gesture}  step {n}/{len(steps)}  "
                         f"{t / speed:6.2f} / {compiled.duration / speed:.2f} s ")
        sys.stderr.flush()

    return show


def add_parser(sub: argparse._SubParsersAction) -> None:
    """``gestplay play GESTURE``, which ``gestplay GESTURE`` is short for."""
    ap = sub.add_parser("play", help="play a gesture (gestplay GESTURE is short for "
                        "gestplay play GESTURE)", description="Play a gesture on the "
                        "InMoov hand (gestplay GESTURE is short for gestplay play GESTURE). "
                        "What was played and the pose the hand ends in go to standard "
                        "output; warnings and progress to standard error. Bench tools: "
                        "gestplay " + "|".join(t for t in TOOLS if t != "play") +
                        " --help.")
    ap.add_argument("target", metavar="GESTURE",
                    help="a library gesture, a .gest file or a compiled .gestc file")
    ap.add_argument("--port", action="append", default=[], metavar="PORT",
                    help="COM3, /dev/ttyUSB0, a pyserial URL (loop://, socket://...) or "
                    f"sim:// (the virtual board); {PORT_FORMS}")
    ap.add_argument("-g", "--gesture", help="the gesture to play from a .gest file")
    ap.add_argument("-p", "--profile", help="robot profile (default rhand, or the "
                    "compiled file's)")
    ap.add_argument("--speed", type=number(0.01, 1), default=1.0,
                    help="play slower: 0.5 is half speed (0.01 to 1; faster than 1 would "
                    "break the servos' limits: change the gesture's timing instead)")
    ap.add_argument("--loop", type=number(1, 1_000_000, whole=True), default=1, metavar="N",
                    nargs="?", const=0, help="play N times, each pass from where the last "
                    "one ended; --loop alone: until Ctrl-C")
    ap.add_argument("--hand", choices=SIDES,
                    help="play the gesture on that side of a robot whose profile pairs its "
                         "sides ([sides]): a hand gesture on the left hand")
    ap.add_argument("--dry-run", action="store_true",
                    help="print the schedule ('<seconds> <byte>') without a port")
    ap.add_argument("--strict", action="store_true", help="stretched moves are errors")
    add_allow_contact(ap)
    ap.add_argument("--stored", action="store_true", help="the board plays the gesture it "
                    "stores in its flash (gestc upload --store; gestplay stored lists them), "
                    "from wherever the hand is")
    sounds.add_argument(ap)
    add_blind(ap)
    add_lib(ap)
    ap.set_defaults(func=run)
