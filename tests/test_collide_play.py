"""The robot never driven into itself (issue 43): gestures that drive the right forearm
into the chest, the right hand into the head and the two hands through each other are
found at their step and time, refused by ``gestc check --strict``, ``gestplay`` (a .gest
file or a compiled one), the repl and the service before anything moves, and played
with ``--allow-contact``; the same gestures moved clear pass."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from inmoov_dsl.cli import gestc, gestplay
from inmoov_dsl.compiling.compiler import compile_program
from inmoov_dsl.language.load import load

pytest.importorskip("fcl", reason="the [collide] extra brings python-fcl")

HEAD = "robot inmoov\n\n"
#: name -> (gesture, the contact's words, its step's line, the gesture moved clear)
CASES = {
    "elbow": ("elbow:\n    r_rotate 125 over 1.5s\n    r_bicep 143 over 2s\n",
              "the right forearm enters the chest", 5,
              "elbow:\n    r_rotate 60 over 1.5s\n    r_bicep 143 over 2s\n"),
    "scratch": ("scratch:\n    rothead 160, neck 84 over 1s\n"
                "    r_shoulder 162, r_rotate 157 over 3s\n    r_bicep 164 over 2s\n",
                "the right hand enters the head", 6,
                "scratch:\n    rothead 160, neck 84 over 1s\n"
                "    r_shoulder 162, r_rotate 157 over 3s\n    r_bicep 90 over 2s\n"),
    "clap": ("clap:\n    r_omoplate 103, l_omoplate 128 over 3s\n"
             "    r_shoulder 114, l_shoulder 118, r_rotate 68, l_rotate 108 over 3s\n"
             "    r_bicep 111, l_bicep 139 over 2s\n",
             "the left hand enters the right hand", 6,
             "clap:\n    r_omoplate 103, l_omoplate 128 over 3s\n"
             "    r_shoulder 114, l_shoulder 118, r_rotate 68, l_rotate 108 over 3s\n"
             "    r_bicep 40, l_bicep 40 over 2s\n"),
}
REST = {"r_bicep": 0, "r_rotate": 90, "r_shoulder": 30, "r_omoplate": 0}


def write(tmp_path: Path, name: str, clear: bool = False) -> Path:
    text, *_, moved = CASES[name]
    path = tmp_path / f"{name}.gest"
    path.write_text(HEAD + (moved if clear else text), encoding="utf-8")
    return path


def told_time(err: str, kind: str, path: Path, line: int) -> float:
    """The time a diagnostic of ``kind`` at ``path:line:5`` gives: ``... at T s ...``."""
    (said,) = [x for x in err.splitlines() if x.startswith(f"{path}:{line}:5: {kind}: at ")]
    return float(said.split(" at ")[1].split()[0])


@pytest.mark.parametrize("name", CASES)
def test_each_contact_is_told_at_its_step_while_that_step_moves(name, tmp_path, capsys):
    path = write(tmp_path, name)
    assert gestc.main(["check", str(path)]) == 0
    err = capsys.readouterr().err
    _, words, line, _ = CASES[name]
    assert f"{path}:{line}:5: warning: at " in err and words in err, err
    at = told_time(err, "warning", path, line)
    _, plan = compile_program(load(str(path)))
    (step,) = [s for s in plan.steps if s.pos and s.pos.line == line]
    assert step.start <= at <= step.end  # while the step that causes it moves
    assert gestc.main(["check", str(path), "--strict"]) == 1
    assert f"{path}:{line}:5: error: at " in capsys.readouterr().err


@pytest.mark.parametrize("name", CASES)
def test_the_same_gesture_moved_clear_passes_strict(name, tmp_path, capsys):
    assert gestc.main(["check", str(write(tmp_path, name, clear=True)), "--strict"]) == 0
    assert "warning" not in capsys.readouterr().err


def held(capsys) -> dict[str, int]:
    """What the virtual InMoov's right board holds (``gestplay dump``)."""
    assert gestplay.main(["dump", "--profile", "inmoov", "--port", "sim://"]) == 0
    out = capsys.readouterr().out
    return {w[0]: int(w[-1]) for w in map(str.split, out.splitlines()) if w and w[0] in REST}


