"""Live motion: typed steps, and a new step taking over a running move."""


import numpy as np
import pytest

from inmoov_dsl.cli.gestplay.repl import library_program
from inmoov_dsl.compiling.plan import MotionState
from inmoov_dsl.errors import GestError
from inmoov_dsl.live.session import RETRY_LATER, Session, line_steps
from inmoov_dsl.profiles.profile import load_profile

RHAND = load_profile("rhand")
INDEX = RHAND.index("index")
REST = [0] * 6


@pytest.fixture(scope="module")
def program():
    return library_program()


def steps(line, program):
    return line_steps(line, program, RHAND)[0]


def test_a_typed_line_is_a_step_or_a_library_name(program):
    (step,) = steps("index 90, middle 45 over 0.5s", program)
    assert dict(step.targets) == {INDEX: 90, RHAND.index("middle"): 45}
    assert step.over == 0.5
    assert len(steps("count", program)) > 5  # the library gesture, every step
    (wait,) = steps("wait 250ms", program)
    assert wait.hold == 0.25


@pytest.mark.parametrize(("line", "column", "message"), [
    ("indx 90", 1, "unknown servo or group 'indx'"),
    ("index 90 ovr 1s", 10, "unexpected"),
    ("index 900", 7, "value 900 is outside 0..180"),
])
def test_errors_point_into_the_typed_line(program, line, column, message):
    with pytest.raises(GestError) as caught:
        line_steps(line, program, RHAND)
    d = caught.value.first
    assert (d.pos.file, d.pos.line, d.pos.column) == ("<repl>", 1, column)
    assert message in d.message
    assert d.format().splitlines()[1] == f"    {line}"


def limits(servo):
    return servo.max_velocity, servo.max_acceleration, servo.max_jerk


@pytest.mark.parametrize("at", [0.05, 0.15, 0.3])
@pytest.mark.parametrize("line", ["index 180", "index 20", "middle 120", "index 180 over 1s"])
def test_a_new_step_takes_over_with_the_current_velocity(program, at, line):
    session = Session(RHAND, REST, now=10.0)
    first = session.submit(steps("index 90 over 0.4s", program), 10.0, REST)
    before = MotionState.at(first.plan, at)
    second = session.submit(steps(line, program), 10.0 + at, list(first.plan.start))
    after = MotionState.at(second.plan, 0.0)
    # no jump in position, velocity or acceleration at the moment of takeover
    np.testing.assert_allclose(after.position, before.position, atol=1e-6)
    np.testing.assert_allclose(after.velocity, before.velocity, atol=1e-3)
    np.testing.assert_allclose(after.acceleration, before.acceleration, atol=1e-2)
    assert second.origin == 10.0 + at
    # servos the step does not name carry on to where they were going
    expected = [0, 0, 90, 0, 0, 0]
    for i, v in second.step.targets:
        expected[i] = v
    assert second.plan.final == tuple(expected)
    t = np.linspace(0, second.plan.duration, 2000)
    for i, servo in enumerate(RHAND.servos):
        track = second.plan.tracks[i]
        assert track.position(second.plan.duration) == pytest.approx(expected[i])
        vmax, amax, _ = limits(servo)
        assert np.abs(track.velocity(t)).max() <= vmax * (1 + 1e-6)
        assert np.abs(track.acceleration(t)).max() <= amax * (1 + 1e-6)


def test_takeover_in_the_same_direction_does_not_stop_first(program):
    session = Session(RHAND, REST, now=0.0)
    first = session.submit(steps("index 90 over 0.6s", program), 0.0, REST)
    second = session.submit(steps("index 180", program), 0.3, REST)
    t = np.linspace(0, second.plan.duration * 0.9, 500)
    v = second.plan.tracks[INDEX].velocity(t)
    assert first.plan.tracks[INDEX].velocity(0.3) > 50
    assert v.min() > 50  # it keeps going up all the way, never near standing still


def test_a_wait_starts_when_the_running_move_ends(program):
    session = Session(RHAND, REST, now=0.0)
    first = session.submit(steps("index 90", program), 0.0, REST)
    assert session.submit(steps("wait 1s", program), 0.1, REST) is None
    assert session.next(first.plan.duration - 0.01, REST) is None
    wait = session.next(first.plan.duration + 0.001, [0, 0, 90, 0, 0, 0])
    assert wait.plan.duration == 1.0 and wait.streams[0].data == bytes([255])
    assert session.busy(wait.origin + 0.5) and not session.busy(wait.origin + 1.01)


