"""The planner: ends where it should, within the limits, as fast as allowed or on time."""

import numpy as np
import pytest
from ruckig import InputParameter, Ruckig, Trajectory

from inmoov_dsl.compiling.actions import Action
from inmoov_dsl.compiling.compiler import plan_gesture
from inmoov_dsl.compiling.plan import Planner
from inmoov_dsl.errors import GestError
from inmoov_dsl.language.load import load


def solo_time(servo, distance):
    """The time-optimal duration of one servo's move, straight from ruckig."""
    inp, traj = InputParameter(1), Trajectory(1)
    inp.current_position, inp.target_position = [0.0], [float(distance)]
    inp.max_velocity = [servo.max_velocity]
    inp.max_acceleration = [servo.max_acceleration]
    inp.max_jerk = [servo.max_jerk]
    Ruckig(1).calculate(inp, traj)
    return traj.duration


def check_limits(plan, profile):
    t = np.linspace(0, plan.duration + 0.05, 20_001)
    for servo, track in zip(profile.servos, plan.tracks, strict=True):
        p, v = track.position(t), track.velocity(t)
        assert np.all(np.abs(v) <= servo.max_velocity * (1 + 1e-9) + 1e-9), servo.name
        acc = np.gradient(v, t)
        assert np.all(np.abs(acc) <= servo.max_acceleration * 1.01 + 1), servo.name
        assert p.min() >= -1e-9 and p.max() <= 180 + 1e-9


def test_random_moves_start_and_end_exactly_within_limits(rhand):
    rng = np.random.default_rng(7)
    planner = Planner(rhand)
    for _ in range(300):
        start = tuple(int(x) for x in rng.integers(0, 181, 6))
        steps = []
        for _ in range(int(rng.integers(1, 4))):
            servos = rng.choice(6, size=int(rng.integers(1, 7)), replace=False)
            over = float(rng.uniform(0.05, 1.5)) if rng.random() < 0.5 else None
            stagger = float(rng.uniform(0, 0.2)) if rng.random() < 0.3 else 0.0
            steps.append(Action(tuple((int(i), int(rng.integers(0, 181))) for i in servos),
                              over=over, stagger=stagger))
        plan = planner.plan(steps, start)
        assert len(plan.tracks) == len(start)  # a track for every servo
        for i, track in enumerate(plan.tracks):
            assert track.position(0.0) == start[i]
            assert track.position(plan.duration) == plan.final[i]
            assert track.position(plan.duration + 10) == plan.final[i]
        expected = list(start)
        for s in steps:
            for i, v in s.targets:
                expected[i] = v
        assert plan.final == tuple(expected)
        check_limits(plan, rhand)  # every plan's, not the last one's only


def test_limits_hold_over_a_sweep(rhand):
    rng = np.random.default_rng(11)
    planner = Planner(rhand)
    for _ in range(40):
        steps = [Action(tuple((i, int(rng.integers(0, 181))) for i in range(6)),
                      over=float(rng.uniform(0.1, 1.0)) if rng.random() < 0.5 else None)
                 for _ in range(3)]
        check_limits(planner.plan(steps, (0,) * 6), rhand)


def test_without_over_a_step_is_as_fast_as_its_slowest_servo(rhand):
    plan = Planner(rhand).plan([Action(((2, 180), (3, 90), (1, 40)))], (0,) * 6)
    slowest = max(solo_time(rhand.servos[2], 180), solo_time(rhand.servos[3], 90),
                  solo_time(rhand.servos[1], 40))
    assert plan.duration == pytest.approx(slowest, abs=1e-6)


def test_with_over_every_servo_arrives_together_on_time(rhand):
    plan = Planner(rhand).plan([Action(((2, 180), (3, 20), (1, 60)), over=1.25)], (0,) * 6)
    assert plan.duration == pytest.approx(1.25, abs=1e-9)
    for i, target in ((2, 180), (3, 20), (1, 60)):
        track = plan.tracks[i]
        assert track.position(1.25 - 0.02) != pytest.approx(target, abs=1e-3)
        assert track.position(1.25) == target
    assert plan.warnings == ()


def test_a_stagger_starts_each_servo_later(rhand):
    step = Action(((5, 90), (4, 90), (3, 90), (2, 90)), over=0.5, stagger=0.1)
    plan = Planner(rhand).plan([step], (0,) * 6)
    assert plan.duration == pytest.approx(0.5 + 3 * 0.1)
    for k, i in enumerate((5, 4, 3, 2)):
        begin = 0.1 * k
        assert plan.tracks[i].position(begin) == 0
        assert plan.tracks[i].position(begin + 0.01) > 0
        assert plan.tracks[i].position(begin + 0.5) == 90


