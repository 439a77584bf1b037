"""The mouth measured as a viewer sees it, with nothing of the planner's code: the
sound's loudness read from the WAV bytes (Python's ``wave``), the jaw as the values
its board receives (the compiled stream's bytes, read here by the protocol's own
rules: 255 CANCEL, then servo ID and value pairs).

Shared by tests/test_jaw.py (a few sentences) and benchmarks/voice.py (every sentence,
both voices and speeds, the recordings).

- Loudness: the RMS of each 20 ms frame of the sound, smoothed over 100 ms (five
  frames, centred).
- The jaw: the value its board holds at the middle of each frame, a value arriving one
  byte-time after its first byte is sent.
- The best shift: the jaw's track against the loudness, shifted by whole frames; a
  positive shift is the jaw ahead of the sound.
- Speech: a frame louder than SILENT of the loudest frame's and than HISS times the
  sound's hiss (the median RMS of its quietest tenth of frames: the noise a recording
  holds where nobody speaks; none in a synthetic voice). Any other frame is silence.
- Frames: the plan needs a new jaw value in a 20 ms servo frame when, at no moment of
  the frame, its whole-degree value is the one the board holds at the frame's start (at
  a turn, the plan may come back to the value held); the value reaches the board in its
  frame when one arrives before the frame ends.
"""

from __future__ import annotations

import io
import subprocess
import wave
from dataclasses import dataclass
from pathlib import Path

import numpy as np

RECORDINGS = Path("/usr/share/sounds/alsa")  #: Debian's recorded speech (alsa-utils)
FRAME = 0.020  #: s
SMOOTH = 5  #: frames: 100 ms
SILENT = 0.03  #: of the loudest frame's RMS (-30 dB)...
HISS = 4.0  #: ...and this many times the sound's hiss (+12 dB): quieter is no speech
#: s: the jaw stays still in a silence longer than this, but for the closing after the
#: sound before it and the opening ahead of the sound after it (together this long: a
#: longer silence has a time the jaw has nothing to do)
LONG_SILENCE = 0.250
CLOSING = 0.150  #: s: closed within this of the last speech (the issue's bound)...
OPENING = 0.100  #: ...and the rest for the opening: a jaw needs it to open ahead
SHIFTS = range(-10, 11)  #: frames tried: +-200 ms
UNSIGNED, SIGNED = ("-e", "unsigned-integer"), ("-e", "signed-integer")
#: the WAV formats recordings are converted to (``converted``): sox's options for each
#: (bits, encoding, channels, rate)
FORMATS = {"16-bit mono 48 kHz": ("-b", "16", *SIGNED, "-c", "1", "-r", "48000"),
           "8-bit mono 8 kHz": ("-b", "8", *UNSIGNED, "-c", "1", "-r", "8000"),
           "16-bit stereo 16 kHz": ("-b", "16", *SIGNED, "-c", "2", "-r", "16000"),
           "8-bit stereo 22.05 kHz": ("-b", "8", *UNSIGNED, "-c", "2", "-r", "22050"),
           "16-bit mono 44.1 kHz": ("-b", "16", *SIGNED, "-c", "1", "-r", "44100")}
CANCEL, LAST_SIGNAL, MAX_VALUE = 255, 249, 180


def spoken(text: str, voice: str, speed: int) -> bytes:
    """espeak-ng's WAV of ``text`` in ``voice`` at ``speed`` words per minute."""
    return subprocess.run(["espeak-ng", "-v", voice, "-s", str(speed), "--stdout", text],
                          capture_output=True, check=True, timeout=60).stdout


def converted(path: Path, out: Path, *options: str, effects: tuple[str, ...] = ()) -> bytes:
    """The WAV at ``path`` in another format (sox ``options``; repeatable: no random
    dither), through sox ``effects`` (``("vol", "0.1")``: 20 dB quieter), written to
    ``out``."""
    subprocess.run(["sox", "-R", str(path), *options, str(out), *effects], check=True,
                   timeout=60)
    return out.read_bytes()


