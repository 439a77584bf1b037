"""gestc record: listen to a glove (or any stream in the protocol), or read a MIDI take
through a map of its controls, and write a gesture.

The port is read until Ctrl-C or ``--seconds``; every (servo, value) pair is kept with
its arrival time (a take's control changes, through ``live.controls``, the same), and
record.py turns the traces into a short gesture that the compiler plays back within the
tolerance of the recording.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from ... import clock
from ...clock import Clock
from ...errors import Diagnostic, GestError
from ..common import EXIT_OK, gesture_name, number, warn

if TYPE_CHECKING:
    from ...decode import StreamReader
    from ...hardware import Glove, Profile
    from ...live.record import Fit
    from ...wire.link import Listener

PROG = "gestc record"


def run(args: argparse.Namespace) -> int:
    """Record from ``--port`` (or a MIDI take, ``--midi`` with ``--map``) into
    ``--output``: listen or read, choose keyframes, write them."""
    from ...profiles.profile import load_profile

    profile = load_profile(args.profile)
    name = gesture_name(args.name, args.output)
    if (args.port is None) == (args.midi is None):
        raise GestError(Diagnostic("error", "record from --port (a glove) or from --midi "
                                   "(a MIDI take), one of them",
                                   hint="gestc record --midi take.mid --map map.toml -o "
                                   "take.gest"))
    if args.midi is not None:
        source, samples, deadband, about = _from_midi(args, profile)
    else:
        source, samples, deadband, about = _from_port(args, profile)
    write_take(samples, profile, args.output, name, args.tolerance, source, deadband, about)
    return EXIT_OK


def write_take(samples: list[tuple[float, int, int]], profile: Profile, output: str,
               name: str, tolerance: float | None, source: str, deadband: float = 0.0,
               about: str = "", prog: str = PROG) -> None:
    """Reduce a take's (time, servo ID, value) samples to the fewest keyframes within
    ``tolerance`` (None: the default), write them to ``output`` as gesture ``name``, say
    how well it follows (and warn where it cannot)."""
    from ...live.record import DEFAULT_TOLERANCE, keyframes, to_gest, traces

    tolerance = DEFAULT_TOLERANCE if tolerance is None else tolerance
    tr = traces(samples, profile, deadband)
    fit = keyframes(tr, profile, tolerance)
    lines = [f"{name}: recorded {source}, {tr.times[-1]:.2f} s, {tr.samples:,} "
             f"samples, {len(fit.keyframes)} keyframes (tolerance {tolerance:g} degrees)"]
    Path(output).write_text(to_gest(name, fit.keyframes, profile, lines), encoding="utf-8")
    print(f"wrote {output}: {name}, {tr.times[-1]:.2f} s, {len(fit.keyframes)} keyframes "
          f"from {tr.samples:,} samples ({tr.dropped} dropped as noise{about}); it follows "
          f"the recording within {fit.error:.1f} degrees beyond the dead-band of "
          f"{deadband:g}", file=sys.stderr)
    for warning in _warnings(fit, tolerance, profile):
        warn(warning, prog)


def _from_port(args: argparse.Namespace, profile: Profile
               ) -> tuple[str, list[tuple[float, int, int]], float, str]:
    """What a glove (or any stream) on ``--port`` sends: (where from, samples, its
    dead-band, what was skipped)."""
    from ...decode import StreamReader
    from ...wire.glove import on_the_clock
    from ...wire.link import open_listener

    listener = open_listener(args.port, profile, args.baud)
    glove = listener.glove
    deadband = glove.deadband if glove and args.deadband is None else (args.deadband or 0)
    reader = StreamReader(recorded_ids(profile, glove))
    print(f"{PROG}: listening on {args.port} at {listener.baud} baud; Ctrl-C stops",
          file=sys.stderr)
    listen(listener, reader, args.seconds)
    if not reader.samples:
        raise GestError(Diagnostic(
            "error", f"no servo command for profile '{profile.name}' came from {args.port}",
            hint="is the glove on this port, sending to these servo IDs?"))
    samples = reader.samples
    if glove is not None:
        samples = on_the_clock(samples, glove.frame_ms / 1000)
    return f"on {args.port}", samples, deadband, f", {reader.skipped} bytes skipped"


def _from_midi(args: argparse.Namespace, profile: Profile
               ) -> tuple[str, list[tuple[float, int, int]], float, str]:
    """A MIDI take's control changes (a .mid file, or a controller's port listened to)
    through the map (``--map``): (where from, samples, no dead-band, what was passed
    over)."""
    from ...language.load import read_text
    from ...live.controls import no_samples, read_map, samples
    from ...live.midi import TakeFile, open_input, take_from

    if args.map is None:
        raise GestError(Diagnostic("error", "--midi needs --map: which control turns which "
                                   "servo", hint="a map.toml of [[control]] tables: cc = 1, "
                                   "servo = \"index\" (docs/puppet.md)"))
    controls = read_map(read_text(args.map), args.map, profile)
    source = open_input(args.midi)
    if isinstance(source, TakeFile):
        messages = source.messages
    else:  # a controller's port: what comes until Ctrl-C or --seconds
        print(f"{PROG}: listening to {source.name}; Ctrl-C stops", file=sys.stderr)
        messages = take_from(source, args.seconds)
    found = samples(messages, controls, profile)
    if not found:
        raise no_samples(args.midi)
    if args.seconds is not None:
        found = [s for s in found if s[0] - found[0][0] <= args.seconds]
    return (f"from {args.midi}", found, args.deadband or 0.0,
            f", {len(messages) - len(found)} control changes the map does not take")


def recorded_ids(profile: Profile, glove: Glove | None) -> frozenset[int]:
    """The servo IDs to record: a glove reports its own fingers (a pair for another
    servo is a byte lost); without a glove, every servo of the profile."""
    if glove is None:
        return frozenset(s.id for s in profile.servos)
    fingers = {x.servo for x in glove.sensors}
    return frozenset(s.id for s in profile.servos if s.name in fingers)


def listen(port: Listener, reader: StreamReader, seconds: float | None,
           now: Clock | None = None) -> None:
    """Feed ``reader`` what comes from ``port``, each read with the time it came, for
    ``seconds`` (None: until Ctrl-C), counting on the terminal; then close the port."""
    live = sys.stderr.isatty()
    now = now or clock.now
    start = now()
    try:
        while seconds is None or now() - start < seconds:
            data = port.read()  # what has come, at once: each byte's own time
            if data:
                reader.feed(now(), data)
            if live:
                sys.stderr.write(f"\r{now() - start:6.1f} s  {len(reader.samples):,} samples ")
                sys.stderr.flush()
    except KeyboardInterrupt:
        pass
    finally:
        port.close()
        if live:
            sys.stderr.write("\n")


def _warnings(fit: Fit, tolerance: float, profile: Profile) -> list[str]:
    """What the gesture cannot follow of the recording."""
    out = []
    if fit.error > tolerance:
        out.append(f"{fit.error:.1f} degrees is more than the tolerance: the recording has "
                   f"motion that moves from rest to rest cannot follow (fingers moving at "
                   f"different times, or lost reports)")
    if fit.stretched:
        times = ", ".join(f"{t:.2f} s" for t in fit.stretched)
        out.append(f"the recording moves faster than {profile.name}'s limits at {times}: "
                   f"those moves will take longer")
    return out


def add_parser(sub: argparse._SubParsersAction) -> None:
    """Add ``record`` to gestc's subcommands."""
    p = sub.add_parser("record", help="record a glove's motion, or a MIDI take, as a gesture")
    p.add_argument("--port", help="the glove's port (or any stream in the protocol): COM3, "
                   "/dev/ttyUSB0, a pyserial URL")
    p.add_argument("--midi", metavar="PORT|FILE.mid", help="a controller's MIDI input port "
                   "(its name, or a part of it) or a take (a DAW's recording of its faders "
                   "and knobs), instead of a glove's port; needs --map")
    p.add_argument("--map", metavar="MAP.toml", help="which MIDI control turns which servo "
                   "([[control]] tables: docs/puppet.md)")
    p.add_argument("-o", "--output", required=True, help="the .gest file to write")
    p.add_argument("--name", help="the gesture's name (default: the file's name)")
    p.add_argument("--seconds", type=number(0, 86400, above=True),
                   help="stop after this long (default: Ctrl-C; a take's end)")
    p.add_argument("--tolerance", type=number(0, 90, above=True),
                   help="degrees the played gesture may stray from the recording "
                   "(default 3)")
    p.add_argument("--deadband", type=number(0, 90), help="degrees a value moves before the glove "
                   "reports it (default: the profile's glove, else 0)")
    p.add_argument("-p", "--profile", default="rhand", help="robot profile (default rhand)")
    p.add_argument("--baud", type=int, help="the port's speed (default: the profile's "
                   "glove, else its first board)")
    p.set_defaults(func=run)
