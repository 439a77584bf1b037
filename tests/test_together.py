"""``a & b``: moves, calls and poses at the same time on their own servos."""

from __future__ import annotations

import numpy as np
import pytest

from inmoov_dsl.compiling.compiler import compile_program
from inmoov_dsl.errors import GestError
from inmoov_dsl.language.fmt import format_source
from inmoov_dsl.language.load import load
from inmoov_dsl.profiles.profile import load_profile

INMOOV = load_profile("inmoov")
LIB = ("peace: thumb 180, ring 180, pinky 180, index 0, middle 0 over 0.7s\n"
       "nod:\n    neck 140 over 0.6s\n    neck 60 over 0.8s\n    neck 90 over 0.5s\n"
       "pose up: r_shoulder 120\n")


def planned(body, profile=INMOOV):
    return compile_program(load("t.gest", LIB + "g:\n    " + body + "\n"), "g", profile)[1]


def at(plan, servo, t):
    return float(plan.tracks[plan.profile.index(servo)].position(t))


def test_two_gestures_run_from_the_steps_start_and_it_ends_with_the_longer():
    together = planned("peace & nod")
    peace, nod = planned("peace"), planned("nod")
    assert together.duration == pytest.approx(max(peace.duration, nod.duration))
    for t in (0.3, 0.7, 1.2, 1.8):  # each part as if it ran alone
        assert at(together, "r_thumb", t) == pytest.approx(at(peace, "r_thumb", t))
        assert at(together, "neck", t) == pytest.approx(at(nod, "neck", t))
    assert together.final == tuple(max(a, b, key=lambda v: v != r)
                                   for a, b, r in zip(peace.final, nod.final, peace.start,
                                                      strict=True))


def test_a_move_a_pose_and_a_call_at_once_then_the_next_step_after_the_longest():
    plan = planned("r_bicep 60 over 2.5s & up & nod\n    r_index 90")
    assert planned("nod").duration < 2.5
    assert plan.steps[0].end == pytest.approx(2.5)  # the bicep's over, the longest part
    assert plan.steps[1].start == pytest.approx(2.5)
    assert at(plan, "r_index", 2.5) == 0 and at(plan, "r_index", plan.duration) == 90
    assert at(plan, "r_shoulder", 2.5) == 120  # the pose, reached before the step ended


def test_a_part_that_is_stretched_warns_at_its_place():
    compiled, _ = compile_program(load("t.gest", "g: r_index 180 over 0.1s & neck 100\n"),
                                  "g", INMOOV)
    (warning,) = compiled.warnings
    assert warning.message.startswith("move stretched: needs ")
    assert (warning.pos.line, warning.pos.column) == (1, 21)  # at the part's 'over'
    assert warning.source_line == "g: r_index 180 over 0.1s & neck 100"


@pytest.mark.parametrize(("body", "message"), [
    ("peace & r_index 90",
     "t.gest:8:13: error: 'r_index' is moved by two parts of this step: 'peace' at column "
     "5 and 'r_index'"),
    ("nod & neck 10 over 1s",
     "t.gest:8:11: error: 'neck' is moved by two parts of this step: 'nod' at column 5 and "
     "'neck'"),
    ("r_index 90 & up & index 45",
     "t.gest:8:23: error: 'r_index' is moved by two parts of this step: 'r_index' at "
     "column 5 and 'index'"),
])
def test_a_servo_claimed_by_two_parts_is_an_error_naming_both(body, message):
    with pytest.raises(GestError) as caught:
        planned(body)
    assert caught.value.diagnostics[0].format().startswith(message)


def test_a_step_at_once_flows_from_and_into_its_neighbours_without_a_jump():
    plan = planned("r_index 90 through\n    peace & nod\n    r_index 0")
    track = plan.tracks[INMOOV.index("r_index")]
    times = np.linspace(0, plan.duration, 5001)
    steps = np.abs(np.diff(track.position(times)))
    assert steps.max() < 2.0  # degrees between two samples 0.5 ms apart at most: no jump


def test_fmt_writes_a_step_at_once_canonically():
    assert format_source("g:\n    peace&nod\n    index 90 over .5s  &  up\n") == \
        "g:\n    peace & nod\n    index 90 over 0.5s & up\n"
