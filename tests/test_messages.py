"""The errors this session's commands give for bad input: one clear message, exit 1."""

import os
import subprocess
import sys

import pytest

from inmoov_dsl import GestError
from inmoov_dsl.cli import gestc, gestplay
from inmoov_dsl.firmware.sketches import sketches
from inmoov_dsl.profiles.profile import parse_profile

POSIX = pytest.mark.skipif(not hasattr(os, "openpty"), reason="pseudo-terminals are POSIX")


@pytest.mark.parametrize(("main", "argv", "message"), [
    (gestc.main, ["record", "--port", "sim://", "-o", "fast.gest", "--name", "2fast"],
     "gestc: error: '2fast' cannot name a gesture\n"
     "  hint: --name takes a word: letters, digits and _\n"),
    (gestplay.main, ["teach", "--port", "sim://", "--name", "my-wave"],
     "gestplay: error: 'my-wave' cannot name a gesture\n"
     "  hint: --name takes a word: letters, digits and _\n"),
    (gestc.main, ["record", "--port", "sim://", "-o", "wait.gest"],
     "gestc: error: 'wait' is a keyword of the language, not a name\n"
     "  hint: --name my_wait\n"),
])
def test_bad_options_are_one_clear_message(main, argv, message, capsys, tmp_path,
                                           monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(argv) == 1
    assert capsys.readouterr().err == message


@pytest.mark.parametrize(("main", "argv", "message"), [
    (gestc.main, ["export", "peace", "--joint-states", "-", "--rate", "0"],
     "gestc export: error: argument --rate: '0' is not a number above 0 and at most 1,000"),
    (gestc.main, ["export", "peace", "--joint-states", "-", "--rate", "inf"],
     "gestc export: error: argument --rate: 'inf' is not a number above 0 and at most 1,000"),
    (gestplay.main, ["send", "--port", "sim://", "--listen", "nan", "cancel"],
     "gestplay send: error: argument --listen: 'nan' is not a number from 0 to 60"),
    (gestplay.main, ["send", "--port", "sim://", "--listen", "-1", "cancel"],
     "gestplay send: error: argument --listen: '-1' is not a number from 0 to 60"),
    (gestplay.main, ["peace", "--speed", "2"],
     "gestplay play: error: argument --speed: '2' is not a number from 0.01 to 1"),
    (gestplay.main, ["peace", "--speed", "1e-300"],
     "gestplay play: error: argument --speed: '1e-300' is not a number from 0.01 to 1"),
    (gestplay.main, ["peace", "--loop", "0"],
     "gestplay play: error: argument --loop: '0' is not a whole number from 1 to 1,000,000"),
    (gestc.main, ["fmt", "a\x00.gest"], "gestc: error: an argument contains a NUL character"),
])
def test_values_out_of_range_are_usage_errors(main, argv, message, capsys):
    with pytest.raises(SystemExit) as exit_:
        main(argv)
    assert exit_.value.code == 2
    assert capsys.readouterr().err.splitlines()[-1] == message


def test_a_board_without_pins_cannot_have_firmware():
    profile = parse_profile('[[board]]\nid = 181\nservos = ["a"]\n[servo.a]\nid = 0\n'
                            'max_velocity = 1\nmax_acceleration = 1\nmax_jerk = 1\n', "p.toml")
    with pytest.raises(GestError) as info:
        sketches(profile)
    assert info.value.format() == ("error: profile 'p': servo a of board 181 has no 'pin'\n"
                                   "  hint: add pin = N to each [servo.NAME] of the board")


@POSIX
@pytest.mark.parametrize(("argv", "message"), [
    (["--glove", "peace", "--profile", "lhand"],
     "gestsim: error: profile 'lhand' has no glove\n"
     "  hint: a [[glove]] table describes one (rhand has it)\n"),
    (["--glove", "peace", "--gap", "later"],
     "gestsim: error: --gap later: give START-END in seconds\n  hint: --gap 1.0-1.3\n"),
])
def test_a_virtual_glove_that_cannot_be_is_one_clear_message(argv, message):
    done = subprocess.run([sys.executable, "-m", "inmoov_dsl.cli.gestsim", *argv],
                          capture_output=True, text=True, timeout=30)
    assert done.returncode == 1
    assert done.stderr == message and done.stdout == ""
    assert "Traceback" not in done.stderr
