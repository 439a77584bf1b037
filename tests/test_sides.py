"""A gesture on either side of the robot: ``left peace`` in a gesture, ``gestplay peace
--hand left``, through the profile's ``[sides]``."""

from __future__ import annotations

import pytest
from boardmodel import final_values, read_stream

from inmoov_dsl.cli import gestplay
from inmoov_dsl.compiling.compiler import compile_program
from inmoov_dsl.errors import GestError
from inmoov_dsl.language.fmt import format_source
from inmoov_dsl.language.load import load
from inmoov_dsl.profiles.profile import load_profile, parse_profile
from inmoov_dsl.resources import profiles_dir
from inmoov_dsl.wire import link

INMOOV = load_profile("inmoov")
PEACE = "peace: thumb 180, ring 180, pinky 180, index 0, middle 0 over 0.7s\n"
BOTH = "both: r_index 90, l_index 90\n"


def moves(source, gesture="g", profile=INMOOV, side=None):
    """Each board's final values (servo ID -> value) of the boards the gesture moves."""
    compiled, _ = compile_program(load("t.gest", source), gesture, profile, side=side)
    return {s.board: final_values(read_stream(s.times, s.data, s.baud), {})
            for s in compiled.streams if len(s.data) > 1}


def test_left_peace_is_peace_on_the_left_hands_board():
    right = moves(PEACE + "g: peace\n")
    left = moves(PEACE + "g: left peace\n")
    assert set(right) == {181} and set(left) == {183}
    # the same values, each servo's partner: IDs 1..5 on the right, 7..11 on the left
    assert {sid + 6: v for sid, v in right[181].items()} == left[183]


def test_hand_left_plays_the_gesture_on_the_left_hand(capsys):
    assert gestplay.main(["peace", "--profile", "inmoov", "--hand", "left", "--dry-run"]) == 0
    boards = capsys.readouterr().out.split("# board ")[1:]
    sent = {int(b.split("\n", 1)[0]): len(b.strip().splitlines()) - 1 for b in boards}
    assert sent[183] > 100 and all(n == 1 for b, n in sent.items() if b != 183)  # CANCEL


def test_one_port_plays_a_hand_gesture_on_the_left_hand(virtual_clock, capsys, monkeypatch):
    opened = []

    class Silent:
        def write(self, data):
            pass

        def read(self, size=1):
            return b""

        def close(self):
            pass

        in_waiting = 0

    monkeypatch.setattr(link, "open_port",
                        lambda name, baud, timeout=0: opened.append(name) or Silent())
    assert gestplay.main(["peace", "--profile", "inmoov", "--hand", "left", "--port", "COM4",
                          "--blind"]) == 0
    assert opened == ["COM4"]
    assert "board 183 on COM4 did not answer (--blind)" in capsys.readouterr().err


def test_right_brings_a_left_hand_gesture_to_the_right():
    source = "wave_l: l_wrist 180, l_index 90\ng: right wave_l\n"
    assert moves(source) == {181: {0: 180, 2: 90}}
    assert moves(source, "wave_l", side="right") == {181: {0: 180, 2: 90}}


def test_a_side_moves_arms_too_and_leaves_the_head_alone():
    source = "g: r_bicep 90, neck 120\n"
    assert moves(source, side="left") == {183: {24: 90, 12: 120}}  # the left Mega


@pytest.mark.parametrize(("source", "profile", "side", "message"), [
    (PEACE + "g: left peace\n", "rhand", None,
     "t.gest:2:4: error: profile 'rhand' has no [sides]: it cannot play 'peace' on the left"),
    (PEACE + "g: peace\n", "rhand", "left",
     "error: profile 'rhand' has no [sides]: it cannot play 'g' on the left"),
    (BOTH + "g: left both\n", "inmoov", None,
     "t.gest:2:4: error: on the left, 'both' would set 'l_index' twice in one step: it "
     "moves both sides"),
    ("g: left index 90\n", "inmoov", None,
     "t.gest:1:4: error: 'left' goes before a gesture's name, alone on its step"),
    ("g: left peace, index 90\n", "inmoov", None,
     "t.gest:1:4: error: 'left' goes before a gesture's name, alone on its step"),
])
def test_a_side_where_it_cannot_be_is_an_error(source, profile, side, message):
    with pytest.raises(GestError) as caught:
        moves(source, profile=load_profile(profile), side=side)
    assert caught.value.diagnostics[0].format().startswith(message)


@pytest.mark.parametrize(("change", "message", "line"), [
    (("r_omoplate\"]\nleft", "r_omoplate\", \"neck\"]\nleft"),
     "[sides] right has 11 servos and left 10: each needs its mirror image", "left = ["),
    (("left = [\"l_wrist\", \"l_thumb\"", "left = [\"l_wrist\", \"l_thmb\""),
     "[sides] left names unknown servo 'l_thmb'", "l_thmb"),
    (("left = [\"l_wrist\", \"l_thumb\"", "left = [\"l_wrist\", \"r_thumb\""),
     "servo 'r_thumb' is on the right side already", "left = [\"l_wrist\", \"r_thumb\""),
])
def test_a_bad_sides_table_is_an_error_at_its_line(change, message, line):
    text = (profiles_dir() / "inmoov.toml").read_text()
    assert change[0] in text
    with pytest.raises(GestError) as caught:
        parse_profile(text.replace(*change), "robot.toml")
    first = caught.value.diagnostics[0]
    assert first.message == message
    assert first.pos.file == "robot.toml" and line in first.source_line


def test_fmt_keeps_the_side():
    assert format_source("g:\n    left   peace\n") == "g:\n    left peace\n"


def test_a_side_moves_each_part_of_a_step_at_once():
    source = PEACE + "nod: neck 120 over 0.5s\nboth: peace & nod\ng: left both\n"
    assert set(moves(source)) == {183}  # the left Mega (hand and head), not the right
    assert set(moves(source, profile="inmoov-six")) == {183, 184}


def test_a_compiled_file_stays_on_its_side(tmp_path, capsys):
    from inmoov_dsl.cli import gestc

    out = tmp_path / "peace.gestc"
    assert gestc.main(["compile", "peace", "-p", "inmoov", "-o", str(out)]) == 0
    capsys.readouterr()
    assert gestplay.main([str(out), "--hand", "left", "--dry-run"]) == 1
    assert capsys.readouterr().err.startswith("gestplay: error: --hand plays a gesture on "
                                              "the other side; a compiled file is for the "
                                              "side it was compiled for")
