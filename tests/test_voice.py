"""``say``: the step in the language, the profile's [voice], sounds from WAV files and
espeak-ng, and the mouth's track: within its servo's limits, closed in silence, open on
a long vowel, closed soon after the sound ends. Bad input is an error at its place."""

import io
import os
import shutil
import wave

import numpy as np
import pytest
from conftest import board_toml, servo_toml

from inmoov_dsl.compiling import speech
from inmoov_dsl.compiling.compiled import to_json
from inmoov_dsl.compiling.compiled_reader import from_json
from inmoov_dsl.compiling.compiler import compile_source
from inmoov_dsl.errors import GestError
from inmoov_dsl.language.fmt import format_source
from inmoov_dsl.language.parse import parse
from inmoov_dsl.profiles.profile import load_profile, parse_profile
from inmoov_dsl.voice import speak as speaking
from inmoov_dsl.voice.wav import SoundError, read_wav

INMOOV = load_profile("inmoov")
JAW = INMOOV.index("jaw")


def wav(samples, rate=22050, width=2, channels=1) -> bytes:
    """PCM WAV bytes of ``samples`` (-1..1) at ``width`` bytes per sample."""
    x = np.repeat(np.asarray(samples, dtype=np.float64)[:, None], channels, axis=1).ravel()
    if width == 1:
        raw = np.clip(np.round(x * 127 + 128), 0, 255).astype(np.uint8).tobytes()
    elif width == 3:
        v = np.round(x * (2 ** 23 - 1)).astype(np.int32)
        raw = np.stack([v & 255, (v >> 8) & 255, (v >> 16) & 255], 1).astype(np.uint8).tobytes()
    else:
        kind = np.int16 if width == 2 else np.int32
        raw = np.round(x * (2 ** (8 * width - 1) - 1)).astype(kind).tobytes()
    out = io.BytesIO()
    with wave.open(out, "wb") as w:
        w.setnchannels(channels)
        w.setsampwidth(width)
        w.setframerate(rate)
        w.writeframes(raw)
    return out.getvalue()


def vowel(rate=22050, silence=0.5, sound=0.8, after=0.5, noise=0.0):
    """Silence, a long loud vowel (a 180 Hz tone), silence; a little noise if asked."""
    t = np.arange(int(rate * sound)) / rate
    parts = [np.zeros(int(rate * silence)), 0.6 * np.sin(2 * np.pi * 180 * t),
             np.zeros(int(rate * after))]
    x = np.concatenate(parts)
    return x + noise * np.random.default_rng(1).standard_normal(len(x))


# -- the language -------------------------------------------------------------------------
def test_say_is_a_step_that_composes_like_any_other():
    (gesture,) = parse('g:\n    say "hi.wav" & index 90\n    say "Hello, I am InMoov"\n',
                       "s.gest").items
    together, said = gesture.steps
    assert [type(p).__name__ for p in together.parts] == ["Say", "Move"]
    assert together.parts[0].is_file and not said.is_file
    assert said.text_pos.column == 9  # the string, for errors about the sound
    assert format_source('g:  say  "hi"   &  wave\n', "s.gest") == 'g: say "hi" & wave\n'
    with pytest.raises(GestError, match="'say' is a keyword and cannot name a gesture"):
        parse("say: index 9", "s.gest")


# -- the profile --------------------------------------------------------------------------
def test_the_robot_profile_names_its_mouth():
    voice = INMOOV.voice
    assert (voice.mouth, voice.closed, voice.opened) == ("jaw", 0, 150)


@pytest.mark.parametrize(("table", "error"), [
    ('mouth = "jw"', "[voice]: 'mouth' must be a servo of the profile, got 'jw'"),
    ('mouth = "a"\nclosed = 9\nopen = 9', "[voice]: 'closed' and 'open' must differ"),
    ('mouth = "a"\nopen = 200', "[voice]: 'open' must be a whole number in a's range 0..180"),
    ('mouth = "a"\nvoice = "en; rm -rf"', "[voice]: 'voice' must be an espeak-ng voice name"),
    ('mouth = "a"\nspeed = 5', "[voice]: 'speed' must be a whole number in 80..450"),
])
def test_a_voice_table_that_is_wrong_says_where(table, error):
    text = board_toml(181, ["a"]) + servo_toml("a", 1) + "[voice]\n" + table
    with pytest.raises(GestError) as info:
        parse_profile(text, "v.toml")
    assert info.value.first.message.startswith(error)
    assert info.value.first.pos.line > text.count("\n") - table.count("\n") - 1


