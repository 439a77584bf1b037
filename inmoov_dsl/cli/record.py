"""gestc record: listen to a glove (or any stream in the protocol) and write a gesture.

The port is read until Ctrl-C or ``--seconds``; every (servo, value) pair is kept with
its arrival time, and record.py turns the traces into a short gesture that the
compiler plays back within the tolerance of the recording.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from ..errors import Diagnostic, GestError
from .common import EXIT_OK, gesture_name, number

PROG = "gestc record"


def cmd_record(args: argparse.Namespace) -> int:
    from ..ports import open_port
    from ..profile import load_profile
    from ..record import DEFAULT_TOLERANCE, StreamReader, keyframes, on_the_clock, to_gest, traces
    from ..urlhandler import protocol_sim

    if args.tolerance is None:
        args.tolerance = DEFAULT_TOLERANCE

    profile = load_profile(args.profile)
    glove = profile.gloves[0] if profile.gloves else None
    baud = args.baud or (glove.baud if glove else profile.boards[0].baud)
    deadband = glove.deadband if glove and args.deadband is None else (args.deadband or 0)
    name = gesture_name(args.name or Path(args.output).stem)
    first = profile.boards[0].id
    port = open_port(protocol_sim.complete(args.port, profile, first), baud, timeout=0.05)
    # a glove reports its own fingers: a pair for another servo is a byte lost
    ids = {s.id for s in profile.servos}
    if glove is not None:
        ids = {s.id for s in profile.servos if s.name in {x.servo for x in glove.sensors}}
    reader = StreamReader(frozenset(ids))
    live = sys.stderr.isatty()
    print(f"{PROG}: listening on {args.port} at {baud} baud; Ctrl-C stops", file=sys.stderr)
    start = time.monotonic()
    try:
        while args.seconds is None or time.monotonic() - start < args.seconds:
            data = port.read(max(1, port.in_waiting))  # at once: each byte's own time
            if data:
                reader.feed(time.monotonic(), data)
            if live:
                sys.stderr.write(f"\r{time.monotonic() - start:6.1f} s  "
                                 f"{len(reader.samples):,} samples ")
                sys.stderr.flush()
    except KeyboardInterrupt:
        pass
    finally:
        port.close()
        if live:
            sys.stderr.write("\n")
    if not reader.samples:
        raise GestError(Diagnostic(
            "error", f"no servo command for profile '{profile.name}' came from {args.port}",
            hint="is the glove on this port, sending to these servo IDs?"))
    samples = reader.samples
    if glove is not None:
        samples = on_the_clock(samples, glove.frame_ms / 1000)
    tr = traces(samples, profile, deadband)
    fit = keyframes(tr, profile, args.tolerance)
    span = tr.times[-1]
    about = [f"{name}: recorded on {args.port}, {span:.2f} s, {tr.samples:,} samples, "
             f"{len(fit.keyframes)} keyframes (tolerance {args.tolerance:g} degrees)"]
    Path(args.output).write_text(to_gest(name, fit, profile, about), encoding="utf-8")
    print(f"wrote {args.output}: {name}, {span:.2f} s, {len(fit.keyframes)} keyframes from "
          f"{tr.samples:,} samples ({tr.dropped} dropped as noise, {reader.skipped} bytes "
          f"skipped); it follows the recording within {fit.error:.1f} degrees beyond the "
          f"glove's dead-band of {deadband:g}", file=sys.stderr)
    if fit.error > args.tolerance:
        print(f"{PROG}: warning: {fit.error:.1f} degrees is more than the tolerance: the "
              f"recording has motion that moves from rest to rest cannot follow (fingers "
              f"moving at different times, or lost reports)", file=sys.stderr)
    if fit.stretched:
        times = ", ".join(f"{t:.2f} s" for t in fit.stretched)
        print(f"{PROG}: warning: the recording moves faster than {profile.name}'s limits "
              f"at {times}: those moves will take longer", file=sys.stderr)
    return EXIT_OK


def add_parser(sub) -> None:
    p = sub.add_parser("record", help="record a glove's motion as a gesture")
    p.add_argument("--port", required=True, help="the glove's port (or any stream in the "
                   "protocol): COM3, /dev/ttyUSB0, a pyserial URL")
    p.add_argument("-o", "--output", required=True, help="the .gest file to write")
    p.add_argument("--name", help="the gesture's name (default: the file's name)")
    p.add_argument("--seconds", type=number(0, 86400, above=True),
                   help="stop after this long (default: Ctrl-C)")
    p.add_argument("--tolerance", type=number(0, 90, above=True),
                   help="degrees the played gesture may stray from the recording "
                   "(default 3)")
    p.add_argument("--deadband", type=number(0, 90), help="degrees a value moves before the glove "
                   "reports it (default: the profile's glove, else 0)")
    p.add_argument("-p", "--profile", default="rhand", help="robot profile (default rhand)")
    p.add_argument("--baud", type=int, help="the port's speed (default: the profile's "
                   "glove, else its first board)")
    p.set_defaults(func=cmd_record)
