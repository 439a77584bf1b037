"""gestplay puppet: drive the hand from a MIDI controller's faders and knobs (or a take
played from a .mid file) through a map of its controls, live, and record the take.

Every control change goes through the drive loop as a move that takes over the running
one (live/puppet.py): the limits shape it, the collision check refuses one into the
body, Ctrl-C leaves the hand holding its pose. What is sent is shown; ``--record`` writes
the take as a short gesture, reduced as ``gestc record`` does (also after Ctrl-C).
"""

from __future__ import annotations

import argparse
import sys
from typing import TYPE_CHECKING

from ...errors import GestError
from ...live.drive import Drive, Note, library_program
from ...profiles.profile import load_profile
from .. import hand
from ..common import (
    EXIT_OK,
    add_allow_contact,
    add_blind,
    add_ports,
    gesture_name,
    guard_for,
    number,
    report,
    warn,
)

if TYPE_CHECKING:
    from ...hardware import Profile
    from ...live.puppet import Puppet

PROG = "gestplay puppet"


def run(args: argparse.Namespace) -> int:
    """Read the map (every mistake told before anything moves), open the input, then
    drive the hand with it until the take ends (a file) or Ctrl-C."""
    from ...language.load import read_text
    from ...live.controls import read_map
    from ...live.midi import open_input
    from ...live.puppet import Puppet, midi_reading

    profile = load_profile(args.profile)
    controls = read_map(read_text(args.map), args.map, profile)
    name = gesture_name(args.name, args.record) if args.record else ""
    guard = guard_for(profile, args.allow_contact, PROG)
    source, shown = open_input(args.midi), Shown()
    puppet = Puppet(source, midi_reading(controls, profile), profile, shown)
    try:
        with hand.opened(PROG, profile, args.port, args.blind) as on:
            print(f"{PROG}: {args.midi} drives {profile.name} through {args.map}"
                  f"{'; Ctrl-C stops' if sys.stdin.isatty() else ''}", file=sys.stderr)
            drive = Drive(on.links, profile, on.pose, library_program([]), Told(PROG),
                          guard=guard.plan)
            drive.run(puppet)
    finally:
        source.close()
        shown.end()
        if args.record:
            _record(puppet, profile, args, name)
    print(f"{PROG}: {len(puppet.samples):,} control changes, {puppet.moves:,} moves",
          file=sys.stderr)
    return EXIT_OK


def _record(puppet: Puppet, profile: Profile, args: argparse.Namespace, name: str) -> None:
    """Write the take (``--record``), if it moved anything."""
    from ..gestc.record import write_take

    samples = puppet.samples
    if not samples:
        warn(f"nothing to record: no control change of the map came from {args.midi}", PROG)
        return
    try:
        write_take(samples, profile, args.record, name, args.tolerance, f"live from {args.midi}",
                   prog=PROG)
    except (GestError, OSError) as exc:
        warn(f"the take could not be written to {args.record}: {exc}", PROG)


class Shown:
    """What is sent, as .gest text: one line rewritten at a terminal, else a line each."""

    def __init__(self) -> None:
        self.live = sys.stdout.isatty()
        self.shown = False  #: a line is on the terminal, not ended

    def __call__(self, text: str) -> None:
        if self.live:
            sys.stdout.write(f"\r\x1b[2K{text}")
        else:
            sys.stdout.write(text + "\n")
        sys.stdout.flush()
        self.shown = True

    def end(self) -> None:
        """End the rewritten line, so that what follows starts on its own."""
        if self.live and self.shown:
            sys.stdout.write("\n")
            sys.stdout.flush()


class Told:
    """The drive loop's errors (a move refused: into the body) and warnings, as they
    come; a fader held into the body is refused at every message, told once until a
    move goes again."""

    def __init__(self, prog: str) -> None:
        self.prog, self.refusing = prog, False

    def __call__(self, note: Note) -> None:
        if note.kind == "start":
            self.refusing = False
        elif note.kind == "warning" or (note.kind == "error" and not self.refusing):
            report(note.diagnostics, "gestplay")
            if note.kind == "error":
                print(f"{self.prog}: the hand stays where it is; the moves refused after this "
                      f"one are not told, until one is played", file=sys.stderr)
                self.refusing = True


def add_parser(sub: argparse._SubParsersAction) -> None:
    """``gestplay puppet --midi PORT|FILE.mid --map map.toml --port PORT``."""
    p = sub.add_parser("puppet", help="drive the hand from a MIDI controller (or a .mid "
                       "take) through a map of its controls; record the take",
                       description=__doc__)
    p.add_argument("--midi", required=True, metavar="PORT|FILE.mid",
                   help="a MIDI input port's name (or a part of it), or a .mid take "
                   "played in time")
    p.add_argument("--map", required=True, metavar="MAP.toml", help="which control turns "
                   "which servo ([[control]] tables: docs/puppet.md)")
    add_ports(p, "as for playing")
    p.add_argument("-p", "--profile", default="rhand", help="robot profile (default rhand)")
    p.add_argument("--record", metavar="TAKE.gest", help="write the take as a gesture "
                   "when it ends (or at Ctrl-C)")
    p.add_argument("--name", help="the recorded gesture's name (default: the file's)")
    p.add_argument("--tolerance", type=number(0, 90, above=True),
                   help="degrees the recorded gesture may stray from the take (default 3)")
    add_blind(p)
    add_allow_contact(p)
    p.set_defaults(func=run)
