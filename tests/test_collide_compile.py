"""The compiler's self-collision check (issue 43, model/collide.py ``check_plan``): a
gesture that drives the right upper arm into the chest warns at its step, at a plausible
time; --strict makes it an error; the same gesture moved clear passes; the library's
whole-robot gestures pass."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import WHOLE_ROBOT

from inmoov_dsl.cli import gestc
from inmoov_dsl.compiling.checking import check_program
from inmoov_dsl.compiling.compiler import plan_checks
from inmoov_dsl.language.load import load
from inmoov_dsl.model.guard import check_plan

pytest.importorskip("fcl", reason="the [collide] extra brings python-fcl")

ROOT = Path(__file__).resolve().parent.parent
# tests/test_collide.py's pinned pose: the upper arm over the top of the chest
INTO_CHEST = """robot inmoov

reach:
    r_bicep 96, r_rotate 32 over 2s
    r_shoulder {shoulder}, r_omoplate 151 over 3s
"""


@pytest.fixture(autouse=True)
def checked():
    """Every plan of the test checked, as gestc check does (and only within the test)."""
    with plan_checks(check_plan):
        yield


def write(tmp_path: Path, shoulder: int) -> Path:
    path = tmp_path / "reach.gest"
    path.write_text(INTO_CHEST.format(shoulder=shoulder), encoding="utf-8")
    return path


def test_the_arm_into_the_chest_warns_at_its_step(tmp_path):
    program = load(str(write(tmp_path, 135)))
    errors, warnings = check_program(program, "inmoov")
    assert not errors
    (w,) = [w for w in warnings if "chest" in w.message]
    assert (w.pos.line, w.pos.column) == (5, 5)
    assert "the right upper arm enters the chest, " in w.message and " mm deep at " in w.message
    assert "r_shoulder" in w.message and "r_omoplate" in w.message and w.hint
    at = float(w.message.split()[1])
    assert 2.0 < at < 5.0 + 1e-9  # during the second step, which starts at 2 s


def test_strict_makes_it_an_error(tmp_path, capsys):
    path = write(tmp_path, 135)
    assert gestc.main(["check", str(path), "--profile", "inmoov", "--strict"]) == 1
    err = capsys.readouterr().err
    assert ":5:5: error: at " in err and "enters the chest" in err
    assert gestc.main(["check", str(path), "--profile", "inmoov"]) == 0
    assert ":5:5: warning: at " in capsys.readouterr().err


def test_the_arm_kept_clear_passes(tmp_path, capsys):
    path = write(tmp_path, 90)
    assert gestc.main(["check", str(path), "--profile", "inmoov", "--strict"]) == 0
    assert "warning" not in capsys.readouterr().err


@pytest.mark.parametrize("name", WHOLE_ROBOT)
def test_the_library_whole_robot_gestures_touch_nothing(name):
    program = load(str(ROOT / "gestures" / name))
    errors, warnings = check_program(program)
    assert not errors
    assert not [w for w in warnings if " s the " in w.message], warnings


ELBOW = "robot inmoov\n\nelbow:\n    r_rotate 125 over 1.5s\n    r_bicep 143 over 2s\n"


def test_a_contact_is_told_when_it_begins_and_when_it_is_deepest(tmp_path):
    """The forearm meets the chest at 2.12 s and goes deepest at the motion's end: both
    moments said (the message joined the first moment with the deepest depth), the
    servos' values those of the first; the live page's mark says the same."""
    path = tmp_path / "elbow.gest"
    path.write_text(ELBOW, encoding="utf-8")
    program = load(str(path))
    _, warnings = check_program(program, "inmoov")
    (w,) = warnings
    assert w.message == ("at 2.12 s the right forearm enters the chest, 24 mm deep at "
                         "3.50 s (r_bicep 39)")
    from inmoov_dsl.compiling.compiler import compile_program
    from inmoov_dsl.views.timeline import contacts

    _, plan = compile_program(program, "elbow", "inmoov")
    (mark,) = contacts(plan)
    assert (round(mark.start, 2), mark.text) == (2.12, w.message.removesuffix(" (r_bicep 39)"))
