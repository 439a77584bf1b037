"""Speaking out loud: a gesture's sounds are played from the same clock as its bytes,
each sound's first sample placed where the sound library says that block is heard (on a
fake output, exactly; on a virtual output, heard in order and never early: how close
to its time on a real machine is benchmarks/sound.py's figure); without a sound
library gestplay says how to get one, or plays in silence with --audio none."""

import builtins
import wave

import numpy as np
import pytest
import serial
from sound_server import sound_server  # noqa: F401 (a fixture)
from stopping import wait_for

from inmoov_dsl.cli import gestplay
from inmoov_dsl.compiling.compiler import compile_source
from inmoov_dsl.profiles.profile import load_profile
from inmoov_dsl.wire.player import Link, play

INMOOV = load_profile("inmoov")


def tone_wav(path, seconds=0.6, rate=44100):
    t = np.arange(int(rate * seconds)) / rate
    x = (0.5 * np.sin(2 * np.pi * 220 * t) * 32767).astype(np.int16)
    with wave.open(str(path), "wb") as w:
        w.setnchannels(1)
        w.setsampwidth(2)
        w.setframerate(rate)
        w.writeframes(x.tobytes())


class FakeOutput:
    """sounddevice's OutputStream as the Speaker uses it: it keeps the callback."""

    def __init__(self, callback, **kwargs):
        self.callback = callback

    def start(self):
        pass

    def stop(self):
        pass

    def close(self):
        pass


def test_a_sound_starts_on_the_sample_its_planned_time_is_heard(tmp_path, monkeypatch):
    """A block asked for at clock time 10.000 is heard 30 ms later: a sound planned for
    10.0425 starts 12.5 ms into it, on that sample, and its start is noted as heard then."""
    import types

    import sounddevice

    from inmoov_dsl.voice.wav import read_wav
    from inmoov_dsl.wire.audio import RATE, Speaker

    monkeypatch.setattr(sounddevice, "OutputStream", FakeOutput)
    tone_wav(tmp_path / "a.wav", rate=RATE)
    sound = read_wav((tmp_path / "a.wav").read_bytes(), "a.wav")
    clock = {"t": 10.0}
    speaker = Speaker(now=lambda: clock["t"])
    speaker.play(sound, 10.0425)
    frames = int(0.02 * RATE)
    for block in range(3):  # blocks of 20 ms, each asked for as the one before ends
        out = np.zeros((frames, 1), np.float32)
        timing = types.SimpleNamespace(currentTime=5.0, outputBufferDacTime=5.030)
        speaker.stream.callback(out, frames, timing, None)
        if block == 0:  # heard from 10.030 to 10.050: the sound from its 600th sample
            assert not out[:600].any() and out[601:].all()
        clock["t"] += 0.02
    assert speaker.heard == [(10.0425, pytest.approx(10.0425, abs=0.5 / RATE))]


def test_each_sound_is_heard_in_order_and_never_early(sound_server, tmp_path):  # noqa: F811
    from inmoov_dsl.wire.audio import Speaker

    tone_wav(tmp_path / "a.wav")
    source = ('g:\n    say "a.wav" & neck 100 over 0.5s\n    wait 0.3s\n'
              '    say "a.wav"\n    neck 90\n')
    compiled = compile_source(source, profile=INMOOV, file=str(tmp_path / "g.gest"))
    first = 0.0  # the first is said with the neck's move, from the start
    second = next(s.start for s in compiled.steps if s.kind == "say" and s.start > 0)
    # the tone starts loud at once: each waits the same, for the mouth to open
    wait = compiled.sounds[0].start - first
    assert 0.05 <= wait <= 0.2 and second > 0.9
    assert [q.start for q in compiled.sounds] == [round(first + wait, 9),
                                                   round(second + wait, 9)]
    links = [Link(b.id, serial.serial_for_url("loop://", timeout=0), "loop://")
             for b in INMOOV.boards]
    speaker = Speaker()
    try:
        assert speaker.wait_flowing(timeout=30)  # a busy machine starts the server slowly
        play(compiled, links, speaker=speaker)
        wait_for(lambda: len(speaker.heard) == 2, "both sounds heard", 30)
    finally:
        speaker.close()
    for planned, heard in speaker.heard:
        assert heard >= planned - 1e-3, (planned, heard)  # never early
    assert speaker.heard[1][0] - speaker.heard[0][0] == pytest.approx(second - first,
                                                                      abs=1e-6)


def test_without_a_sound_library_gestplay_says_how_or_plays_in_silence(virtual_clock, tmp_path,
                                                                        capsys, monkeypatch):
    tone_wav(tmp_path / "a.wav")
    (tmp_path / "g.gest").write_text('g: say "a.wav" & neck 100 over 0.5s\n')
    real_import = builtins.__import__

    def no_sounddevice(name, *args, **kwargs):
        if name == "sounddevice":
            raise ImportError("No module named 'sounddevice'")
        return real_import(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_sounddevice)
    argv = [str(tmp_path / "g.gest"), "--profile", "inmoov", "--port", "loop://",
            "--blind"]
    assert gestplay.main(argv) == 1
    err = capsys.readouterr().err
    assert "error: playing sound needs sounddevice and PortAudio" in err
    assert "pip install 'inmoov-dsl[voice]'" in err and "--audio none" in err
    assert gestplay.main([*argv, "--audio", "none"]) == 0
    assert capsys.readouterr().out.startswith("played g: ")


def test_say_plays_at_its_own_speed_only(virtual_clock, tmp_path, capsys):
    tone_wav(tmp_path / "a.wav")
    (tmp_path / "g.gest").write_text('g: say "a.wav"\n')
    assert gestplay.main([str(tmp_path / "g.gest"), "--profile", "inmoov", "--port",
                          "loop://", "--blind", "--speed", "0.5"]) == 1
    assert "'say' plays its sound at its own speed" in capsys.readouterr().err


def test_a_wav_changed_since_it_was_compiled_is_refused(virtual_clock, tmp_path, capsys):
    from inmoov_dsl.compiling.compiled import to_json

    tone_wav(tmp_path / "a.wav")
    compiled = compile_source('g: say "a.wav"\n', profile=INMOOV,
                              file=str(tmp_path / "g.gest"))
    (tmp_path / "g.gestc").write_text(to_json(compiled))
    tone_wav(tmp_path / "a.wav", seconds=0.5)
    assert gestplay.main([str(tmp_path / "g.gestc"), "--port", "loop://", "--blind",
                          "--audio", "default"]) == 1
    err = capsys.readouterr().err
    assert "error: '" in err and "a.wav' has changed since the gesture was compiled" in err

