"""A file names its robot: ``robot inmoov`` on its first line is the profile every tool
uses when none is given, and a profile given is checked against it."""

import json
import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

from inmoov_dsl import compile_source
from inmoov_dsl.cli import gestc, gestplay
from inmoov_dsl.errors import GestError
from inmoov_dsl.language.fmt import format_source
from inmoov_dsl.language.parse import parse

ROOT = Path(__file__).resolve().parent.parent
HEAD = "wave_hi: r_shoulder 90, fingers 0 over 1.5s & jaw 40\n"


def write(tmp_path, name, text):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_the_robot_line_parses_as_a_name_or_a_profile_file():
    assert parse("# the robot\nrobot inmoov\n" + HEAD).robot.name == "inmoov"
    assert parse("robot rhand-maestro\nx: index 90\n").robot.name == "rhand-maestro"
    line = parse('robot "my_hand.toml"\nx: index 90\n').robot
    assert (line.name, line.is_file) == ("my_hand.toml", True)
    assert parse("x: index 90\n").robot is None
    # a name that starts with the keyword is a name
    assert parse("pose robot_rest: index 0\nx: robot_rest\n").robot is None


@pytest.mark.parametrize(("text", "message", "hint"), [
    ("x: index 90\nrobot inmoov\n", "2:7: error: a file names its robot once, on its first "
     "line", "move the robot line to the top of the file, above its gestures"),
    ("robot inmoov\nrobot rhand\n", "2:7: error: a file names its robot once, on its first "
     "line", "keep one robot line"),
    ('robot "hand.gest"\n', "1:7: error: a robot is a profile's name or a .toml file, not "
     "'hand.gest'", 'robot inmoov, or robot "my_hand.toml"'),
    ("robot\n", "1:6: error: unexpected end of line; expected a robot's profile (rhand, "
     'inmoov) or a file name in quotes ("other.gest")', None),
    ("robot: index 90\n", "1:6: error: unexpected ':'; expected a robot's profile", None),
])
def test_a_bad_robot_line_is_an_error_at_it(text, message, hint):
    with pytest.raises(GestError) as info:
        parse(text, "f.gest")
    said = str(info.value)
    assert said.startswith(f"f.gest:{message}")
    assert hint is None or said.endswith(f"hint: {hint}")


def test_fmt_keeps_the_robot_line():
    text = "# for the whole robot\nrobot   inmoov\n\n" + HEAD
    assert format_source(text) == "# for the whole robot\nrobot inmoov\n\n" + HEAD
    assert format_source('robot  "mine.toml"  # mine\nx: index 90\n') == \
        'robot "mine.toml"  # mine\nx: index 90\n'


def test_a_file_plays_on_its_robot_without_a_profile():
    compiled = compile_source("robot inmoov\n" + HEAD)
    assert compiled.profile == "inmoov"
    assert compile_source("x: index 90\n").profile == "rhand"


def test_a_profile_given_must_have_the_robots_names():
    # the robot's right hand answers to the hand's names: a rhand file plays on it
    assert compile_source("robot rhand\nx: index 90\n", profile="inmoov").profile == "inmoov"
    with pytest.raises(GestError) as info:
        compile_source("robot inmoov\n" + HEAD, profile="rhand", file="w.gest")
    assert str(info.value).startswith(
        "w.gest:1:7: error: this file is for robot 'inmoov', and profile 'rhand' has no "
        "r_wrist, r_thumb, r_index, r_middle, r_ring, r_pinky and 31 more\n")


def test_an_unknown_robot_is_an_error_at_its_name():
    with pytest.raises(GestError) as info:
        compile_source("robot inmov\nx: index 90\n", file="w.gest")
    said = str(info.value)
    assert said.startswith("w.gest:1:7: error: unknown profile 'inmov'")
    assert said.endswith("hint: did you mean 'inmoov'?")


def test_a_profile_file_beside_the_gesture_file(tmp_path, capsys):
    profile = (ROOT / "gestures" / "profiles" / "rhand.toml").read_text()
    write(tmp_path, "mine.toml", profile.replace('name = "rhand"', 'name = "mine"'))
    sub = tmp_path / "sub"
    sub.mkdir()
    write(sub, "w.gest", 'robot "../mine.toml"\nw: index 90\n')
    assert gestc.main(["show", str(sub / "w.gest")]) == 0
    assert capsys.readouterr().out.startswith("w: 0.308 s on profile 'mine'\n")