def test_a_segment_sends_only_what_the_board_does_not_hold(program):
    session = Session(RHAND, [0, 0, 90, 0, 0, 0], now=0.0)
    segment = session.submit(steps("index 90, middle 30", program), 0.0, [0, 0, 90, 0, 0, 0])
    data = segment.streams[0].data
    assert data[0] == 255
    assert set(data[1::2]) == {RHAND.servos[RHAND.index("middle")].id}


def test_a_script_waits_for_each_step(program):
    session = Session(RHAND, REST, now=0.0)
    first = session.append(steps("index 90 over 0.3s", program), 0.0, REST)
    assert session.append(steps("index 0", program), 0.1, REST) is None
    second = session.next(0.31, [0, 0, 90, 0, 0, 0])
    assert first.plan.final[INDEX] == 90 and second.origin == pytest.approx(0.31)
    assert MotionState.at(second.plan, 0).velocity[INDEX] == 0


def test_a_warning_about_a_typed_line_points_into_it(program):
    line = "index 180 over 0.01s"
    actions, sources = line_steps(line, program, RHAND)
    segment = Session(RHAND, REST, 0.0, sources).submit(actions, 0.0, REST, sources)
    (warning,) = segment.warnings
    assert (warning.pos.line, warning.pos.column) == (1, line.index("0.01s") + 1)
    assert warning.format().splitlines()[1:3] == [f"    {line}", " " * 19 + "^~~~~"]


@pytest.mark.parametrize(("file", "number"), [("<stdin>", 4), ("<repl>", 12)])
def test_errors_and_warnings_name_the_line_of_the_input(program, file, number):
    with pytest.raises(GestError) as caught:
        line_steps("indx 90", program, RHAND, file, number)
    assert caught.value.first.format().splitlines()[:2] == [
        f"{file}:{number}:1: error: unknown servo or group 'indx'", "    indx 90"]
    line = "index 180 over 0.01s"
    actions, sources = line_steps(line, program, RHAND, file, number)
    (warning,) = Session(RHAND, REST, 0.0, sources).submit(actions, 0.0, REST,
                                                          sources).warnings
    said = warning.format().splitlines()
    assert said[0].startswith(f"{file}:{number}:16: warning: move stretched")
    assert said[1] == f"    {line}"


def test_a_step_that_cannot_be_planned_drops_its_line_not_the_next(program, monkeypatch):
    session = Session(RHAND, REST, now=0.0)
    broken, broken_sources = line_steps("count", program, RHAND)  # a gesture: many steps
    after, after_sources = line_steps("middle 90", program, RHAND)
    plan = session.planner.plan

    def refuse_the_second(steps, pose, *args, **kwargs):
        if steps[0] is broken[1]:
            raise GestError(broken_sources.error("cannot plan", steps[0].pos))
        return plan(steps, pose, *args, **kwargs)

    monkeypatch.setattr(session.planner, "plan", refuse_the_second)
    first = session.append(broken, 0.0, REST, broken_sources)
    session.append(after, 0.1, REST, after_sources)
    with pytest.raises(GestError):
        session.next(first.plan.duration, REST)  # the rest of 'count' goes with it
    following = session.next(first.plan.duration, REST)
    assert following.step.targets == ((RHAND.index("middle"), 90),)
    assert not session.queue


def test_every_takeover_is_planned_even_where_ruckig_stumbles(program):
    """Requests 0.1 s apart, each reversing a 0.3 s move: the seventh once started from a
    state ruckig could not plan from (an error to the person); it is planned from a
    millisecond on, and so is every one of many random takeovers."""
    there, back = steps("index 90 over 0.3s", program), steps("index 0 over 0.3s", program)
    session = Session(RHAND, [0] * 6, 0.0)
    for k in range(12):
        session.submit(back if k % 2 == 0 else there, k * 0.1, [0] * 6)
    rng = np.random.default_rng(1)
    session, t = Session(RHAND, [0] * 6, 0.0), 0.0
    for _ in range(300):
        t += rng.uniform(0.01, 0.3)
        line = (f"index {rng.integers(181)}, middle {rng.integers(181)} over "
                f"{rng.choice([0.1, 0.3, 0.6])}s")
        segment = session.submit(steps(line, program), t, [0] * 6)
        assert segment is not None and segment.origin - t <= max(RETRY_LATER)
