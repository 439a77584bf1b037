"""gestplay teach: keys pose the hand, poses become keyframes, keyframes a gesture."""

import os
import sys
import time

import pytest
from terminal import AtTerminal

from inmoov_dsl import compile_source, load_profile
from inmoov_dsl.cli.keys import _posix_keys
from inmoov_dsl.live.calibrate import HELP as CALIBRATE_HELP
from inmoov_dsl.live.calibrate import Ends
from inmoov_dsl.live.teach import HELP as TEACH_HELP
from inmoov_dsl.live.teach import Teach

POSIX = pytest.mark.skipif(not hasattr(os, "openpty"), reason="pseudo-terminals are POSIX")
UP, DOWN, PGUP, PGDN, RIGHT = "\x1b[A", "\x1b[B", "\x1b[5~", "\x1b[6~", "\x1b[C"


def test_keys_move_the_chosen_servo_within_its_range_and_keep_keyframes():
    teach = Teach(load_profile("rhand"), [0] * 6)
    assert teach.press("down") is None  # already at 0: nothing to send
    assert teach.press("right") is None and teach.selected == 1
    assert [teach.press(k) for k in ("pageup", "up")] == ["send", "send"]
    assert teach.pose == [0, 11, 0, 0, 0, 0]
    teach.press("enter")
    teach.press("4")
    for _ in range(20):
        teach.press("pageup")
    assert teach.pose[3] == 180
    for _ in range(3):
        teach.press("+")
    teach.press(" ")
    teach.press("-")
    teach.press("enter")  # the same pose again: a hold
    assert teach.line() == ("wrist 0  thumb 11  index 0  [middle 180]  ring 0  pinky 0  | "
                            "3 keyframes, next over 0.7 s")
    assert teach.gesture("mine") == (
        "# mine: taught with gestplay teach, 3 keyframes\n"
        "mine:\n"
        "    wrist 0, thumb 11, index 0, middle 0, ring 0, pinky 0\n"
        "    middle 180 over 800ms\n"
        "    hold 700ms\n")
    assert teach.press("u") is None and len(teach.keys) == 2
    assert teach.press("p") == "play" and teach.press("s") == "save"


def test_quitting_with_keyframes_not_saved_asks_first():
    teach = Teach(load_profile("rhand"), [0] * 6)
    assert teach.press("q") == "quit"  # nothing to lose
    teach.press("enter")
    teach.saved = False
    assert teach.press("q") is None
    assert teach.line().startswith("1 keyframe not saved: q again quits without them")
    assert teach.press("up") == "send" and teach.press("q") is None  # it asks again
    assert teach.press("esc") == "quit"
    teach.saved = True  # as the caller marks it after writing the file
    assert teach.press("q") == "quit"


def test_the_taught_gesture_compiles_to_its_keyframes():
    teach = Teach(load_profile("rhand"), [0, 10, 20, 30, 40, 50])
    teach.press("enter")
    teach.press("3")
    for _ in range(9):
        teach.press("pageup")
    teach.press("enter")
    compiled = compile_source(teach.gesture("g"))
    assert compiled.final == (0, 10, 110, 30, 40, 50)


def test_a_key_does_the_same_thing_in_teach_and_in_calibrate():
    teach = Teach(load_profile("rhand"), [90] * 6)
    teach.press("3")  # index
    ends = Ends("index", 90, lambda value: value)
    for key, step in (("up", 1), ("down", -1), ("pageup", 10), ("pagedown", -10),
                      ("shift-up", 10), ("shift-down", -10)):
        assert teach.press(key) == ends.press(key) == "send", key
        assert teach.pose[2] == ends.value == 90 + step, key
        teach.pose[2] = ends.value = 90
    assert teach.press("right") is ends.press("right") is None  # calibrate has one servo
    assert teach.selected == 3 and ends.value == 90
    teach.press("left")
    for _ in range(2):  # Enter keeps the pose: a keyframe, an end
        teach.press("enter")
        ends.press("enter")
    assert len(teach.keys) == len(ends.kept) == 2
    assert (teach.press("u"), ends.press("u")) == (None, None)  # takes back the last one
    assert len(teach.keys) == len(ends.kept) == 1
    teach.press(" ")
    ends.press(" ")
    assert teach.press("s") == ends.press("s") == "save"
    assert teach.press("q") is ends.press("q") is None  # not saved yet: it asks
    assert teach.press("q") == ends.press("q") == "quit"


def test_both_tools_show_the_same_keys_for_the_same_things():
    for row in ("up/down  move +1/-1", "page up/down  move +10/-10", "Enter or space  keep "
                "the pose as a", "u  take back the last", "q or Esc  "):
        assert row in TEACH_HELP and row in CALIBRATE_HELP, row
    assert "left/right  choose a servo" in TEACH_HELP
    assert "s  save them to the file" in TEACH_HELP
    assert "s  write the ends into the profile" in CALIBRATE_HELP
    assert all(len(line) <= 80 for line in (TEACH_HELP + "\n" + CALIBRATE_HELP).splitlines())


@POSIX
def test_keys_that_send_sequences_are_read_whole():
    read, write = os.pipe()
    os.write(write, b"\x1b[1;2A\x1b[H\x1b[[A\x1bOB\x1b[6~x\x1b")  # ends on a lone Esc
    os.close(write)
    try:
        keys = list(_posix_keys(read))
    finally:
        os.close(read)
    # shift+up, then Home and F1 (no action: skipped, never Esc), down, page down
    assert keys == ["shift-up", "down", "pagedown", "x", "esc"]


@POSIX
def test_teach_at_a_terminal_poses_plays_back_and_saves(tmp_path):
    term = AtTerminal([sys.executable, "-m", "inmoov_dsl.cli.gestplay", "teach",
                       "--port", "sim://?boot=0", "-o", "wave.gest"], cwd=tmp_path)
    term.read_until(b"keyframes, next over")
    term.press("2", *[UP] * 5, PGUP, PGUP, "\r")            # thumb 25: the first keyframe
    term.press("3", *[PGUP] * 9, *["+"] * 5, "\r")          # index 90, one second later
    term.press(*[PGDN] * 9, "-", "-", " ")                   # index 0, 0.8 s later
    term.press("p")
    term.read_until(b"playing 3 keyframes")
    time.sleep(2.2)                                          # the playback: 1.8 s
    term.press("q")
    term.read_until(b"3 keyframes not saved: q again quits")  # it asks before losing them
    term.press("s")
    term.read_until(b"saved 3 keyframes")
    term.press("q")
    code, screen = term.finish()
    assert code == 0, screen
    text = (tmp_path / "wave.gest").read_text()
    assert text == ("# wave: taught with gestplay teach, 3 keyframes\n"
                    "wave:\n"
                    "    wrist 0, thumb 25, index 0, middle 0, ring 0, pinky 0\n"
                    "    index 90 over 1000ms\n"
                    "    index 0 over 800ms\n")
    assert "[thumb 25]" in screen and "[index 90]" in screen
    assert TEACH_HELP.replace("\n", "\r\n") in screen  # the keys, on screen
    assert "Traceback" not in screen