def test_gestplay_refuses_before_the_first_byte_and_allow_contact_plays(tmp_path, capsys):
    path = write(tmp_path, "elbow")
    assert gestplay.main([str(path), "--port", "sim://"]) == 1
    err = capsys.readouterr().err
    assert ":5:5: error: at " in err and "--allow-contact plays it anyway" in err
    assert held(capsys) == REST  # the gesture's first step never reached the board
    assert gestplay.main([str(path), "--port", "sim://", "--allow-contact"]) == 0
    err = capsys.readouterr().err
    assert ":5:5: warning: at " in err and "the right forearm enters the chest" in err
    assert held(capsys) == {**REST, "r_rotate": 125, "r_bicep": 143}


def test_a_compiled_file_that_collides_is_refused(tmp_path, capsys):
    out = tmp_path / "elbow.gestc"
    assert gestc.main(["compile", str(write(tmp_path, "elbow")), "-o", str(out)]) == 0
    assert "warning: at " in capsys.readouterr().err  # compiling tells it
    assert gestplay.main([str(out), "--port", "sim://"]) == 1
    err = capsys.readouterr().err
    assert "error: at " in err and "the right forearm enters the chest" in err
    assert held(capsys) == REST


def test_gestplay_plays_the_gesture_moved_clear(tmp_path, capsys):
    assert gestplay.main([str(write(tmp_path, "elbow", clear=True)), "--port", "sim://"]) == 0
    assert "warning" not in capsys.readouterr().err
    assert held(capsys) == {**REST, "r_rotate": 60, "r_bicep": 143}