def samples(wav: bytes) -> tuple[np.ndarray, int]:
    """The WAV's samples mixed to mono, in -1..1, and its rate (PCM 8 to 32 bits)."""
    with wave.open(io.BytesIO(wav)) as w:
        channels, width, rate = w.getnchannels(), w.getsampwidth(), w.getframerate()
        raw = w.readframes(w.getnframes())
    if width == 1:
        x = np.frombuffer(raw, np.uint8).astype(float) / 128 - 1
    elif width == 3:
        b = np.frombuffer(raw, np.uint8).reshape(-1, 3).astype(np.int64)
        v = b[:, 0] + (b[:, 1] << 8) + (b[:, 2] << 16)
        x = np.where(v >= 1 << 23, v - (1 << 24), v) / float(1 << 23)
    else:
        x = np.frombuffer(raw, {2: "<i2", 4: "<i4"}[width]).astype(float)
        x /= float(1 << (8 * width - 1))
    return x.reshape(-1, channels).mean(axis=1), rate


def frame_rms(wav: bytes) -> np.ndarray:
    """The RMS of each whole 20 ms frame of the sound."""
    x, rate = samples(wav)
    n = int(round(FRAME * rate))
    count = len(x) // n
    return np.sqrt((x[:count * n].reshape(count, n) ** 2).mean(axis=1))


