"""Moves that flow ``through`` their keyframes: one jerk-limited motion within every
servo's limits, no overshoot, never slower than stopping at each keyframe, and faster
where the limits allow."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from inmoov_dsl.compiling.compiler import compile_program
from inmoov_dsl.errors import GestError
from inmoov_dsl.language.fmt import format_source
from inmoov_dsl.language.load import load
from inmoov_dsl.profiles.profile import load_profile

RHAND = load_profile("rhand")
SERVOS = ["wrist", "thumb", "index", "middle", "ring", "pinky"]


def planned(source, profile=RHAND):
    compiled, plan = compile_program(load("t.gest", source), "g", profile)
    return compiled, plan


def stop_and_go(source):
    return planned(source.replace(" through", ""))


def at(plan, servo, t):
    track = plan.tracks[plan.profile.index(servo)]
    return float(track.position(t)), float(track.velocity(t))


def test_a_sweep_crosses_its_keyframe_at_speed_and_ends_sooner():
    flowing = "g:\n    index 90 through\n    index 180\n"
    _, plan = planned(flowing)
    _, stopping = stop_and_go(flowing)
    crossing = plan.steps[0].end
    assert at(plan, "index", crossing) == pytest.approx((90, 432), abs=1e-6)  # full speed
    assert at(stopping, "index", stopping.steps[0].end) == pytest.approx((90, 0), abs=1e-6)
    assert plan.duration < 0.9 * stopping.duration
    assert plan.final == stopping.final


def test_over_is_when_the_keyframe_is_crossed():
    _, plan = planned("g:\n    wrist 90 over 0.5s through\n    wrist 180 over 0.5s\n")
    assert [s.end for s in plan.steps] == pytest.approx([0.5, 1.0])
    position, velocity = at(plan, "wrist", 0.5)
    assert position == pytest.approx(90, abs=1e-6) and velocity > 100
    assert not plan.warnings


def test_a_servo_that_turns_back_crosses_at_rest():
    _, plan = planned("g:\n    index 90 through\n    index 30 through\n    index 180\n")
    assert len(plan.steps) == 3  # the two steps that go through, then the last
    for step in plan.steps[:2]:
        assert at(plan, "index", step.end)[1] == pytest.approx(0, abs=1e-6)


def test_a_servo_the_next_step_leaves_alone_stops_at_its_keyframe():
    _, plan = planned("g:\n    index 90, middle 90 through\n    index 180\n")
    end = plan.steps[0].end
    assert at(plan, "index", end)[1] > 0
    assert at(plan, "middle", end) == pytest.approx((90, 0), abs=1e-6)


def test_a_run_ends_before_a_staggered_step_which_starts_from_rest():
    source = "g:\n    index 90 through\n    middle 90, ring 90 over 0.5s stagger 100ms\n"
    _, plan = planned(source)
    _, stopping = stop_and_go(source)
    assert plan.duration == pytest.approx(stopping.duration)  # the stagger is kept
    assert plan.steps[1].end - plan.steps[1].start == pytest.approx(0.6)


def test_a_stretched_crossing_warns_as_a_stretched_move_does():
    compiled, plan = planned("g:\n    index 90 over 0.1s through\n    index 180\n")
    needed = plan.steps[0].end
    assert plan.steps[0].stretched and needed > 0.2
    assert [w.message for w in compiled.warnings] == [
        f"move stretched: needs {needed:.2f} s, asked 0.10 s"]
    assert at(plan, "index", needed)[1] > 0  # and it still flows


keyframes = st.lists(st.tuples(st.lists(st.tuples(st.sampled_from(SERVOS),
                                                  st.integers(0, 180)),
                                        min_size=1, max_size=4, unique_by=lambda t: t[0]),
                               st.one_of(st.none(), st.integers(20, 900))),
                     min_size=2, max_size=6)


def source_of(frames):
    lines = []
    for k, (targets, over_ms) in enumerate(frames):
        text = ", ".join(f"{n} {v}" for n, v in targets)
        if over_ms is not None:
            text += f" over {over_ms}ms"
        lines.append("    " + text + (" through" if k < len(frames) - 1 else ""))
    return "g:\n" + "\n".join(lines) + "\n"


@settings(max_examples=150, deadline=None, derandomize=True)
@given(frames=keyframes)
def test_a_run_holds_every_limit_never_overshoots_and_is_never_slower(frames):
    source = source_of(frames)
    _, plan = planned(source)
    _, stopping = stop_and_go(source)
    assert plan.final == stopping.final
    assert plan.duration <= stopping.duration + 1e-6
    times = np.linspace(0, plan.duration, 4001)
    for servo, track in zip(RHAND.servos, plan.tracks, strict=True):
        assert np.abs(track.velocity(times)).max() <= servo.max_velocity * (1 + 1e-6) + 1e-6
        assert np.abs(track.acceleration(times)).max() <= \
            servo.max_acceleration * (1 + 1e-6) + 1e-6
        assert np.abs(track.coefs[:, 3]).max() <= servo.max_jerk * (1 + 1e-6) + 1e-6
        # between two keyframes a servo stays between their values
        k = RHAND.index(servo.name)
        before = plan.start[k]
        for step in plan.steps:
            window = np.append(times[(times >= step.start) & (times <= step.end)], step.end)
            after = float(track.position(step.end))
            low, high = min(before, after), max(before, after)
            path = track.position(window)
            assert path.min() >= low - 0.25 and path.max() <= high + 0.25, (servo.name, step)
            before = after


def test_fmt_keeps_through():
    source = "g:\n    index 90  over .5s   through\n    index 0\n"
    assert format_source(source, "t.gest") == "g:\n    index 90 over 0.5s through\n    index 0\n"


@pytest.mark.parametrize(("source", "message"), [
    ("g:\n    index 90 stagger 50ms through\n    index 0\n",
     "t.gest:2:27: error: a step that flows 'through' its keyframe cannot 'stagger'"),
    ("h: index 90\ng:\n    h through\n    index 0\n",
     "t.gest:3:7: error: a gesture call takes no timing: 'h' sets its own"),
    ("g:\n    index 90 through through\n",
     "t.gest:2:22: error: 'through' is given twice in this step"),
])
def test_through_where_it_cannot_go_is_an_error(source, message):
    with pytest.raises(GestError) as caught:
        planned(source)
    assert caught.value.diagnostics[0].format().startswith(message)