def test_the_repl_refuses_a_line_and_the_hand_stays_where_it_was():
    lines = "r_rotate 125 over 1.5s\nr_bicep 143 over 2s\nwhere\n"
    done = subprocess.run([sys.executable, "-m", "inmoov_dsl.cli.gestplay", "repl",
                           "--profile", "inmoov", "--port", "sim://"], input=lines,
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 1  # a script with a line that failed
    assert "<stdin>:2:1: error: at " in done.stderr
    assert "the right forearm enters the chest" in done.stderr
    where = dict(zip(*[iter(done.stdout.split())] * 2, strict=True))
    assert (where["r_rotate"], where["r_bicep"]) == ("125", "0")


def test_the_service_answers_422_saying_where_and_when():
    from test_service import serving, still, until, values

    with serving("--profile", "inmoov") as service, service.events() as ws:
        status, answer, _ = service.call("POST", "/api/play",
                                         {"steps": "r_rotate 125, r_bicep 143 over 2s"})
        assert status == 422, answer
        assert answer["error"].startswith("at ") and "enters the chest" in answer["error"]
        assert answer["diagnostics"][0]["line"] == 1 and "--allow-contact" in answer["text"]
        assert values(still(service))["r_bicep"] == 0  # nothing moved
        status, answer, _ = service.call("POST", "/api/play", {
            "steps": "r_rotate 125, r_bicep 143 over 2s", "allow_contact": True})
        assert status == 202 and "enters the chest" in answer["warnings"][0]["message"]
        until(ws, "done", answer["id"])
        assert values(still(service))["r_bicep"] == 143
        status, answer, _ = service.call("POST", "/api/play", {"steps": "r_bicep 0 over 2s",
                                                               "allow_contact": "yes"})
        assert status == 400 and "allow_contact" in answer["error"]


def test_the_service_document_names_the_field():
    from inmoov_dsl.service import openapi

    document = json.dumps(openapi.document("0", 1, 1))
    assert '"allow_contact"' in document and "drive the robot's parts" in document


def test_gestc_collide_says_what_is_checked_and_makes_the_kept_pairs_again(tmp_path, capsys):
    from inmoov_dsl.model.allowed import load, path_for
    from inmoov_dsl.profiles.profile import load_profile

    out = tmp_path / "inmoov.collisions.json"
    assert gestc.main(["collide", "--profile", "inmoov", "--write", "-o", str(out)]) == 0
    said = capsys.readouterr().out
    assert "pairs of parts checked, closer than 10 mm is touching" in said
    assert "adjacent" in said and "hand" in said
    kept = load(path_for(load_profile("inmoov")))
    assert load(out).pairs == kept.pairs  # made again, the same as the file kept


def test_gestc_plot_marks_when_the_robot_meets_itself(tmp_path):
    from inmoov_dsl.model.guard import marks
    from inmoov_dsl.views.plot import figure

    compiled, plan = compile_program(load(str(write(tmp_path, "elbow"))))
    (at, what), = marks(plan)
    assert "the right forearm enters the chest" in what and 1.5 <= at <= 3.5
    drawn = figure(plan, compiled, marks(plan))
    lines = [line for ax in drawn.axes for line in ax.get_lines()
             if line.get_label().startswith("the robot meets itself")]
    assert lines and all(line.get_xdata()[0] == at for line in lines)


def repl_on_the_right_arm(script, guard):
    """The repl on a timeline (tests/test_repl.py), the InMoov's right board virtual:
    what it holds at the end, servo name -> value."""
    from test_repl import ClockedPort, Timeline

    from inmoov_dsl.boards.rig.core import BoardCore
    from inmoov_dsl.cli.gestplay.repl import repl
    from inmoov_dsl.profiles.profile import load_profile
    from inmoov_dsl.wire.player import Link
    from inmoov_dsl.wire.sim import VirtualBoard

    profile = load_profile("inmoov")
    timeline = Timeline(script)
    boards = {b.name: VirtualBoard(BoardCore.from_profile(profile, b), b.baud)
              for b in profile.boards}
    links = [Link(b.id, ClockedPort(boards[b.name], timeline), b.name)
             for b in profile.boards]
    repl(links, profile, {}, timeline.next_line, True, now=timeline.now,
         sleep=timeline.sleep, guard=guard)
    board = boards["right"]
    board.advance(timeline.t + 1)
    ids = {s.id: s.name for s in profile.servos}
    return {ids[i]: v for i, v in board.positions().items() if ids[i] in REST}


def test_a_live_take_over_into_the_chest_is_refused_and_the_move_goes_on(capsys):
    from inmoov_dsl.model.guard import Guard
    from inmoov_dsl.profiles.profile import load_profile

    held = repl_on_the_right_arm([(0.0, "r_rotate 125 over 1.5s"),
                                  (0.5, "r_bicep 143 over 1s")],
                                 Guard(load_profile("inmoov")).plan)
    assert "<repl>:2:1: error: at " in capsys.readouterr().err
    assert held == {**REST, "r_rotate": 125}  # the first move went on to its end


def test_a_take_over_s_own_path_is_checked_and_a_refusal_stops_the_hand(capsys):
    from inmoov_dsl.errors import Diagnostic, GestError

    asked = []

    def guard(plan, sources, allow):  # refuses any path planned from a moving hand
        moving = any(abs(t.velocity(0.0)) > 1 for t in plan.tracks)
        asked.append(moving)
        if moving:
            raise GestError(Diagnostic("error", "refused: a moving start"))
        return ()

    held = repl_on_the_right_arm([(0.0, "r_rotate 125 over 1.5s"),
                                  (0.5, "r_bicep 60 over 1s")], guard)
    assert asked == [False, False, True]  # two requests from rest, then the take-over
    assert "refused: a moving start" in capsys.readouterr().err
    assert 90 < held["r_rotate"] < 125 and held["r_bicep"] == 0  # stopped where it was