def test_say_on_a_profile_without_a_mouth_is_an_error_at_the_say():
    with pytest.raises(GestError) as info:
        compile_source('g: say "Hello"', profile="rhand", file="s.gest")
    d = info.value.first
    assert (d.message, d.pos.line, d.pos.column) == (
        "profile 'rhand' has no [voice]: no mouth moves with 'say'", 1, 4)
    assert d.hint == ("play it on a robot whose profile names its mouth in [voice] "
                      "(robot inmoov)")


# -- sounds -------------------------------------------------------------------------------
@pytest.mark.parametrize("width", [1, 2, 3, 4])
@pytest.mark.parametrize(("rate", "channels"), [(8000, 1), (22050, 2), (44100, 1),
                                                (48000, 2)])
def test_pcm_wav_of_any_width_rate_and_channels_is_read(width, rate, channels):
    sound = read_wav(wav(vowel(rate), rate, width, channels), "v.wav")
    assert sound.rate == rate and abs(sound.duration - 1.8) < 1e-3
    loud = np.abs(sound.samples[int(0.5 * rate):int(1.3 * rate)]).max()
    assert 0.55 < loud < 0.65 and np.abs(sound.samples[:int(0.4 * rate)]).max() < 0.01


def test_a_file_that_is_not_pcm_wav_is_refused_with_what_it_is(tmp_path):
    float_wav = bytearray(wav(vowel()))
    float_wav[20:22] = (3).to_bytes(2, "little")  # IEEE float: not PCM
    empty = wav(np.zeros(0))
    long = bytearray(wav(np.zeros(100)))
    long[24:28] = (8).to_bytes(4, "little")  # 8 samples a second: 100 samples, 12.5 s...
    cases = [(b"ID3\x03mp3 data", "'x.wav' is not a WAV file"),
             (bytes(float_wav), "'x.wav' is not a WAV file say can play (unknown format: 3)"),
             (empty, "'x.wav' holds no sound (0 samples)")]
    for data, message in cases:
        with pytest.raises(SoundError) as info:
            read_wav(data, "x.wav")
        assert info.value.message == message
    hour = bytearray(wav(np.zeros(1000), rate=1))  # 1,000 s at 1 sample a second
    with pytest.raises(SoundError, match="lasts 1,000 s, more than 600 s"):
        read_wav(bytes(hour), "x.wav")


def test_a_missing_or_wrong_sound_file_is_an_error_at_the_string(tmp_path):
    (tmp_path / "notes.txt.wav").write_text("not a sound")
    (tmp_path / "a.gest").write_text('g:\n    say "nowhere.wav"\n')
    (tmp_path / "b.gest").write_text('g: say "notes.txt.wav" & neck 90\n')
    for name, line, column, message in (("a.gest", 2, 9, "cannot find 'nowhere.wav'"),
                                        ("b.gest", 1, 8,
                                         "'notes.txt.wav' is not a WAV file")):
        with pytest.raises(GestError) as info:
            compile_source((tmp_path / name).read_text(), profile=INMOOV,
                           file=str(tmp_path / name))
        d = info.value.first
        assert (d.message, d.pos.line, d.pos.column) == (message, line, column)


def test_text_too_long_or_espeak_missing_or_failing_is_an_error_at_the_string(monkeypatch):
    with pytest.raises(GestError) as info:  # longer than a line may be
        compile_source(f'g: say "{"a" * 100_000}"', profile=INMOOV, file="s.gest")
    assert info.value.first.message == "this line is longer than 10,000 characters (100,009)"
    with pytest.raises(GestError) as info:
        compile_source(f'g: say "{"a" * 5_000}"', profile=INMOOV, file="s.gest")
    assert info.value.first.message == ("the text to speak has 5,000 characters, more "
                                        "than 1,000")
    assert info.value.first.pos.column == 8
    monkeypatch.setattr(shutil, "which", lambda name: None)
    with pytest.raises(GestError) as info:
        compile_source('g: say "Hello"', profile=INMOOV, file="s.gest")
    assert info.value.first.message == "speaking text needs espeak-ng, which is not installed"
    assert "apt-get install espeak-ng" in info.value.first.hint


def need_espeak():
    if shutil.which("espeak-ng") is None:
        if os.environ.get("CI") == "true":
            pytest.fail("CI: needs espeak-ng (apt-get install espeak-ng)")
        pytest.skip("needs espeak-ng (apt-get install espeak-ng)")


