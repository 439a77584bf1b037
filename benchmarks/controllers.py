"""The controllers a hand may hang on: time on the wire or bus per servo frame for all
of a board's servos, and what one command degree is in each controller's unit.

A frame's time is counted from the bytes the library's right-hand gestures really send
(the encoder's streams, cut into commands by the virtual devices' own parsers), at each
link's rate: a Maestro at 115200 (the Command Port is USB; this is the pace the
commands are timed at), with and without Set Multiple Targets (a Micro 6 has none);
MrlComm's moves and our firmware's pairs at 115200 (the rig's stream is one continuous
run: only its commands count here, not the filler between them); a PCA9685 at 100 and
400 kHz (nine clocks a byte, plus start, address and stop).

    python benchmarks/controllers.py
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from common import library_gestures

from inmoov_dsl import load_profile
from inmoov_dsl.boards import controller
from inmoov_dsl.compiling.compiler import compile_program

I2C_OVERHEAD = 2 + 9 + 9  #: bits of a block write besides its register and data: start,
#: stop, the address byte and its acknowledge (the register byte is counted as data)


def at_baud(profile, baud):
    return replace(profile, boards=tuple(replace(b, baud=baud) for b in profile.boards))


def variants():
    maestro = load_profile("rhand-maestro")
    pca = load_profile("rhand-pca9685")

    def board(profile, **options):
        b = profile.boards[0]
        opts = dict(b.options) | options
        return replace(profile, boards=(replace(b, options=tuple(opts.items())),))

    yield "Maestro Mini, Set Multiple Targets", maestro, 115_200, 10
    yield "Maestro Micro 6, Set Target each", board(maestro, model=0), 115_200, 10
    yield "MrlComm on a Mega, 115200", load_profile("rhand-mrlcomm"), 115_200, 10
    yield "our firmware (rig), 115200", at_baud(load_profile("rhand"), 115_200), 115_200, 10
    yield "PCA9685 at 100 kHz", pca, 100_000, 9
    yield "PCA9685 at 400 kHz", board(pca, bus=400_000), 400_000, 9


def frame_times(profile, rate: int, bits: int) -> list[float]:
    """Seconds on the wire of each frame's commands, over the right-hand library."""
    c = controller(profile, profile.boards[0])
    out = []
    for name, program, _ in library_gestures(("rhand",)):
        compiled, _ = compile_program(program, name, profile)
        stream = compiled.streams[0]
        frames: dict[int, float] = {}
        for first, stop in c.commands(stream.data):
            f = int(np.floor(stream.times[stop - 1] / 0.02 + 1e-9))
            n = stop - first
            # a PCA9685's framing: 3 bytes are the register and 2 of ours
            t = (I2C_OVERHEAD + (n - 2) * bits if c.kind == "pca9685" else n * bits) / rate
            frames[f] = frames.get(f, 0.0) + t
        out += frames.values()
    return out


def main() -> None:
    print("frame time for the right hand's six servos (library, every frame that sends)")
    print(f"{'controller':<36} {'median ms':>9} {'worst ms':>9} {'of 20 ms':>8}")
    for label, profile, rate, bits in variants():
        times = np.array(frame_times(profile, rate, bits)) * 1000
        print(f"{label:<36} {np.median(times):9.2f} {times.max():9.2f} "
              f"{times.max() / 20:8.0%}")
    print()
    print("one command degree, in us, and in each controller's unit")
    rhand = load_profile("rhand")
    pca = controller(load_profile("rhand-pca9685"), load_profile("rhand-pca9685").boards[0])
    print(f"{'servo':<8} {'us/degree':>9} {'Maestro 1/4 us':>14} {'PCA9685 ticks':>13}")
    for s, w in zip(rhand.servos, controller(rhand, rhand.boards[0]).widths, strict=True):
        per = abs(w.table[-1] - w.table[0]) / 180
        print(f"{s.name:<8} {per:9.2f} {per * 4:14.1f} {per / (pca.tick * 1e6):13.2f}")


if __name__ == "__main__":
    main()
