"""The InMoov's two Megas: the link's use per servo frame at 115200 for all of a Mega's
servos, with our protocol and with MrlComm's; how often each servo gets a new target; and
the delay from the plan to the board, measured at the pins.

The gesture moves every servo of the board at once, back and forth, three times (each
move as its servo's limits allow). Link use: the bytes of each frame's commands, cut by
each protocol's own parser, at 115200 (230 bytes a 20 ms frame; the rig's filler between
commands is not counted). The delay is measured where a servo sees it: our firmware,
built for the ATmega2560, runs in simavr (firmware/harness) fed the stream at the wire's
pace, and each pin's pulses are compared with the width the plan gives at the shift that
best aligns them (1 ms steps); the widths the pins show are the firmware's, not the
encoder's. MrlComm's pins were measured the same way on MrlComm itself, built for the
Mega (not ours to ship: docs/controllers.md says how); here, what its controller sends.

    python benchmarks/mega.py      (gcc-avr, arduino-core-avr and libsimavr-dev for the pins)
"""

from __future__ import annotations

import shutil
import subprocess
import tempfile
from pathlib import Path

import numpy as np
from common import ROOT

from inmoov_dsl import load_profile, to_timed
from inmoov_dsl.boards import controller
from inmoov_dsl.boards.rig.core import BoardServo
from inmoov_dsl.compiling.compiler import compile_program
from inmoov_dsl.language.load import load

FRAME = 0.020
PER_FRAME = 115_200 / 10 * FRAME  #: bytes a frame at 115200, 8N1


def sweep(profile, board: int) -> str:
    """Every servo of ``board`` to 160 and back to 20, three times."""
    names = [s.name for s in profile.servos if s.board == board]
    there = ", ".join(f"{n} 160" for n in names)
    back = ", ".join(f"{n} 20" for n in names)
    return f"g:\n    repeat 3:\n        {there}\n        {back}\n"


def frames(profile, board: int, compiled) -> tuple[np.ndarray, dict[int, int], float]:
    """Bytes of each frame's commands, targets sent per servo, and the stream's length."""
    b = next(x for x in profile.boards if x.id == board)
    c = controller(profile, b)
    stream = compiled.stream(board)
    used: dict[int, int] = {}
    for first, stop in c.commands(stream.data):
        f = int(np.floor(stream.times[stop - 1] / FRAME + 1e-9))
        used[f] = used.get(f, 0) + stop - first
    targets: dict[int, int] = {}
    for sid, _ in c.moves(stream.data):
        targets[sid] = targets.get(sid, 0) + 1
    return np.array(list(used.values())), targets, float(stream.times[-1])


def build() -> Path | None:
    """The Megas' images and the simulator, built in a directory of their own."""
    if not all(shutil.which(t) for t in ("make", "avr-gcc", "cc")):
        return None
    where = Path(tempfile.mkdtemp(prefix="mega-bench-"))
    done = subprocess.run(["make", "-s", "-C", str(ROOT / "firmware"), f"BUILD={where}",
                           "-j2", "servo_inmoov_left", "servo_inmoov_right", "harness"],
                          capture_output=True, text=True)
    return where if done.returncode == 0 else None


def pins(build_dir: Path, sketch: str, timed: str) -> dict[int, list[tuple[float, float]]]:
    """Every pulse (start s after ready, width us) of each pin of the image in simavr."""
    done = subprocess.run([str(build_dir / "harness" / "simboard"),
                           str(build_dir / f"{sketch}.elf"), "--baud", "115200", "--pulses",
                           "--run-on", "0.3"], input=timed, capture_output=True, text=True,
                          check=True)
    out: dict[int, list[tuple[float, float]]] = {}
    for line in done.stdout.splitlines():
        if line.startswith("pulse "):
            _, pin, t, w = line.split()
            out.setdefault(int(pin), []).append((float(t), float(w)))
    return out


def delays(profile, board: int, plan, pulses) -> dict[str, float]:
    """Each servo's delay (s) from plan to pin: the shift that best aligns its pulses
    with the widths its planned values give."""
    out = {}
    for j, s in enumerate(profile.servos):
        if s.board != board:
            continue
        servo = BoardServo(s.id, s.calibration, s.reversed, s.rest)
        got = np.array(pulses[s.pin])
        t, w = got[:, 0], got[:, 1]
        keep = (t > 0.1) & (t < plan.duration)
        best = None
        for shift in np.arange(0.0, 0.08, 0.001):
            planned = np.round(plan.tracks[j].position(np.clip(t[keep] - shift, 0, None)))
            want = np.array([servo.pulse(int(v)) for v in planned])
            err = float(np.mean(np.abs(want - w[keep])))
            if best is None or err < best[0]:
                best = (err, shift)
        out[s.name] = best[1]
    return out


def main() -> None:
    built = build()
    print("link use per 20 ms frame at 115200 (230 bytes), every servo of a Mega moving")
    print(f"{'board':<22} {'protocol':<14} {'median B':>8} {'worst B':>7} {'worst':>6} "
          f"{'targets/s per servo':>19}")
    delay_rows = []
    for board, name, sketch in ((181, "right (10 servos)", "servo_inmoov_right"),
                                (183, "left (18 servos)", "servo_inmoov_left")):
        for label, profile_name in (("ours (rig)", "inmoov"), ("MrlComm", "inmoov-mrlcomm")):
            profile = load_profile(profile_name)
            compiled, plan = compile_program(load("sweep.gest", sweep(profile, board)), "g",
                                             profile)
            used, targets, length = frames(profile, board, compiled)
            rate = np.array(list(targets.values())) / plan.duration
            print(f"{name:<22} {label:<14} {np.median(used):8.0f} {used.max():7.0f} "
                  f"{used.max() / PER_FRAME:6.0%} {rate.min():9.1f} - {rate.max():5.1f}")
            if profile_name == "inmoov" and built is not None:
                found = delays(profile, board, plan,
                               pins(built, sketch, to_timed(compiled.stream(board))))
                delay_rows.append((name, found))
    print()
    if not delay_rows:
        print("(no gcc-avr or simavr here: no delay at the pins)")
        return
    print("delay from plan to pin, our firmware on the Mega in simavr (best-aligning shift)")
    for name, found in delay_rows:
        values = np.array(list(found.values())) * 1000
        worst = max(found, key=found.get)
        print(f"{name:<22} median {np.median(values):4.0f} ms, worst {values.max():4.0f} ms "
              f"({worst})")


if __name__ == "__main__":
    main()
