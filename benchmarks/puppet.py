"""gestplay puppet (docs/puppet.md): POSIX, ~1 min.

A gestsim board on a pty logs every byte it receives with the monotonic clock; a MIDI
port of mido's backend interface (tests/midi_backend.py) logs when it hands each control
change over. First, a fader jumping every 0.8 s, the hand at rest in between: the time
from a message to the first byte of its move at the board (goal: p99 within a servo
frame, 20 ms). Then the recorder: a take of two faders swept smoothly (a .mid file
written here) through ``gestc record``: lines per second of take, and how far the
gesture's plan strays from the take.

    python benchmarks/puppet.py
"""

from __future__ import annotations

import math
import os
import re
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import mido
from common import ROOT, arrivals

JUMPS, EVERY = 40, 0.8
MAP = '[[control]]\ncc = 1\nservo = "index"\n\n[[control]]\ncc = 2\nservo = "middle"\n'


def latency(tmp: Path) -> list[float]:
    log, sent, script = tmp / "board.log", tmp / "sent.txt", tmp / "script.txt"
    script.write_text("".join(f"{1.0 + k * EVERY:.3f} 1 1 {127 * (k % 2)}\n"
                              for k in range(1, JUMPS + 1)))
    (tmp / "map.toml").write_text(MAP)
    board = subprocess.Popen([sys.executable, "-m", "inmoov_dsl.cli.gestsim", "--quiet",
                              "--boot", "0.1", "--log", str(log)], stdout=subprocess.PIPE,
                             stderr=subprocess.DEVNULL, text=True)
    pty = board.stdout.readline().strip()
    env = {**os.environ, "MIDO_BACKEND": "midi_backend", "MIDI_PORTS": "Faders",
           "MIDI_SCRIPT": str(script), "MIDI_SENT": str(sent),
           "PYTHONPATH": os.pathsep.join([str(ROOT / "tests"), os.environ.get("PYTHONPATH", "")])}
    puppet = subprocess.Popen([sys.executable, "-m", "inmoov_dsl.cli.gestplay", "puppet",
                               "--midi", "Faders", "--map", str(tmp / "map.toml"), "--port",
                               pty], env=env, stdout=subprocess.DEVNULL,
                              stderr=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + 60 + JUMPS * EVERY
        while (not sent.exists() or len(sent.read_text().split()) < JUMPS) and \
                time.monotonic() < deadline:
            time.sleep(0.2)
        time.sleep(EVERY)
    finally:
        puppet.send_signal(signal.SIGINT)
        puppet.wait(30)
        board.terminate()
        board.wait(10)
    times, out = [t for t, _ in arrivals(log)], []
    for t in map(float, sent.read_text().split()):
        after = [a for a in times if a >= t - 1e-4]
        out.append(after[0] + 1 / 960 - t)  # the log says when a byte starts on the wire
    return out


def recorder(tmp: Path) -> tuple[float, float, float]:
    """Lines per second of a smooth two-fader take, and the error gestc record reports."""
    mid = mido.MidiFile(ticks_per_beat=480)
    track = mido.MidiTrack()
    mid.tracks.append(track)
    before, duration = 0, 6.0
    for k in range(int(duration / 0.02) + 1):
        t = k * 0.02
        for cc, phase in ((1, 0.0), (2, 1.0)):
            level = round(63.5 + 63.5 * math.sin(t * 1.3 + phase))
            tick = round(mido.second2tick(t, 480, 500000))
            track.append(mido.Message("control_change", control=cc, value=level,
                                      time=tick - before))
            before = tick
    mid.save(tmp / "take.mid")
    done = subprocess.run([sys.executable, "-m", "inmoov_dsl.cli.gestc", "record", "--midi",
                           str(tmp / "take.mid"), "--map", str(tmp / "map.toml"), "-o",
                           str(tmp / "take.gest")], capture_output=True, text=True, check=True)
    lines = [x for x in (tmp / "take.gest").read_text().splitlines() if x.startswith("    ")]
    error = float(re.search(r"within ([\d.]+) degrees", done.stderr)[1])
    return len(lines) / duration, error, duration


def main() -> None:
    with tempfile.TemporaryDirectory() as tmp:
        took = sorted(latency(Path(tmp)))
        p99 = took[min(len(took) - 1, round(0.99 * (len(took) - 1)))]
        print(f"MIDI message to the first byte of its move at the board ({len(took)} jumps): "
              f"p50 {statistics.median(took) * 1000:.1f} ms, p99 {p99 * 1000:.1f} ms, "
              f"max {took[-1] * 1000:.1f} ms (goal: p99 within 20 ms)")
        per_second, error, duration = recorder(Path(tmp))
        print(f"recorder: a {duration:g} s take of two faders swept smoothly -> "
              f"{per_second:.2f} lines a second, within {error:.1f} degrees of the take")


if __name__ == "__main__":
    main()
