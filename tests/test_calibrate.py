"""gestplay calibrate: the keys of teach at a real terminal, the result written into the profile."""

import os
import sys
from pathlib import Path

import pytest
from terminal import AtTerminal

from inmoov_dsl.errors import GestError
from inmoov_dsl.live.calibrate import HELP, Ends, edit_profile, found
from inmoov_dsl.profiles.profile import find_profile, load_profile, parse_profile

ROOT = Path(__file__).resolve().parent.parent

RHAND_TEXT = find_profile("rhand").read_text(encoding="utf-8")
RHAND = load_profile("rhand")
POSIX = pytest.mark.skipif(not hasattr(os, "openpty"), reason="pseudo-terminals are POSIX")


def servo(name):
    return RHAND.servos[RHAND.index(name)]


def test_the_ends_become_the_calibration_and_the_real_speed_is_kept():
    new = found(servo("index"), straight=147, curled=103)
    assert new.calibration == (103, 147) and new.reversed
    # the same real degrees per second over a range of 44 real degrees instead of 100
    assert new.max_velocity == pytest.approx(432 * 100 / 44)
    assert not found(servo("index"), straight=20, curled=160).reversed
    with pytest.raises(GestError, match="straight and curled are the same angle"):
        found(servo("index"), 90, 90)


def test_only_that_servo_changes_and_comments_stay():
    edited = edit_profile(RHAND_TEXT, "middle", found(servo("middle"), 40, 150))
    profile = parse_profile(edited)
    middle = profile.servos[profile.index("middle")]
    assert middle.calibration == (40, 150) and not middle.reversed
    assert middle.max_velocity == round(360 * 120 / 110)
    for other in ("wrist", "thumb", "index", "ring", "pinky"):
        assert profile.servos[profile.index(other)] == servo(other)
    changed = [(a, b) for a, b in zip(RHAND_TEXT.splitlines(), edited.splitlines(),
                                      strict=True) if a != b]
    assert [a.split("=")[0].strip() for a, _ in changed] == [
        "calibration", "reversed", "max_velocity", "max_acceleration", "max_jerk"]
    assert "# 35..155: 120 real degrees" in edited


def test_missing_keys_are_added_and_a_missing_table_is_a_clear_error():
    text = ('name = "one"\n[[board]]\nid = 181\nservos = ["a"]\n\n[servo.a]\nid = 0\n'
            'max_velocity = 400\nmax_acceleration = 8000\nmax_jerk = 160000\n# end\n')
    edited = edit_profile(text, "a", found(parse_profile(text).servos[0], 10, 170))
    assert parse_profile(edited).servos[0].calibration == (10, 170)
    with pytest.raises(GestError, match=r"no \[servo.b\] table in the profile"):
        edit_profile(text, "b", found(parse_profile(text).servos[0], 10, 170))


# a profile as a person writes one: comments, blank lines, odd spacing, tables board by
# board (which tomlkit alone would reorder: only the servo's table goes through it)
MINE = """\
# my hand   (comments stay)
name   =   "mine"

[[board]]          # the right hand
id = 181
servos = [
    "a",   # one
]

[servo.a]\t\t# first
id=0
  calibration   =   [ 30 , 150 ]    # at the bench, 2024
max_velocity = 400   # real 240 deg/s
max_acceleration=8000

max_jerk = 160000
reversed = false

[[board]]
id = 183
servos = ["b"]

[servo.b]
id = 1
max_velocity = 400
max_acceleration = 8000
max_jerk = 160000

# the glove of the hand, below
"""
A, B = parse_profile(MINE).servos


def test_comments_blank_lines_and_spacing_stay_only_the_values_change():
    edited = edit_profile(MINE, "a", found(A, 20, 160))
    assert edited == MINE.replace(
        "[ 30 , 150 ]    #", "[20, 160]    #").replace(
        "max_velocity = 400   #", "max_velocity = 343   #").replace(
        "max_acceleration=8000\n", "max_acceleration=6857\n").replace(
        "max_jerk = 160000\nreversed", "max_jerk = 137143\nreversed")
    assert parse_profile(edited).servos[0].calibration == (20, 160)


def test_keys_added_go_after_the_last_key_not_after_the_next_tables_comment():
    edited = edit_profile(MINE, "b", found(B, 150, 40))
    assert edited == MINE[:MINE.index("[servo.b]")] + (
        "[servo.b]\nid = 1\nmax_velocity = 655\nmax_acceleration = 13091\n"
        "max_jerk = 261818\ncalibration = [40, 150]\nreversed = true\n\n"
        "# the glove of the hand, below\n")
    crlf = MINE.replace("\n", "\r\n")
    assert edit_profile(crlf, "b", found(B, 150, 40)).replace("\r\n", "\n") == edited
    unended = MINE[:MINE.index("\n\n# the glove")]
    assert edit_profile(unended, "b", found(B, 150, 40)) == edited[:edited.index("\n# the")]


