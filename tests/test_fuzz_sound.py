"""Seeded bad WAV files: each is read as a sound or refused with a SoundError saying what
the file is, never another exception; a ``say`` of one is planned or is an error at its
string. (A RIFF file of nothing but a LIST chunk made Python's ``wave`` raise a bare
RuntimeError; a stereo file whose data ends mid-frame failed at a reshape.)"""

from __future__ import annotations

import random
import struct

import numpy as np
import pytest
from test_voice import INMOOV, wav

from inmoov_dsl.compiling.compiler import compile_source
from inmoov_dsl.errors import GestError
from inmoov_dsl.voice.wav import SoundError, read_wav


def base(width: int, channels: int, rate: int, seconds: float = 0.3) -> bytes:
    """A WAV of a tone with a pause (test_voice's ``wav`` writes it)."""
    t = np.arange(int(rate * seconds)) / rate
    return wav(0.5 * np.sin(2 * np.pi * 220 * t) * (t < seconds / 2), rate, width, channels)


BASES = [base(1, 1, 8000), base(2, 2, 22050), base(3, 1, 44100), base(4, 2, 48000),
         base(2, 1, 384000, 0.05)]
#: (offset, struct format) of the header's fields: sizes, format, channels, rate, width
FIELDS = [(4, "<I"), (16, "<I"), (20, "<H"), (22, "<H"), (24, "<I"), (28, "<I"),
          (32, "<H"), (34, "<H"), (40, "<I")]
ODD = [0, 1, 2, 3, 5, 7, 255, 256, 65535, 2 ** 31 - 1, 2 ** 32 - 1, 384001, 10 ** 9]


def mutant(rng: random.Random) -> bytes:
    """One to three mutations of a base WAV."""
    data = bytearray(rng.choice(BASES))
    for _ in range(rng.randint(1, 3)):
        how = rng.randrange(6)
        if how == 0:  # a header field made odd
            offset, kind = rng.choice(FIELDS)
            value = rng.choice(ODD) % (1 << (8 * struct.calcsize(kind)))
            data[offset:offset + struct.calcsize(kind)] = struct.pack(kind, value)
        elif how == 1:  # cut short anywhere
            del data[rng.randrange(len(data)):]
        elif how == 2:  # bytes flipped in the header
            for _ in range(rng.randint(1, 4)):
                data[rng.randrange(min(44, len(data) or 1))] ^= 1 << rng.randrange(8)
        elif how == 3:  # a chunk before the data, of any size
            chunk = b"LIST" + struct.pack("<I", rng.choice(ODD)) + bytes(rng.randrange(9))
            data[36:36] = chunk
        elif how == 4:  # a partial frame at the end
            data += bytes(rng.randint(1, 3))
        else:  # nothing but RIFF, WAVE and a chunk
            data = bytearray(b"RIFF" + struct.pack("<I", rng.choice(ODD)) + b"WAVELIST" +
                             bytes(rng.randrange(6)))
    return bytes(data)


def test_the_wavs_the_fuzzing_found():
    for data in [b"RIFF\x0d\x00\x00\x00WAVELIST\x01\x00\x00\x00",  # 21 bytes
                 b"RIFF\x0d\x00\x00\x00WAVELIST\x01\x00\x00"]:
        with pytest.raises(SoundError, match="is not a WAV file say can play"):
            read_wav(data, "x.wav")
    stereo = bytearray(base(2, 2, 8000))
    stereo += b"\x01\x02"  # half a frame more, the sizes saying so
    stereo[4:8] = struct.pack("<I", len(stereo) - 8)
    stereo[40:44] = struct.pack("<I", struct.unpack("<I", stereo[40:44])[0] + 2)
    sound = read_wav(bytes(stereo), "s.wav")
    assert abs(sound.duration - 0.3) < 1e-3  # the whole frames, and no more


def test_bad_wavs_are_sounds_or_clear_errors_and_say_plans_or_tells(tmp_path):
    rng = random.Random(35)
    for k in range(500):
        data = mutant(rng)
        try:
            sound = read_wav(data, "m.wav")
        except SoundError as exc:
            assert exc.message.startswith("'m.wav' "), (k, exc.message)
            continue
        assert sound.duration > 0 and np.isfinite(sound.samples).all(), k
        if k % 10:
            continue  # (a say of every tenth accepted: planning takes a while)
        (tmp_path / "m.wav").write_bytes(data)
        try:
            compile_source('g: say "m.wav"\n', profile=INMOOV, file=str(tmp_path / "g.gest"))
        except GestError as exc:
            assert all(d.pos is not None for d in exc.diagnostics), (k, str(exc))


def test_a_wav_written_to_a_pipe_is_read_for_what_it_holds():
    """espeak-ng --stdout writes its header before it knows the length: the sizes say
    the most they can."""
    data = bytearray(base(2, 1, 22050))
    data[4:8] = data[40:44] = struct.pack("<I", 0x7FFFFFFF)
    assert abs(read_wav(bytes(data), "p.wav").duration - 0.3) < 1e-3


@pytest.mark.parametrize(("rate", "kept"), [(8000, 8000), (48000, 48000), (96000, 48000),
                                             (384000, 48000), (352800, 44100)])
def test_a_fast_rate_is_kept_at_48_khz_at_most_and_lasts_as_long(rate, kept):
    sound = read_wav(base(2, 2, rate, 0.05), "r.wav")
    assert sound.rate == kept and abs(sound.duration - 0.05) < 1e-4
    assert sound.samples.dtype == np.float32
