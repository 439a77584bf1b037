"""A WAV file's sound (pure: bytes in, samples out): PCM, 8, 16, 24 or 32 bits, mono or
stereo (mixed to mono), any sample rate. Anything else is a ``SoundError`` saying what
the file is and what is taken.

The file is read a second at a time, and a rate above KEPT_RATE is kept as the mean of
each few samples (a whole number of them) down to at most KEPT_RATE: what speech needs
and what a speaker plays, so that the samples of the longest, fastest file allowed take
a hundred-odd MB, not a GB."""

from __future__ import annotations

import hashlib
from dataclasses import dataclass, field

import numpy as np

MAX_SECONDS = 600.0  #: the longest sound a step may say (10 minutes)
MAX_RATE = 384_000  #: samples per second
KEPT_RATE = 48_000  #: samples per second kept, at most


class SoundError(Exception):
    """A sound that cannot be had: what, and what to do (a hint)."""

    def __init__(self, message: str, hint: str | None = None):
        super().__init__(message)
        self.message, self.hint = message, hint


@dataclass(frozen=True, eq=False)
class Sound:
    """Mono samples in -1..1 at ``rate`` per second (the file's, or a whole fraction of
    it); ``digest`` names the bytes they came from; ``source``: the file or the text, as
    the step says it."""

    samples: np.ndarray = field(repr=False)
    rate: float
    source: str
    digest: str
    path: str = ""  #: the file it was read from (none for spoken text)

    @property
    def duration(self) -> float:
        """Seconds."""
        return len(self.samples) / self.rate


def read_wav(data: bytes, source: str) -> Sound:
    """The sound of WAV bytes ``data`` (``source`` names them in messages)."""
    import io
    import wave  # (imported when a sound is first read)

    if data[:4] != b"RIFF" or data[8:12] != b"WAVE":
        raise SoundError(f"'{source}' is not a WAV file", "say takes a PCM .wav file, or "
                         "text to speak: say \"Hello\"")
    try:
        with wave.open(io.BytesIO(data)) as w:
            channels, width, rate, frames = (w.getnchannels(), w.getsampwidth(),
                                             w.getframerate(), w.getnframes())
            _check(source, channels, rate, width)
            wanted = min(frames, int(MAX_SECONDS * rate) + 1)
            samples, got = _read(w, wanted, width, channels, _factor(rate))
            frames = frames if got == wanted else got  # (a header written to a pipe
            # says the most it can: the file holds less)
    except (wave.Error, EOFError, ValueError, RuntimeError, OverflowError) as exc:
        # (wave's chunk reader raises a bare RuntimeError on a chunk cut short)
        raise SoundError(f"'{source}' is not a WAV file say can play "
                         f"({str(exc) or 'a chunk is cut short'})",
                         "save it as PCM WAV (8, 16, 24 or 32 bits): compressed WAV is not "
                         "read") from None
    if frames == 0 or not len(samples):
        raise SoundError(f"'{source}' holds no sound (0 samples)")
    if frames / rate > MAX_SECONDS:
        raise SoundError(f"'{source}' lasts {frames / rate:,.0f} s, more than "
                         f"{MAX_SECONDS:.0f} s", "split it into shorter sounds")
    return Sound(samples, rate / _factor(rate), source, hashlib.sha256(data).hexdigest())


def _check(source: str, channels: int, rate: int, width: int) -> None:
    """What the header says is a sound this module reads."""
    if not 1 <= channels <= 2 or not 0 < rate <= MAX_RATE:
        raise SoundError(f"'{source}' has {channels} channels at {rate} Hz",
                         "say plays mono or stereo WAV at up to 384 kHz")
    if width not in (1, 2, 3, 4):
        raise SoundError(f"'{source}' has samples of {8 * width} bits", "save the file as "
                         "PCM WAV of 8, 16, 24 or 32 bits")


def _factor(rate: int) -> int:
    """How many of the file's samples each kept one averages."""
    return max(1, -(-rate // KEPT_RATE))


def _read(w, wanted: int, width: int, channels: int, factor: int
          ) -> tuple[np.ndarray, int]:
    """Up to ``wanted`` frames of ``w``, a second at a time, mixed to mono and averaged
    ``factor`` at a time (float32); and how many frames were read."""
    size = width * channels
    block = max(factor, w.getframerate() // factor * factor)  # about a second
    out = np.empty(wanted // factor + 1, np.float32)
    kept = got = 0
    while got < wanted:
        asked = min(block, wanted - got)
        raw = w.readframes(asked)
        count = len(raw) // size
        mono = _samples(raw[:count * size], width).reshape(-1, channels).mean(axis=1)
        whole = count // factor * factor  # (only the file's last block can leave some)
        mono = mono[:whole].reshape(-1, factor).mean(axis=1) if whole else mono[:0]
        out[kept:kept + len(mono)] = mono
        kept, got = kept + len(mono), got + count
        if count < asked:  # the file ends
            break
    # (a header written to a pipe claims more than the file holds: keep only what it does)
    return (out[:kept] if kept + 1 >= len(out) else out[:kept].copy()), got


def _samples(raw: bytes, width: int) -> np.ndarray:
    """Whole PCM samples of ``width`` bytes (1 to 4: ``_check``) as floats in -1..1
    (8-bit WAV is unsigned, the rest signed)."""
    if width == 1:
        return (np.frombuffer(raw, np.uint8).astype(np.float64) - 128) / 128
    if width == 3:
        b = np.frombuffer(raw, np.uint8).reshape(-1, 3).astype(np.int32)
        values = b[:, 0] | (b[:, 1] << 8) | (b[:, 2] << 16)
        return np.where(values & 0x800000, values - (1 << 24), values) / float(1 << 23)
    kind = np.int16 if width == 2 else np.int32
    return np.frombuffer(raw, kind) / float(1 << (8 * width - 1))