def test_espeak_failing_names_the_voice():
    need_espeak()
    with pytest.raises(SoundError) as info:
        speaking.speak("Hello", "xx-nosuch", 150, 50)
    assert info.value.message.startswith("espeak-ng failed: ")
    assert "is 'xx-nosuch' one of its voices?" in info.value.hint


# -- the mouth ----------------------------------------------------------------------------
def mouth(samples, rate=22050):
    sound = read_wav(wav(samples, rate), "v.wav")
    s = speech.heard(sound, JAW, INMOOV.voice)
    track, moved, wait = speech.track(s, INMOOV.servos[JAW], INMOOV.voice.closed)
    assert wait == 0  # the sound begins with silence: no wait
    return sound, track, moved


def test_a_long_vowel_holds_the_mouth_open_and_silence_keeps_it_closed():
    sound, track, moved = mouth(vowel(noise=0.002))  # with noise in the silences
    voice = INMOOV.voice
    quiet = track.position(np.arange(0.0, 0.3, 0.01))
    assert np.all(quiet == voice.closed)  # no chatter on the noise before the sound
    held = track.position(np.arange(0.7, 1.1, 0.01))
    assert np.all(held > voice.opened - 5)  # the vowel holds it open
    end = 1.3  # the sound's end: closed and still 0.2 s later
    after = np.arange(end + 0.2, sound.duration, 0.01)
    assert np.all(track.position(after) == voice.closed)
    assert np.all(np.abs(track.velocity(after)) < 1e-9)


def test_the_mouth_stays_within_its_servo_s_limits():
    need_espeak()
    sound = read_wav(speaking.speak("Hello, I am InMoov, the robot you can print.", "en",
                                    150, 45), "hello")
    s = speech.heard(sound, JAW, INMOOV.voice)
    servo = INMOOV.servos[JAW]
    track, moved, _ = speech.track(s, servo, 0)
    t = np.arange(0, moved, 0.0005)
    assert np.abs(track.velocity(t)).max() <= servo.max_velocity * (1 + 1e-9)
    assert np.abs(track.acceleration(t)).max() <= servo.max_acceleration * (1 + 1e-9)
    jerk = track.coefs[:, 3]
    assert np.abs(jerk).max() <= servo.max_jerk * (1 + 1e-9)
    positions = track.position(t)
    assert positions.min() >= servo.lo - 1e-6 and positions.max() <= servo.hi + 1e-6


def test_a_compiled_say_keeps_its_sound_and_reads_back(tmp_path):
    (tmp_path / "v.wav").write_bytes(wav(vowel()))
    source = 'hi: say "v.wav" & neck 120 over 1s\n'
    compiled = compile_source(source, profile=INMOOV, file=str(tmp_path / "s.gest"))
    (cue,) = compiled.sounds
    assert (cue.start, cue.said, cue.file) == (0.0, "v.wav", str(tmp_path / "v.wav"))
    assert compiled.duration >= cue.duration
    again = from_json(to_json(compiled))
    assert again.sounds == compiled.sounds and again.sounds[0].sound is None


def test_gestc_show_and_plot_show_the_sound_beside_the_mouth(tmp_path, capsys):
    from inmoov_dsl.cli import gestc

    (tmp_path / "v.wav").write_bytes(wav(vowel()))
    (tmp_path / "g.gest").write_text('g: say "v.wav" & neck 100 over 1s\n')
    argv = [str(tmp_path / "g.gest"), "--profile", "inmoov"]
    assert gestc.main(["show", *argv]) == 0
    out = capsys.readouterr().out.splitlines()
    head = next(k for k, line in enumerate(out) if line.startswith('say "v.wav"'))
    assert out[head] == ('say "v.wav" at 0.000 s: 1.80 s of sound; the jaw opens 0..150, '
                         'leading the sound by 40 ms')
    loud, jaw = out[head + 1], out[head + 2]
    assert loud.startswith("     0.00 s  loudness  ") and jaw.lstrip().startswith("jaw ")
    bars = loud[len("     0.00 s  loudness  "):]
    assert bars[:9].strip() == "" and set(bars[11:25]) == {"█"}  # silence, then the vowel
    pytest.importorskip("matplotlib")
    assert gestc.main(["plot", *argv, "-o", str(tmp_path / "g.png")]) == 0
    assert (tmp_path / "g.png").stat().st_size > 10_000