def test_a_servo_without_a_table_of_its_own_is_a_clear_error():
    text = MINE.replace("[servo.a]\t\t# first\n", "[servo]\na = { id = 0 }\n[servo.z]\n")
    with pytest.raises(GestError) as info:
        edit_profile(text, "a", found(A, 10, 170))
    assert info.value.format() == ("error: no [servo.a] table in the profile\n"
                                   "  hint: set calibration = [10, 170] and reversed = false "
                                   "by hand")


def calibrate(tmp_path, keys, *argv):
    """Run gestplay calibrate on a new sim:// board (at rest) at a real pseudo-terminal,
    pressing ``keys``."""
    term = AtTerminal([sys.executable, "-m", "inmoov_dsl.cli.gestplay", "calibrate",
                       "--port", "sim://?boot=0&fresh", *argv], cwd=tmp_path)
    term.read_until(b"value   0")
    term.press(*keys, pause=0.02)
    return term.finish()


RIGHT, UP, PGUP, SHIFT_UP = "\x1b[C", "\x1b[A", "\x1b[5~", "\x1b[1;2A"


@POSIX
def test_the_keys_of_teach_find_the_ends_and_s_writes_them(tmp_path):
    mine = tmp_path / "mine.toml"
    mine.write_text(RHAND_TEXT, encoding="utf-8")
    # up by 1 and page up by 10, as in gestplay teach; Enter keeps straight, then curled
    code, out = calibrate(tmp_path, [RIGHT] + [UP] * 5 + [PGUP, "\r"] + [PGUP] * 7
                          + [SHIFT_UP, "\r", "s"], "--servo", "index", "--profile", str(mine))
    assert code == 0, out
    assert HELP.replace("\n", "\r\n") in out  # the keys, on screen, as teach shows its own
    assert "index: value   0  angle 155  |  Enter keeps straight" in out
    assert "index: value   1  angle 154" in out
    # index maps 0..180 onto 155..55 (reversed, the original firmware's map(v, 180, 0,
    # 55, 155)): value 15 is angle 146, 95 is 102
    assert "index: value  15  angle 146" in out
    assert "index: value  95  angle 102  |  straight 146  curled 102" in out
    index = load_profile(str(mine)).servos[2]
    assert index.calibration == (102, 146) and index.reversed


@POSIX
def test_a_built_in_profile_is_copied_and_q_writes_nothing(tmp_path):
    code, out = calibrate(tmp_path, [UP, "q"], "--servo", "ring")
    assert code == 0 and "nothing written" in out
    code, out = calibrate(tmp_path, ["\r", "q", "q"], "--servo", "ring")
    assert code == 0 and "1 end not written: q again leaves without them" in out
    assert "nothing written" in out and not (tmp_path / "rhand.toml").exists()
    code, out = calibrate(tmp_path, ["\r", PGUP, "\r", "s"], "--servo", "ring")
    assert code == 0, out
    assert load_profile(str(tmp_path / "rhand.toml")).servos[4].calibration == (139, 145)
    assert find_profile("rhand").read_text(encoding="utf-8") == RHAND_TEXT


def test_enter_keeps_straight_then_curled_and_s_needs_both():
    ends = Ends("index", 0, lambda value: 155 - value)
    assert ends.press("s") is None
    assert ends.line() == ("index: value   0  angle 155  |  keep both ends first: Enter at "
                           "straight, then at curled")
    ends.press("enter")
    assert ends.line() == "index: value   0  angle 155  |  straight 155  |  Enter keeps curled"
    assert [ends.press("pageup") for _ in range(3)] == ["send"] * 3
    ends.press("enter")
    assert ends.marks() == {"straight": 155, "curled": 125}
    assert ends.press("enter") is None and ends.kept == [0, 30]  # a third is not kept
    assert "both ends kept: s writes them, u takes back the curled one" in ends.line()
    assert ends.press("u") is None and ends.marks() == {"straight": 155}
    ends.value = 180
    assert ends.press("up") is None  # at the end of the range: nothing to send


def test_an_unknown_servo_is_named_with_a_suggestion(capsys):
    from inmoov_dsl.cli import gestplay

    assert gestplay.main(["calibrate", "--port", "sim://", "--servo", "indx"]) == 1
    err = capsys.readouterr().err
    assert err.startswith("gestplay: error: profile 'rhand' has no servo 'indx'")
    assert "did you mean 'index'?" in err


@POSIX
def test_a_maestro_s_servo_is_calibrated_with_the_same_keys(tmp_path):
    """On a Maestro (the host maps each value to a width: the tool connects to it as
    gestplay does, by its own commands) the same keys find the same ends."""
    mine = tmp_path / "mine.toml"
    mine.write_text((ROOT / "gestures/profiles/rhand-maestro.toml").read_text(),
                    encoding="utf-8")
    code, out = calibrate(tmp_path, [RIGHT] + [UP] * 5 + [PGUP, "\r"] + [PGUP] * 7
                          + [SHIFT_UP, "\r", "s"], "--servo", "index", "--profile", str(mine))
    assert code == 0, out
    assert "index: value  95  angle 102  |  straight 146  curled 102" in out
    index = load_profile(str(mine)).servos[2]
    assert index.calibration == (102, 146) and index.reversed
