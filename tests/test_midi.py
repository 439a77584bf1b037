"""A MIDI take recorded as a gesture (``gestc record --midi take.mid --map map.toml``):
the take written by mido (a library we did not write), its map's mistakes told at their
keys, and the gesture's plan following the take within the tolerance, measured against
the take's own messages."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from inmoov_dsl.cli import gestc
from inmoov_dsl.compiling.compiler import compile_program
from inmoov_dsl.errors import GestError
from inmoov_dsl.language.load import load
from inmoov_dsl.live.controls import read_map
from inmoov_dsl.profiles.profile import load_profile

mido = pytest.importorskip("mido", reason="the [midi] extra brings mido")

MAP = """\
[[control]]
cc = 1            # the first fader
servo = "index"

[[control]]
cc = 2
channel = 1
servo = "middle"
low = 20          # the fader at its bottom
high = 160        # and at its top
"""


def fader(level_at, seconds: float, rate: float = 60.0) -> list[tuple[float, int]]:
    """(time, level 0..127) of a fader moved by hand: a message whenever its level
    changes, at most ``rate`` a second."""
    out, last = [], None
    for t in np.arange(0.0, seconds, 1 / rate):
        level = int(round(float(np.clip(level_at(t), 0, 127))))
        if level != last:
            out.append((float(t), level))
            last = level
    return out


def write_take(path: Path, moves: dict[int, list[tuple[float, int]]]) -> None:
    """A type-0 MIDI file of control changes on channel 1, at 120 bpm."""
    events = sorted((t, cc, level) for cc, levels in moves.items() for t, level in levels)
    take = mido.MidiFile(type=0, ticks_per_beat=480)
    track = mido.MidiTrack()
    take.tracks.append(track)
    tempo, before = mido.bpm2tempo(120), 0
    for t, cc, level in events:
        tick = round(mido.second2tick(t, take.ticks_per_beat, tempo))
        track.append(mido.Message("control_change", channel=0, control=cc, value=level,
                                  time=tick - before))
        before = tick
    take.save(path)


def smooth(a: float, b: float, start: float, end: float):
    """A level easing from ``a`` to ``b`` between ``start`` and ``end`` s, held outside."""
    def at(t: float) -> float:
        x = float(np.clip((t - start) / (end - start), 0, 1))
        return a + (b - a) * (3 * x * x - 2 * x * x * x)
    return at


def test_a_take_of_two_faders_becomes_a_short_gesture_that_ends_where_it_ends(tmp_path,
                                                                               capsys):
    index = smooth(0, 127, 0.2, 1.2)
    middle = lambda t: smooth(0, 127, 0.2, 1.2)(t) if t < 2.0 else smooth(127, 30, 2.0, 3.0)(t)  # noqa: E731
    moves = {1: fader(index, 3.4), 2: fader(middle, 3.4)}
    take, map_, out = tmp_path / "take.mid", tmp_path / "map.toml", tmp_path / "take.gest"
    write_take(take, moves)
    map_.write_text(MAP)
    assert gestc.main(["record", "--midi", str(take), "--map", str(map_), "-p", "rhand",
                       "-o", str(out)]) == 0
    said = capsys.readouterr().err
    assert f"wrote {out}: take, " in said and "it follows the recording within" in said
    text = out.read_text()
    steps = [row.strip() for row in text.splitlines() if row.startswith("    ")]
    assert 2 <= len(steps) <= 8, text  # motion, not samples: 164 messages in
    assert "index 180, middle 160 over" in text  # both faders up together, as one step
    _, plan = compile_program(load(str(out)), "take", "rhand")
    controls = read_map(MAP, "map.toml", plan.profile)
    ends = {c.servo: c.value(moves[cc][-1][1]) for c, cc in zip(controls, (1, 2), strict=True)}
    assert {i: plan.final[i] for i in ends} == ends  # where the take's faders ended
    # a fader moved smoothly over a second is a move the planner shapes its own way:
    # the recorder says how far its plan strays (docs/puppet.md)


@pytest.mark.parametrize(("text", "said"), [
    ("[[control]]\ncc = 1\nservo = \"indx\"\n", "map.toml:3:1: error: control 1: unknown "
     "servo 'indx'"),
    ("[[control]]\ncc = 128\nservo = \"index\"\n", "map.toml:2:1: error: control 1: 'cc' "
     "must be a MIDI control number, a whole number 0..127, got 128"),
    ("[[control]]\ncc = 1\nservo = \"index\"\n[[control]]\ncc = 2\nservo = \"index\"\n",
     "map.toml:6:1: error: servo 'index' is mapped twice"),
    ("[[control]]\ncc = 1\nservo = \"index\"\n[[control]]\ncc = 1\nservo = \"ring\"\n",
     "map.toml:5:1: error: control 1 is mapped twice"),
    ("[[control]]\ncc = 1\nservo = \"index\"\nhihg = 90\n", "map.toml:4:1: error: control "
     "1: unknown key 'hihg'"),
    ("[[control]]\ncc = 1\nservo = \"index\"\nchannel = 17\n", "'channel' must be a MIDI "
     "channel, a whole number 1..16, got 17"),
    ("[[contorl]]\ncc = 1\n", "map.toml:1:1: error: unknown table 'contorl'"),
    ("cc = [", "map.toml:1:1: error: invalid TOML"),
])
def test_each_mistake_of_a_map_is_told_at_its_key(text, said):
    with pytest.raises(GestError) as info:
        read_map(text, "map.toml", load_profile("rhand"))
    assert said in str(info.value)


def test_what_is_not_a_take_is_an_error_naming_it(tmp_path, capsys):
    (tmp_path / "map.toml").write_text(MAP)
    (tmp_path / "bad.mid").write_bytes(b"MThd\x00\x00\x00\x06garbage")
    args = ["record", "--map", str(tmp_path / "map.toml"), "-o", str(tmp_path / "x.gest")]
    assert gestc.main([*args, "--midi", str(tmp_path / "bad.mid")]) == 1
    assert f"'{tmp_path / 'bad.mid'}' is not a MIDI take that can be read" in \
        capsys.readouterr().err
    assert gestc.main([*args, "--midi", str(tmp_path / "none.mid")]) == 1
    assert "cannot read" in capsys.readouterr().err
    silent = tmp_path / "silent.mid"
    write_take(silent, {7: [(0.0, 3), (0.5, 90)]})  # a control the map does not take
    assert gestc.main([*args, "--midi", str(silent)]) == 1
    assert "has no control change that the map takes" in capsys.readouterr().err
    assert not (tmp_path / "x.gest").exists()  # nothing written
