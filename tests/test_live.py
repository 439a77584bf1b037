"""Live motion: typed steps, and a new step taking over a running move."""

import os
import queue
import subprocess
import sys
import threading
import time

import numpy as np
import pytest
from terminal import AtTerminal

from inmoov_dsl.cli.gestplay.repl import library_program, repl, waiting_on
from inmoov_dsl.errors import GestError
from inmoov_dsl.live import Session, line_steps
from inmoov_dsl.plan import MotionState
from inmoov_dsl.player import Link
from inmoov_dsl.ports import open_port
from inmoov_dsl.profile import load_profile

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


# -- the REPL against the virtual board ----------------------------------------------
def run_repl(script, take_over=True):
    """Play timed lines [(seconds, line)] into the REPL on sim://; the board's log."""
    link = Link(181, open_port("sim://?boot=0", 9600), "sim://")
    lines: queue.Queue = queue.Queue()

    def typist():
        start = time.perf_counter()
        for at, line in script:
            time.sleep(max(0, at - (time.perf_counter() - start)))
            lines.put(line)
        lines.put(None)

    threading.Thread(target=typist, daemon=True).start()
    start = time.monotonic()
    assert repl([link], RHAND, {}, waiting_on(lines), take_over) == 0
    board = link.port.board
    board.advance(time.monotonic())
    return board, [(t - start, w) for t, w in board.log]


def test_the_repl_takes_over_on_the_board_without_a_jump():
    board, log = run_repl([(0.0, "index 90 over 0.6s"), (0.3, "index 180")])
    index = [(t, w.value) for t, w in log if w.id == 2]
    values = [v for _, v in index]
    assert values[-1] == 180 and board.positions()[2] == 180
    assert values == sorted(values)  # never went back
    vmax = RHAND.servos[INDEX].max_velocity
    gaps = np.diff([t for t, _ in index])
    steps_ = np.diff(values)
    assert np.all(steps_ <= vmax * np.maximum(gaps, 0.02) + 1)  # no jump
    # around the takeover (0.3 s) the finger keeps moving: every frame a new value
    around = [v for t, v in index if 0.2 < t < 0.5]
    assert len(around) >= 12 and len(set(around)) == len(around)


def test_the_repl_runs_library_gestures_and_reports_errors(capsys):
    board, _ = run_repl([(0.0, "indx 3"), (0.0, "peace"), (0.0, "where")])
    out, err = capsys.readouterr()
    assert "<repl>:1:1: error: unknown servo or group 'indx'" in err
    assert "hint: did you mean 'index'?" in err
    assert out.startswith("wrist 0  thumb 0  index 0")
    assert board.positions() == {0: 0, 1: 180, 2: 0, 3: 0, 4: 180, 5: 180}


def test_gestplay_repl_reads_steps_from_a_pipe():
    done = subprocess.run([sys.executable, "-m", "inmoov_dsl.cli.gestplay", "repl", "--port",
                           "sim://?boot=0.05"], input="ring 45 over 0.2s\nwhere\nquit\n",
                          capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("wrist 0  thumb 0  index 0  middle 0  ring 0  pinky 0")


@pytest.mark.skipif(not hasattr(os, "openpty"), reason="pseudo-terminals are POSIX")
def test_at_a_terminal_each_reply_comes_before_the_next_prompt():
    term = AtTerminal([sys.executable, "-m", "inmoov_dsl.cli.gestplay", "repl", "--port",
                       "sim://?boot=0"])
    term.read_until(b"gest> ")
    term.press("indx 3\r")
    term.read_until(b"did you mean 'index'?")
    term.press("where\r")
    term.read_until(b"pinky 0")
    term.press("\x04")
    code, screen = term.finish()
    assert code == 0, screen
    typed, answer = screen.split("gest> indx 3", 1)[1], screen.split("gest> where", 1)[1]
    assert typed.index("error: unknown servo or group 'indx'") < typed.index("gest> ")
    assert answer.index("wrist 0  thumb 0") < answer.index("gest> ")


@pytest.mark.parametrize(("take_over", "peak"), [(False, 90), (True, 0)])
def test_typed_lines_take_over_and_scripts_wait(take_over, peak):
    board, log = run_repl([(0.0, "index 90 over 0.3s"), (0.0, "index 0")], take_over)
    index = [w.value for _, w in log if w.id == 2]
    assert max(index, default=0) == peak and board.positions()[2] == 0


def test_a_script_waits_for_each_step(program):
    session = Session(RHAND, REST, now=0.0)
    first = session.append(steps("index 90 over 0.3s", program), 0.0, REST)
    assert session.append(steps("index 0", program), 0.1, REST) is None
    second = session.next(0.31, [0, 0, 90, 0, 0, 0])
    assert first.plan.final[INDEX] == 90 and second.origin == pytest.approx(0.31)
    assert MotionState.at(second.plan, 0).velocity[INDEX] == 0