def speaking(rms: np.ndarray) -> np.ndarray:
    """Each frame: is it speech (louder than SILENT of the loudest, and than HISS times
    the median of the quietest tenth of the frames)?"""
    quietest = np.sort(rms)[:max(1, len(rms) // 10)]
    return rms >= max(SILENT * float(rms.max()), HISS * float(np.median(quietest)))


def loudness(rms: np.ndarray) -> np.ndarray:
    """The frames' RMS smoothed over 100 ms."""
    return np.convolve(rms, np.ones(SMOOTH) / SMOOTH, mode="same")


def received(times: np.ndarray, data: bytes, byte_time: float, servo: int
             ) -> list[tuple[float, int]]:
    """(arrival, value) of each value a rig board reads for ``servo`` from a stream."""
    out, sid = [], None
    expecting_id = True
    for t, b in zip(times.tolist(), data, strict=True):
        if b == CANCEL:
            sid, expecting_id = None, True
            continue
        if b >= LAST_SIGNAL:  # another signal: no part of a pair
            continue
        if expecting_id:
            sid, expecting_id = b, False
        elif sid is not None:
            if sid == servo:
                out.append((t + byte_time, min(b, MAX_VALUE)))
            sid, expecting_id = None, True
    return out


def held(values: list[tuple[float, int]], start: int, at: np.ndarray) -> np.ndarray:
    """The value the board holds at each of ``at``, ``start`` before the first."""
    arrivals = np.array([t for t, _ in values])
    held_ = np.array([start] + [v for _, v in values], dtype=float)
    return held_[np.searchsorted(arrivals, at, side="right")] if len(values) else \
        np.full(len(at), float(start))


@dataclass(frozen=True)
class Figures:
    """One sound said, as a viewer sees it."""

    seconds: float
    r: float  #: correlation at the best shift
    shift: float  #: s; the best shift, positive: the jaw ahead of the sound
    closed_after: float  #: s from the last speech to the jaw holding its closed value
    #: no jaw value changed inside a long silence, nor before the first speech (but
    #: for the opening ahead of it) or after the last (but for the closing)
    still_in_silence: bool
    silences: int  #: silences longer than LONG_SILENCE between two speech frames
    tail: float  #: s of the sound after its last speech (its hiss, or silence)
    widest: int  #: the widest opening received
    needed: int  #: servo frames in which the plan needs a new jaw value
    reached: int  #: of those, the frames a value reached the board in


def correlation(jaw: np.ndarray, loud: np.ndarray, shift: int) -> float:
    """r between the jaw and the loudness ``shift`` frames later."""
    n = len(loud)
    a = jaw[:n - shift] if shift >= 0 else jaw[-shift:]
    b = loud[shift:] if shift >= 0 else loud[:n + shift]
    if a.std() == 0 or b.std() == 0:
        return 0.0
    return float(np.corrcoef(a, b)[0, 1])


def frame_moments(duration: float) -> np.ndarray:
    """Moments of each servo frame from 0 to ``duration``, a row per frame, every
    millisecond from its start to its end."""
    count = int(duration / FRAME) + 2
    return np.arange(count)[:, None] * FRAME + np.linspace(0, FRAME, 21)[None, :]


def frames_reached(values: list[tuple[float, int]], planned: np.ndarray, start: int
                   ) -> tuple[int, int]:
    """(needed, reached): ``planned`` is the plan's jaw at ``frame_moments``; the jaw
    starts at ``start``."""
    wanted = np.floor(np.asarray(planned) + 0.5)
    kept = held(values, start, np.arange(len(wanted)) * FRAME)
    needed = np.flatnonzero(np.all(wanted != kept[:, None], axis=1))
    arrivals = np.array([t for t, _ in values])
    frame_of = np.ceil(arrivals / FRAME - 1e-9).astype(int) - 1  # (f, f + 1] * FRAME
    return len(needed), int(np.isin(needed, frame_of).sum())


def measure(wav: bytes, start: float, values: list[tuple[float, int]], closed: int,
            planned: np.ndarray) -> Figures:
    """The figures of a sound heard from ``start`` (s in the stream's time) and the jaw's
    ``values`` received (``received``), the jaw starting ``closed``; ``planned``: the
    plan's jaw at ``frame_moments``."""
    rms = frame_rms(wav)
    loud = loudness(rms)
    mids = start + (np.arange(len(rms)) + 0.5) * FRAME
    jaw = held(values, closed, mids)
    best = max(SHIFTS, key=lambda s: correlation(jaw, loud, s))
    sounding = np.flatnonzero(speaking(rms))
    last_sound = start + (sounding[-1] + 1) * FRAME
    last_change = max((t for t, _ in values), default=start)
    final = values[-1][1] if values else closed
    closed_after = last_change - last_sound if final == closed else float("inf")
    # before the first speech (but for the opening ahead of it), after the last (but
    # for the closing), and in each long silence between two speech frames
    quiet = [(start, start + sounding[0] * FRAME - OPENING), (last_sound + CLOSING, np.inf)]
    silences = 0
    for a, b in zip(sounding[:-1], sounding[1:], strict=True):
        if (b - a - 1) * FRAME > LONG_SILENCE:
            silences += 1
            quiet.append((start + (a + 1) * FRAME + CLOSING, start + b * FRAME - OPENING))
    still = all(_still(values, closed, a, b) for a, b in quiet)
    return Figures(len(rms) * FRAME, correlation(jaw, loud, best), best * FRAME,
                   closed_after, still, silences, float(len(rms) - 1 - sounding[-1]) * FRAME,
                   max((v for _, v in values), default=closed),
                   *frames_reached(values, planned, closed))


def _still(values: list[tuple[float, int]], closed: int, a: float, b: float) -> bool:
    """Does no value the board receives between ``a`` and ``b`` change the jaw?"""
    before = held(values, closed, np.array([a]))[0]
    return all(v == before for t, v in values if a < t < b)


def said(wav: bytes, folder, with_head: bool = True) -> tuple[Figures, float]:
    """Compile ``say`` of the WAV bytes on the ``inmoov`` profile (while the head looks
    around, unless not ``with_head``), read what its head board receives and measure it;
    also the plan's jaw at most (as a share of the mouth wide open)."""
    from pathlib import Path

    from inmoov_dsl.compiling.compiler import compile_program
    from inmoov_dsl.language.load import load
    from inmoov_dsl.profiles.profile import load_profile

    profile = load_profile("inmoov")
    jaw = profile.servos[profile.index("jaw")]
    head = next(b for b in profile.boards if jaw.name in b.servos)
    folder = Path(folder)
    (folder / "said.wav").write_bytes(wav)
    text = f'use "body.gest"\ng: say "said.wav"{" & look_around" if with_head else ""}\n'
    library = Path(__file__).resolve().parent.parent / "gestures"
    program = load(str(folder / "said.gest"), text, search=[str(folder), str(library)])
    compiled, plan = compile_program(program, "g", profile)
    stream = next(s for s in compiled.streams if s.board == head.id)
    (cue,) = compiled.sounds
    values = received(stream.times, stream.data, stream.byte_time, jaw.id)
    moments = frame_moments(plan.duration)
    track = plan.tracks[profile.index("jaw")]
    planned = track.position(moments.ravel()).reshape(moments.shape)
    voice = profile.voice
    return (measure(wav, cue.start, values, voice.closed, planned),
            (float(planned.max()) - voice.closed) / (voice.opened - voice.closed))
