"""A WAV file's sound (pure: bytes in, samples out): PCM, 8, 16, 24 or 32 bits, mono or
stereo (mixed to mono), any sample rate. Anything else is a ``SoundError`` saying what
the file is and what is taken."""

from __future__ import annotations

import hashlib
from dataclasses import dataclass, field

import numpy as np

MAX_SECONDS = 600.0  #: the longest sound a step may say (10 minutes)
MAX_RATE = 384_000  #: samples per second


class SoundError(Exception):
    """A sound that cannot be had: what, and what to do (a hint)."""

    def __init__(self, message: str, hint: str | None = None):
        super().__init__(message)
        self.message, self.hint = message, hint


@dataclass(frozen=True, eq=False)
class Sound:
    """Mono samples in -1..1 at ``rate`` per second; ``digest`` names the bytes they came
    from; ``source``: the file or the text, as the step says it."""

    samples: np.ndarray = field(repr=False)
    rate: int
    source: str
    digest: str
    wav: bytes = field(repr=False, default=b"")  #: the file's bytes, to play them as they are
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
            wanted = min(frames, int(MAX_SECONDS * min(rate, MAX_RATE)) + 1)
            raw = w.readframes(wanted)
    except (wave.Error, EOFError, ValueError) as exc:
        raise SoundError(f"'{source}' is not a WAV file say can play ({exc})",
                         "save it as PCM WAV (8, 16, 24 or 32 bits): compressed WAV is not "
                         "read") from None
    if not 1 <= channels <= 2 or not 0 < rate <= MAX_RATE:
        raise SoundError(f"'{source}' has {channels} channels at {rate} Hz",
                         "say plays mono or stereo WAV at up to 384 kHz")
    if len(raw) // (width * channels) < wanted:  # less than the header says (a WAV
        frames = len(raw) // (width * channels)  # written to a pipe says the most it can)
    if frames == 0:
        raise SoundError(f"'{source}' holds no sound (0 samples)")
    if frames / rate > MAX_SECONDS:
        raise SoundError(f"'{source}' lasts {frames / rate:,.0f} s, more than "
                         f"{MAX_SECONDS:.0f} s", "split it into shorter sounds")
    samples = _samples(raw[:frames * width * channels], width).reshape(-1, channels).mean(axis=1)
    return Sound(samples.astype(np.float32), rate, source,
                 hashlib.sha256(data).hexdigest(), data)


def _samples(raw: bytes, width: int) -> np.ndarray:
    """PCM bytes as floats in -1..1 (8-bit WAV is unsigned, the rest signed)."""
    if width == 1:
        return (np.frombuffer(raw, np.uint8).astype(np.float64) - 128) / 128
    if width == 3:
        b = np.frombuffer(raw[:len(raw) // 3 * 3], np.uint8).reshape(-1, 3).astype(np.int32)
        values = b[:, 0] | (b[:, 1] << 8) | (b[:, 2] << 16)
        return np.where(values & 0x800000, values - (1 << 24), values) / float(1 << 23)
    if width in (2, 4):
        kind = np.int16 if width == 2 else np.int32
        return np.frombuffer(raw[:len(raw) // width * width], kind) / float(1 << (8 * width - 1))
    raise SoundError(f"samples of {8 * width} bits are not read", "save the file as PCM WAV "
                     "of 8, 16, 24 or 32 bits")
