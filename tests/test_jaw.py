"""The jaw with the voice, measured as a viewer sees it (tests/jawmeasure.py: the
loudness from the WAV bytes, the jaw from the bytes its board receives, nothing of the
planner's code), on speech from espeak-ng and on recorded human speech converted by sox
into other WAV formats. Every figure is benchmarks/voice.py's; here, a few sounds held
to the goals: r >= 0.85 at the best shift, that shift the planned lead (20-60 ms ahead),
the mouth closed within 150 ms of the last speech, still in long silences and in a
recording's hiss, every jaw value in its frame, and the mouth opening wide; and a
recording's hiss, or a quiet voice, judged against the sound's own noise floor."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest
from jawmeasure import CLOSING, FORMATS, RECORDINGS, converted, said, spoken
from toolchain import need


def espeak(text: str, voice: str, speed: int) -> bytes:
    need("espeak-ng", packages="espeak-ng")
    return spoken(text, voice, speed)


def recording(name: str, tmp_path: Path, *sox: str, effects: tuple[str, ...] = ()) -> bytes:
    """Debian's recorded ``name`` (alsa-utils), converted by sox with ``sox`` options
    and ``effects``."""
    need("sox", str(RECORDINGS / f"{name}.wav"), packages="sox alsa-utils")
    return converted(RECORDINGS / f"{name}.wav", tmp_path / f"{name}.wav", *sox,
                     effects=effects)


SOUNDS = {
    # quick speech in a woman's voice: the hardest sentence of the benchmark
    "espeak, quick": lambda tmp: espeak(
        "Good morning everyone, welcome to the maker faire.", "en-us+f3", 200),
    # the profile's voice, with a pause between two sentences
    "espeak, a pause": lambda tmp: espeak(
        "Hello, I am InMoov. I can wave and talk.", "en", 150),
    "recorded, 8-bit mono 8 kHz": lambda tmp: recording(
        "Front_Center", tmp, "-b", "8", "-e", "unsigned-integer", "-c", "1", "-r", "8000"),
    "recorded, 16-bit stereo 16 kHz": lambda tmp: recording(
        "Front_Right", tmp, "-b", "16", "-c", "2", "-r", "16000"),
    "recorded, as shipped (48 kHz)": lambda tmp: recording("Rear_Left", tmp),
}


@pytest.mark.parametrize("sound", SOUNDS)
def test_the_jaw_the_board_receives_moves_with_the_sound(sound, tmp_path):
    figures, widest = said(SOUNDS[sound](tmp_path), tmp_path)
    assert figures.r >= 0.85, figures
    assert 0.020 <= figures.shift <= 0.060, figures  # ahead of the sound, as planned
    assert figures.closed_after <= CLOSING, figures
    assert figures.still_in_silence, figures
    assert figures.reached == figures.needed > 0, figures
    assert widest >= 0.6  # it visibly opens: not a twitch that correlates


@pytest.mark.parametrize("form", FORMATS)
def test_in_a_recording_s_hiss_the_jaw_closes_after_the_speech_and_stays_shut(form, tmp_path):
    """Debian's "Front Left" in 8 bits holds hiss at about 2% of its loudest, and after
    the speech a faint tail (4-5%) hardly louder than the hiss: judged against a fixed
    3%, the jaw followed it, about 6 degrees open for 300 ms after the speech. Judged
    against the sound's own hiss, the jaw closes as the speech ends (speech by the
    measure: well above the hiss) and stays still in the hiss, in every format."""
    figures, widest = said(recording("Front_Left", tmp_path, *FORMATS[form]), tmp_path)
    if form == "8-bit mono 8 kHz":
        assert figures.tail >= 0.4, figures  # the measure hears hiss after the speech
    assert figures.closed_after <= CLOSING, figures
    assert figures.still_in_silence, figures  # nor does it move in the hiss before
    assert figures.r >= 0.85 and widest >= 0.6, figures  # the speech still opens it


@pytest.mark.parametrize("form", ["16-bit mono 48 kHz", "8-bit mono 8 kHz"])
def test_a_quiet_voice_still_opens_the_jaw(form, tmp_path):
    """The same recording 20 dB quieter (sox ``vol 0.1``): in 16 bits still clean, the
    jaw moves as with the loud one; in 8 bits a voice in loud hiss (about 16% of its
    loudest), the jaw still opens wide with the speech and stays shut in the hiss."""
    quiet, widest = said(recording("Front_Left", tmp_path, *FORMATS[form],
                                   effects=("vol", "0.1")), tmp_path)
    assert quiet.r >= 0.85 and 0.020 <= quiet.shift <= 0.060, quiet
    assert quiet.closed_after <= CLOSING and quiet.still_in_silence, quiet
    assert widest >= 0.6, quiet
    if form.startswith("16-bit"):
        loud, loud_widest = said(recording("Front_Left", tmp_path, *FORMATS[form]), tmp_path)
        assert abs(quiet.r - loud.r) < 0.01 and abs(widest - loud_widest) < 0.02


def test_a_long_silence_inside_a_sound_holds_the_jaw_still(tmp_path):
    """The recordings say two words with a pause between: the pause is a silence the jaw
    waits through, closed and still."""
    figures, _ = said(recording("Rear_Left", tmp_path), tmp_path, with_head=False)
    assert figures.silences >= 1 and figures.still_in_silence


def test_without_scipy_a_say_is_an_error_at_the_step_saying_how(tmp_path, monkeypatch):
    import numpy as np
    from test_voice import INMOOV, wav

    from inmoov_dsl.compiling.compiler import compile_source
    from inmoov_dsl.errors import GestError

    (tmp_path / "v.wav").write_bytes(wav(np.zeros(2205)))
    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec",
                        lambda name, *a: None if name == "scipy" else real(name, *a))
    with pytest.raises(GestError) as info:
        compile_source('hi: say "v.wav"\n', profile=INMOOV, file=str(tmp_path / "s.gest"))
    text = str(info.value)
    assert "s.gest:1:5: error: planning the mouth for 'say' needs scipy" in text
    assert "pip install 'inmoov-dsl[voice]'" in text


def test_the_plot_of_a_say_draws_the_sound_its_loudness_and_the_jaw_received(tmp_path):
    pytest.importorskip("matplotlib")
    import numpy as np
    from jawmeasure import received
    from test_voice import INMOOV, vowel, wav

    from inmoov_dsl.compiling.compiler import compile_program
    from inmoov_dsl.language.load import load
    from inmoov_dsl.views.plot import figure

    (tmp_path / "v.wav").write_bytes(wav(vowel()))
    program = load(str(tmp_path / "g.gest"), 'g: say "v.wav" & neck 100 over 1s\n')
    compiled, plan = compile_program(program, "g", INMOOV)
    row = figure(plan, compiled).axes[0]
    assert row.get_title(loc="left") == 'say "v.wav" at 0.00 s'
    lines = {line.get_label(): line for line in row.get_lines()}
    assert set(lines) == {"its loudness", "the jaw as its board receives it\n(0 closed, 1 open)"}
    # the jaw drawn is every value the head's board reads, as a share of open
    jaw = INMOOV.servos[INMOOV.index("jaw")]
    head = next(s for s in compiled.streams if s.board == 183)
    values = [v for _, v in received(head.times, head.data, head.byte_time, jaw.id)]
    drawn = lines["the jaw as its board receives it\n(0 closed, 1 open)"].get_ydata()
    assert np.allclose(drawn[1:-1], np.array(values) / INMOOV.voice.opened)
    assert max(values) >= 0.8 * INMOOV.voice.opened  # the vowel opens it wide
