"""gestplay teach: pose the hand from the keyboard, keep poses as keyframes, play them
back, and save them as a gesture."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from ...compiling.compiler import compile_program, plan_checks
from ...errors import GestError
from ...language.load import load
from ...live.teach import HELP, Teach
from ...profiles.profile import load_profile
from ...wire.player import Link, play
from .. import hand
from ..common import (
    EXIT_OK,
    add_allow_contact,
    add_blind,
    add_ports,
    gesture_name,
    guard_for,
    report,
    send_value,
    status_line,
)
from ..keys import key_reader

if TYPE_CHECKING:
    from ...model.guard import Guard

PROG = "gestplay teach"


def run(args: argparse.Namespace) -> int:
    """Teach a gesture on the hand, from the pose it holds."""
    name = gesture_name(args.name, args.output or "taught")
    output = Path(args.output or f"{name}.gest")
    profile = load_profile(args.profile or "rhand")
    guard = guard_for(profile, args.allow_contact, PROG)
    with hand.opened(PROG, profile, args.port, args.blind) as on:
        return teach_on(on, name, output, guard)


def teach_on(on: hand.Hand, name: str, output: Path, guard: Guard | None = None) -> int:
    """The keyboard loop: keys move servos, keep keyframes, play them back, save them.
    ``guard``: a pose or a play-back that drives the robot into itself is refused."""
    profile, links = on.profile, on.links
    link_of = {link.board: link for link in links}
    teach = Teach(profile, [on.pose.get(s.name, s.rest) for s in profile.servos])
    with key_reader() as keys:
        print(HELP)
        _show(teach)
        for key in keys:
            before = list(teach.pose)
            action = teach.press(key)
            if action == "send" and not _allowed(teach, guard, before):
                action = None
            if action == "send":
                servo = profile.servos[teach.selected]
                link = link_of[servo.board]
                send_value(link.port, servo.id, teach.pose[teach.selected], link.controller)
            elif action == "play":
                try:
                    _play_back(teach, name, links, guard)
                except GestError as exc:
                    report(exc.diagnostics, PROG)
            elif action == "save":
                output.write_text(teach.gesture(name), encoding="utf-8")
                teach.saved = True
                _say(f"saved {len(teach.keys)} keyframes to {output} as '{name}'")
            elif action == "quit":
                break
            _show(teach)
    if not teach.saved:
        _say(f"left without saving {len(teach.keys)} keyframes")
    print()
    return EXIT_OK


def _allowed(teach: Teach, guard: Guard | None, before: list[int]) -> bool:
    """Whether the servo just moved may be sent: the pose does not drive the robot into
    itself (or contact is allowed: its warning said); else the servo is put back."""
    if guard is None:
        return True
    try:
        report(guard.pose(teach.pose, [teach.selected]), PROG)
        return True
    except GestError as exc:
        report(exc.diagnostics, PROG)
        teach.pose[:] = before
        return False


def _play_back(teach: Teach, name: str, links: list[Link], guard: Guard | None) -> None:
    """Play the keyframes from the pose the hand is in; the hand ends on the last one
    (refused, a GestError, if they drive the robot into itself)."""
    start = dict(zip((s.name for s in teach.profile.servos), teach.pose, strict=True))
    with plan_checks(*([guard.check] if guard else [])):
        compiled, _ = compile_program(load(f"<{name}>", teach.gesture(name)), name,
                                      teach.profile, start)
    report(compiled.warnings, PROG)
    _say(f"playing {len(teach.keys)} keyframes, {compiled.duration:.2f} s")
    play(compiled, links)
    teach.pose = list(compiled.final)


def _say(text: str) -> None:
    sys.stdout.write(f"\n{text}\n")


def _show(teach: Teach) -> None:
    status_line(teach.line())


def add_parser(sub: argparse._SubParsersAction) -> None:
    """``gestplay teach --port PORT``."""
    p = sub.add_parser("teach", help="pose the hand from the keyboard and save the poses "
                       "as a gesture", description=HELP,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    add_ports(p, "as for playing")
    p.add_argument("-o", "--output", help="the .gest file 's' writes (default NAME.gest)")
    p.add_argument("--name", help="the gesture's name (default: the file's name, or taught)")
    p.add_argument("-p", "--profile", help="robot profile (default rhand)")
    add_blind(p)
    add_allow_contact(p)
    p.set_defaults(func=run)
