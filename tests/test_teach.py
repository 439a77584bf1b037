"""gestplay teach: keys pose the hand, poses become keyframes, keyframes a gesture."""

import os
import sys
import time

import pytest
from terminal import AtTerminal

from inmoov_dsl import compile_source, load_profile
from inmoov_dsl.teach import Teach

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
    assert "Traceback" not in screen