def test_a_gesture_called_from_a_robot_file_is_checked_at_the_call(tmp_path):
    write(tmp_path, "body2.gest", "robot inmoov\n" + HEAD)
    mine = write(tmp_path, "mine.gest", 'use "body2.gest"\nboth:\n    index 90\n    wave_hi\n')
    # without a robot line of its own, the file takes its imports' robot
    from inmoov_dsl.compiling.compiler import compile_file

    assert compile_file(mine).profile == "inmoov"
    with pytest.raises(GestError) as info:
        compile_file(mine, profile="rhand")
    first = info.value.first
    assert (first.pos.line, first.pos.column) == (4, 5)
    assert first.message.startswith("this gesture is from body2.gest, which is for robot "
                                    "'inmoov', and profile 'rhand' has no ")


def test_the_docs_show_the_message_gestc_gives(capsys):
    doc = (ROOT / "docs" / "language.md").read_text()
    shown = re.search(r"```text\n(body\.gest:3:7: error: this file is for robot.*?)```",
                      doc, re.S)[1]
    body = ROOT / "gestures" / "body.gest"
    assert gestc.main(["check", str(body), "--profile", "rhand"]) == 1
    assert capsys.readouterr().err.replace(str(body), "body.gest") == shown


def test_the_repl_and_service_refuse_a_robot_gesture_on_another_robot(rhand):
    from inmoov_dsl.live.drive import library_program
    from inmoov_dsl.live.session import line_steps
    from inmoov_dsl.service.core import problem

    with pytest.raises(GestError) as info:
        line_steps("hello", library_program(None), rhand)
    body = problem(info.value)
    assert body["error"].startswith("this gesture is from body.gest, which is for robot "
                                    "'inmoov', and profile 'rhand' has no ")
    assert "--profile" not in json.dumps(body)


def test_gestplay_plays_a_robot_file_on_its_robot(capsys):
    assert gestplay.main(["hello_talk", "--dry-run", "--audio", "none"]) == 0
    boards = [line for line in capsys.readouterr().out.splitlines() if line.startswith("#")]
    assert boards == [f"# board {b}" for b in (181, 183)]  # inmoov: its two Megas


@pytest.mark.skipif(os.name != "posix", reason="gestsim serves a pseudo-terminal")
@pytest.mark.parametrize("argv", [["peace"], ["peace", "--profile", "inmoov", "--hand", "left"],
                                  ["nod"]])
def test_the_line_to_watch_it_move_runs_as_printed(argv, capsys):
    """The commands after 'to watch it move' run as they are printed, what gestsim
    prints put where the line says: on the whole robot, one gestsim for every board
    (the robot played on, whichever boards the gesture drives)."""
    assert gestplay.main([*argv, "--port", "sim://"]) == 0
    line = capsys.readouterr().err.splitlines()[-1]
    assert line.startswith("to watch it move: run 'gestsim --view")
    sim, play = re.findall(r"'([^']*)'", line)
    whole = "--profile" in argv or argv == ["nod"]
    assert ("--port PORTS" in play) == whole and ("--port PTY" in play) != whole
    if whole:
        assert sim == "gestsim --view --profile inmoov"
        assert line.endswith("with the PORTS it prints (181=PTY181,183=PTY183)")
    proc = subprocess.Popen([sys.executable, "-m", "inmoov_dsl.cli.gestsim",
                             *shlex.split(sim)[1:], "--boot", "0.2"], stdout=subprocess.PIPE,
                            stderr=subprocess.DEVNULL, text=True)
    try:
        printed = proc.stdout.readline().strip()
        if whole:
            assert re.fullmatch(r"181=/dev/\S+,183=/dev/\S+", printed)
        command = shlex.split(play.replace("PORTS" if whole else "PTY", printed))
        assert command[0] == "gestplay" and "PTY" not in " ".join(command)
        assert gestplay.main(command[1:]) == 0, capsys.readouterr().err
    finally:
        proc.kill()
        proc.wait()


def test_where_there_are_no_pseudo_terminals_the_line_draws_it(tmp_path, monkeypatch):
    """On Windows the line names gestc preview, with the options it takes."""
    import argparse

    from inmoov_dsl.cli.gestplay import play
    from inmoov_dsl.profiles.profile import load_profile

    monkeypatch.chdir(tmp_path)
    args = argparse.Namespace(target="peace", profile="inmoov", hand="left")
    line = play.watch(args, load_profile("inmoov"), {183}, posix=False)
    assert line == "'gestc preview peace --profile inmoov -o peace.gif' draws it"
    assert gestc.main(shlex.split(line.split("'")[1])[1:]) == 0
    assert (tmp_path / "peace.gif").read_bytes()[:6] == b"GIF89a"
