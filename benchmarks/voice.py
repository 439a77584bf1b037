"""The mouth moving with the voice (``say``, docs/speaking.md): ten sentences spoken by
espeak-ng, and the same sounds as WAV files read back, each said while the head looks
around (``say "..." & look_around`` on the inmoov profile).

For each: the correlation between the sound's loudness (per 20 ms frame) and the jaw's
planned opening at its best time shift, and that shift (the planned opening should lead
the sound by speech.RESPONSE); the jaw's track within its servo's limits; the head
board's coverage; the time from the first loud sound to the mouth open, and from the
sound's end to the mouth closed.

    python benchmarks/voice.py
"""

from __future__ import annotations

import tempfile
from pathlib import Path

import numpy as np

from inmoov_dsl.compiling import speech
from inmoov_dsl.compiling.compiler import compile_program
from inmoov_dsl.compiling.metrics import measure
from inmoov_dsl.language.load import load
from inmoov_dsl.profiles.profile import load_profile
from inmoov_dsl.voice.speak import speak

SENTENCES = [
    "Hello, I am InMoov. I can wave and talk.",
    "The quick brown fox jumps over the lazy dog.",
    "Good morning everyone, welcome to the maker faire.",
    "One, two, three, four, five.",
    "Would you like to shake my hand?",
    "I am a robot made with a 3D printer.",
    "Please press the button to see me wave.",
    "My jaw moves when I speak.",
    "Thank you for visiting, have a nice day.",
    "Artificial intelligence is fascinating.",
]
FRAME = 0.020  #: s; the loudness is compared frame by frame
SHIFTS = range(-15, 16)  #: frames tried


def figures(plan, profile) -> dict:
    """The say step's figures in ``plan``."""
    (start, s), = plan.sounds
    jaw, servo = s.servo, profile.servos[s.servo]
    track = plan.tracks[jaw]
    per = round(FRAME / speech.HOP)
    count = len(s.levels) // per
    loud = s.levels[:count * per].reshape(count, per).mean(axis=1)
    t = start + (np.arange(count) + 0.5) * FRAME
    opening = track.position(t)

    def corr(shift: int) -> float:  # shift > 0: the opening leads the sound
        a = opening[:count - shift] if shift >= 0 else opening[-shift:]
        b = loud[shift:] if shift >= 0 else loud[:count + shift]
        return float(np.corrcoef(a, b)[0, 1])

    best = max(SHIFTS, key=corr)
    dense = np.arange(0, plan.duration, 0.0005)
    loud_at = np.flatnonzero(loud > 0.5)
    open_at = np.flatnonzero(opening > s.voice.closed + 0.5 * (s.voice.opened - s.voice.closed))
    closed = np.flatnonzero(track.position(dense) > s.voice.closed + 0.5)
    silent_from = (np.flatnonzero(s.levels > 0)[-1] + 1) * speech.HOP
    return {"corr": corr(best), "shift": best * FRAME,
            "v": np.abs(track.velocity(dense)).max() / servo.max_velocity,
            "a": np.abs(track.acceleration(dense)).max() / servo.max_acceleration,
            "j": np.abs(track.coefs[:, 3]).max() / servo.max_jerk,
            "open": (open_at[0] - loud_at[0]) * FRAME if len(open_at) and len(loud_at)
            else float("nan"),
            "close": dense[closed[-1]] - (start + silent_from) if len(closed) else 0.0,
            "seconds": s.sound.duration}


def main() -> None:
    profile = load_profile("inmoov")
    head = next(b.id for b in profile.boards if "jaw" in b.servos)
    folder = Path(tempfile.mkdtemp())
    print(f"Lead chosen: {speech.RESPONSE * 1000:.0f} ms (the tracker aims "
          f"{speech.aim(profile.servos[profile.index('jaw')], profile.voice) * 1000:.0f} ms "
          f"ahead).\n")
    print("| sentence | s | corr. (best) | best shift | jaw v / a / j of limit | head "
          "coverage | loud to open | end to closed | as a WAV file |")
    print("|---|---:|---:|---:|---|---:|---:|---:|---|")
    worst = 1.0
    for k, text in enumerate(SENTENCES):
        wav = folder / f"s{k}.wav"
        wav.write_bytes(speak(text, "en", profile.voice.speed, profile.voice.pitch))
        rows = []
        for said in (text, wav.name):
            program = load(str(folder / f"s{k}.gest"),
                           f'use "body.gest"\ng: say "{said}" & look_around\n',
                           search=[str(folder), str(Path(__file__).resolve().parent.parent
                                                    / "gestures")])
            compiled, plan = compile_program(program, "g", profile)
            f = figures(plan, profile)
            cover = next(r.coverage for r in measure(plan, compiled.streams)
                         if r.board == head)
            rows.append((f, cover, compiled.streams))
        (f, cover, streams), (_, _, from_file) = rows
        same = all(a.data == b.data for a, b in zip(streams, from_file, strict=True))
        worst = min(worst, f["corr"])
        print(f"| {text} | {f['seconds']:.2f} | {f['corr']:.3f} | {f['shift'] * 1000:+.0f} ms"
              f" | {f['v']:.2f} / {f['a']:.2f} / {f['j']:.2f} | {100 * cover:.1f}% | "
              f"{f['open'] * 1000:.0f} ms | {f['close'] * 1000:.0f} ms | "
              f"{'the same bytes' if same else 'DIFFERENT'} |")
    print(f"\nLowest correlation: {worst:.3f}")


if __name__ == "__main__":
    main()
