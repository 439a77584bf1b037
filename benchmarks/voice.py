"""The mouth moving with the voice (``say``, docs/speaking.md), measured as a viewer sees
it: ten sentences spoken by espeak-ng in two voices at two speeds, and Debian's recorded
human speech (alsa-utils) in several WAV formats (sox), one also 20 dB quieter, each
said while the head looks around (``say "said.wav" & look_around`` on the inmoov
profile).

Nothing of the planner measures it (tests/jawmeasure.py): the loudness is the RMS of
each 20 ms frame of the WAV file, averaged over 100 ms; speech is a frame well above the
recording's hiss; the jaw is the values its board receives, read from the compiled
stream's bytes. For each sound: the correlation at the best shift and that shift
(positive: the jaw ahead), the time from the last speech to the jaw closed, whether it
stays still in every silence longer than 250 ms and in the hiss before and after the
speech, the servo frames that needed a jaw value and got one, and how wide the jaw
opens.

    python benchmarks/voice.py      (espeak-ng, alsa-utils and sox; a few seconds)
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

from common import ROOT

sys.path.insert(0, str(ROOT / "tests"))
import jawmeasure  # noqa: E402 (the tests' measure)

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
VOICES = ("en", "en-us+f3")  #: espeak-ng's default voice, and a woman's American voice
SPEEDS = (150, 200)  #: words per minute: the profile's, and quick
FORMATS = jawmeasure.FORMATS  #: sox's options for each format: bits, encoding, channels, rate
QUIETER = ("16-bit mono 48 kHz", "8-bit mono 8 kHz")  #: "Front Left" 20 dB quieter in these


def cases(folder: Path):
    """(what, WAV bytes) of every sound measured."""
    for voice in VOICES:
        for speed in SPEEDS:
            for text in SENTENCES:
                yield f"{text} ({voice}, {speed} wpm)", jawmeasure.spoken(text, voice, speed)
    names = list(FORMATS)
    for k, path in enumerate(sorted(jawmeasure.RECORDINGS.glob("*.wav"))):
        if path.stem == "Noise":
            continue
        shown = path.stem.replace("_", " ")
        formats = names if k == 0 else [names[k % len(names)]]
        for name in formats:
            yield (f'"{shown}" (recorded, {name})',
                   jawmeasure.converted(path, folder / "converted.wav", *FORMATS[name]))
    for name in QUIETER:  # a quiet voice: clean in 16 bits, in loud hiss in 8
        yield (f'"Front Left" (recorded, {name}, 20 dB quieter)',
               jawmeasure.converted(jawmeasure.RECORDINGS / "Front_Left.wav",
                                    folder / "converted.wav", *FORMATS[name],
                                    effects=("vol", "0.1")))


def main() -> None:
    folder = Path(tempfile.mkdtemp())
    print("| sound | s | r (best shift) | best shift | last speech to closed | "
          "still in silences | jaw values in their frame | widest opening |")
    print("|---|---:|---:|---:|---:|---|---:|---:|")
    worst, shifts, late, ok = 1.0, set(), 0.0, True
    for what, wav in cases(folder):
        f, widest = jawmeasure.said(wav, folder)
        worst, late = min(worst, f.r), max(late, f.closed_after)
        shifts.add(round(f.shift * 1000))
        ok = ok and f.still_in_silence and f.reached == f.needed
        still = "yes" if f.still_in_silence else "NO"
        print(f"| {what} | {f.seconds:.2f} | {f.r:.3f} | {f.shift * 1000:+.0f} ms | "
              f"{f.closed_after * 1000:.0f} ms | {still} ({f.silences}) | "
              f"{f.reached}/{f.needed} | {100 * widest:.0f}% |")
    print(f"\nLowest r: {worst:.3f}; best shifts: "
          f"{', '.join(f'{s:+d}' for s in sorted(shifts))} ms; closed at most "
          f"{late * 1000:.0f} ms after the last speech; still in every long silence and "
          f"every jaw value in its frame: {'yes' if ok else 'NO'}")


if __name__ == "__main__":
    main()
