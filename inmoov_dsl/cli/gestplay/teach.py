"""gestplay teach: pose the hand from the keyboard, keep poses as keyframes, play them
back, and save them as a gesture."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ...compiling.compiler import compile_program
from ...language.load import load
from ...live.teach import HELP, Teach
from ...profiles.profile import load_profile
from ...wire.player import Link, play
from .. import hand
from ..common import EXIT_OK, add_blind, add_ports, gesture_name, report, send_value, status_line
from ..keys import key_reader

PROG = "gestplay teach"


def run(args: argparse.Namespace) -> int:
    """Teach a gesture on the hand, from the pose it holds."""
    name = gesture_name(args.name or (Path(args.output).stem if args.output else "taught"))
    output = Path(args.output or f"{name}.gest")
    profile = load_profile(args.profile or "rhand")
    with hand.opened(PROG, profile, args.port, args.blind) as on:
        return teach_on(on, name, output)


def teach_on(on: hand.Hand, name: str, output: Path) -> int:
    """The keyboard loop: keys move servos, keep keyframes, play them back, save them."""
    profile, links = on.profile, on.links
    link_of = {link.board: link for link in links}
    teach = Teach(profile, [on.pose.get(s.name, s.rest) for s in profile.servos])
    with key_reader() as keys:
        print(HELP)
        _show(teach)
        for key in keys:
            action = teach.press(key)
            if action == "send":
                servo = profile.servos[teach.selected]
                link = link_of[servo.board]
                send_value(link.port, servo.id, teach.pose[teach.selected], link.controller)
            elif action == "play":
                _play_back(teach, name, links)
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


def _play_back(teach: Teach, name: str, links: list[Link]) -> None:
    """Play the keyframes from the pose the hand is in; the hand ends on the last one."""
    start = dict(zip((s.name for s in teach.profile.servos), teach.pose, strict=True))
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
    p.set_defaults(func=run)