def test_an_impossible_over_is_stretched_with_a_warning(rhand):
    program = load("card.gest", "peace: index 180, middle 180 over 0.4s")
    plan = plan_gesture(program, "peace", rhand)
    needed = max(solo_time(rhand.servos[2], 180), solo_time(rhand.servos[3], 180))
    assert plan.duration == pytest.approx(needed)
    (warning,) = plan.warnings
    assert warning.format().splitlines() == [
        f"card.gest:1:35: warning: move stretched: needs {needed:.2f} s, asked 0.40 s",
        "    peace: index 180, middle 180 over 0.4s",
        "                                      ^~~~",
        "  hint: the profile's limits allow no faster move; ask for more time or raise "
        "the limits",
    ]
    assert plan.steps[0].stretched


def test_strict_makes_a_stretch_an_error(rhand):
    program = load("card.gest", "peace: index 180, middle 180 over 0.4s")
    with pytest.raises(GestError) as info:
        plan_gesture(program, "peace", rhand, strict=True)
    assert info.value.format().startswith(
        "card.gest:1:35: error: move stretched: needs 0.60 s, asked 0.40 s")


def test_holds_and_moves_to_the_current_pose(rhand):
    plan = Planner(rhand).plan([Action((), hold=0.5), Action(((2, 0),), over=0.3),
                                Action(((2, 0),))], (0,) * 6)
    assert plan.duration == pytest.approx(0.8)
    assert [s.kind for s in plan.steps] == ["hold", "move", "move"]


def test_a_gesture_longer_than_an_hour_is_refused(rhand):
    program = load("long.gest", "g:\n    repeat 10:\n        wait 600s\n")
    with pytest.raises(GestError) as info:
        plan_gesture(program, "g", rhand)
    assert "the gesture lasts more than 3600 s" in info.value.format()


def test_a_stretched_stagger_reports_each_servos_move_time(rhand):
    program = load("w.gest", "g: index 180, middle 180 over 0.3s stagger 100ms")
    plan = plan_gesture(program, "g", rhand)
    needed = max(solo_time(rhand.servos[2], 180), solo_time(rhand.servos[3], 180))
    assert plan.duration == pytest.approx(needed + 0.1)
    assert plan.warnings[0].message == f"move stretched: needs {needed:.2f} s, asked 0.30 s"


# -- failures and warnings (issue 11) -------------------------------------------------
class FailingRuckig:
    """A ruckig that fails as the real one did on limits like 1e-09."""

    def __init__(self, dofs):
        pass

    def calculate(self, inp, traj):
        raise ValueError("-1 is not a valid Result.")


class RefusingRuckig(FailingRuckig):
    def calculate(self, inp, traj):
        from ruckig import Result
        return Result.ErrorSynchronizationCalculation


@pytest.mark.parametrize(("ruckig", "why"), [
    (FailingRuckig, "-1 is not a valid Result."),
    (RefusingRuckig, "ErrorSynchronizationCalculation"),
])
def test_any_failure_of_ruckig_is_an_error_naming_the_step(rhand, monkeypatch, ruckig, why):
    from inmoov_dsl.compiling import plan as planner
    monkeypatch.setattr(planner, "Ruckig", ruckig)
    program = load("f.gest", "up: index 90 over 0.5s\ng:\n    wait 1s\n    up\n")
    with pytest.raises(GestError) as info:
        plan_gesture(program, "g", rhand)
    assert info.value.format().splitlines()[:3] == [
        f"f.gest:1:5: error: cannot plan this step of 'g > up': ruckig failed ({why})",
        "    up: index 90 over 0.5s", "        ^~~~~"]


STRETCHED = "slow: index 180, middle 180 over 0.4s\nback: index 0, middle 0 over 2s\n"


@pytest.mark.parametrize("body", [
    "    repeat 9:\n        slow\n        back\n",
    "    repeat 9:\n        index 180, middle 180 over 0.4s\n        back\n",
    "    slow\n    back\n" * 9,
])
def test_a_stretch_is_told_once_per_place_with_its_count(rhand, body):
    plan = plan_gesture(load("w.gest", STRETCHED + "g:\n" + body), "g", rhand)
    needed = max(solo_time(rhand.servos[2], 180), solo_time(rhand.servos[3], 180))
    (warning,) = plan.warnings
    assert warning.message == f"move stretched: needs {needed:.2f} s, asked 0.40 s (9 times)"
    assert sum(s.stretched for s in plan.steps) == 9


def test_a_stretch_says_enough_decimals_to_tell_the_two_apart():
    from inmoov_dsl.compiling.stretch import stretch_message
    assert stretch_message(0.5049, 0.5) == "move stretched: needs 0.505 s, asked 0.500 s"
    assert stretch_message(0.62, 0.4) == "move stretched: needs 0.62 s, asked 0.40 s"


def test_positions_are_exact_to_a_nanodegree(rhand):
    # float noise below 1e-9 degree no longer decides which way a half degree rounds
    plan = Planner(rhand).plan([Action(((2, 180),))], (0,) * 6)
    t = np.linspace(0, plan.duration, 1001)
    p = plan.tracks[2].position(t)
    assert np.all(p == np.round(p, 9))
