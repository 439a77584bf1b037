"""How close to its planned time is a `say` heard? A gesture of tones and moves plays
on loop:// boards with a PulseAudio null sink as the output, and each sound's start is
timed by PortAudio's own clock of the block that carries it (`outputBufferDacTime`),
not by the player. Needs pulseaudio and PortAudio (libportaudio2); ~30 s.

    python benchmarks/sound.py [--runs 5]
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile
import wave
from pathlib import Path

import numpy as np
from common import ROOT

sys.path.insert(0, str(ROOT / "tests"))

from sound_server import null_sink, rescan  # noqa: E402


def tone(path: Path, seconds: float = 0.3, rate: int = 44100) -> None:
    t = np.arange(int(rate * seconds)) / rate
    with wave.open(str(path), "wb") as w:
        w.setnchannels(1)
        w.setsampwidth(2)
        w.setframerate(rate)
        w.writeframes((0.5 * np.sin(2 * np.pi * 220 * t) * 32767).astype(np.int16).tobytes())


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=5)
    args = ap.parse_args()
    import serial

    from inmoov_dsl.compiling.compiler import compile_source
    from inmoov_dsl.profiles.profile import load_profile
    from inmoov_dsl.wire.audio import Speaker
    from inmoov_dsl.wire.player import Link, play

    inmoov = load_profile("inmoov")
    with tempfile.TemporaryDirectory() as home:
        tone(Path(home) / "a.wav")
        source = "g:\n" + "".join(f'    say "a.wav" & neck {90 + 5 * (k % 2)} over 0.3s\n'
                                  f"    wait {0.1 + 0.05 * k:.2f}s\n" for k in range(4))
        compiled = compile_source(source, profile=inmoov, file=str(Path(home) / "g.gest"))
        with null_sink(Path(home) / "pulse") as address:
            os.environ["PULSE_SERVER"] = address
            rescan()
            errors = []
            for _ in range(args.runs):
                links = [Link(b.id, serial.serial_for_url("loop://", timeout=0), "loop://")
                         for b in inmoov.boards]
                speaker = Speaker()
                try:
                    speaker.wait_flowing(timeout=30)
                    play(compiled, links, speaker=speaker)
                finally:
                    speaker.close()
                errors += [heard - planned for planned, heard in speaker.heard]
    ms = sorted(abs(e) * 1000 for e in errors)
    print(f"{len(ms)} sounds ({args.runs} runs of {len(compiled.sounds)}): heard after their "
          f"planned time by median {statistics.median(ms):.2f} ms, worst {ms[-1]:.2f} ms "
          f"(earliest {min(errors) * 1000:+.2f} ms)")


if __name__ == "__main__":
    main()
