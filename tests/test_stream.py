"""Invariants of every byte stream, for generated gestures, checked with a board model
written from the protocol (tests/boardmodel.py), not from the encoder."""

import math

import numpy as np
import pytest
from boardmodel import final_values, read_stream
from conftest import make_profile
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from inmoov_dsl import measure, protocol
from inmoov_dsl.compiler import compile_program, load

FRAME = protocol.SERVO_FRAME


def durations(lo_ms, hi_ms):
    return st.integers(lo_ms, hi_ms).map(lambda ms: f"{ms}ms")


@st.composite
def gestures(draw, servo_names):
    """Source text of a random valid gesture over ``servo_names``."""

    def move():
        chosen = draw(st.lists(st.sampled_from(servo_names), min_size=1, max_size=6,
                               unique=True))
        text = ", ".join(f"{n} {draw(st.integers(0, 180))}" for n in chosen)
        if draw(st.booleans()):
            text += f" over {draw(durations(20, 1500))}"
        if draw(st.integers(0, 3)) == 0:
            text += f" stagger {draw(durations(1, 150))}"
        return text

    lines = []
    for _ in range(draw(st.integers(1, 5))):
        kind = draw(st.integers(0, 5))
        if kind == 0:
            lines.append(f"    wait {draw(durations(1, 400))}")
        elif kind == 1:
            lines.append(f"    repeat {draw(st.integers(1, 3))}:")
            lines.append(f"        {move()}")
            lines.append(f"        {move()}")
        else:
            lines.append(f"    {move()}")
    return "g:\n" + "\n".join(lines) + "\n"


def check_stream_invariants(profile, source):
    compiled, plan = compile_program(load("gen.gest", source), "g", profile)
    start = dict(zip((s.id for s in profile.servos), plan.start, strict=True))
    final = dict(zip((s.id for s in profile.servos), plan.final, strict=True))
    for stream in compiled.streams:
        board = next(b for b in profile.boards if b.id == stream.board)
        servos = {profile.servos[profile.index(n)].id: profile.servos[profile.index(n)]
                  for n in board.servos}
        tau = protocol.byte_time(board.baud)
        data = list(stream.data)
        times = stream.times

        # the stream opens with CANCEL; bytes never closer than one byte-time
        assert data[0] == protocol.Signal.CANCEL and times[0] == 0
        assert np.all(np.diff(times) >= tau - 1e-9)
        # no value above 180, every ID one of this board's servos
        events = read_stream(times.tolist(), data, board.baud)
        assert all(sid in servos and 0 <= v <= 180 for _, sid, v in events)
        assert max(data[1:], default=0) <= 180
        # the board ends in exactly the final keyframe
        ends = final_values(events, {sid: start[sid] for sid in servos})
        assert ends == {sid: final[sid] for sid in servos}

        last: dict[int, tuple[float, int]] = {}
        frames_used: set[tuple[int, int]] = set()
        pairs_in_frame: dict[int, int] = {}
        for arrival, sid, value in events:
            frame = math.ceil(arrival / FRAME - 1e-9) - 1
            # one value per servo per 20 ms frame, and no more pairs than fit in it
            assert (sid, frame) not in frames_used
            frames_used.add((sid, frame))
            pairs_in_frame[frame] = pairs_in_frame.get(frame, 0) + 1
            assert pairs_in_frame[frame] <= protocol.pairs_per_frame(board.baud)
            # sent only when the rounded value changed
            before = last.get(sid, (0.0, start[sid]))
            assert value != before[1]
            # within the velocity limit (plus one degree of rounding)
            servo = servos[sid]
            assert abs(value - before[1]) <= servo.max_velocity * (arrival - before[0]) + 1
            # the plan at the moment the value arrives, rounded
            planned = float(plan.tracks[profile.index(servo.name)].position(arrival))
            assert abs(value - planned) <= 0.5 + 1e-9
            last[sid] = (arrival, value)
    return compiled, plan


HYPOTHESIS = settings(max_examples=60, deadline=None,
                      suppress_health_check=[HealthCheck.too_slow])


@HYPOTHESIS
@given(data=st.data())
def test_right_hand_streams(rhand, data):
    source = data.draw(gestures(list(rhand.names)))
    compiled, plan = check_stream_invariants(rhand, source)
    # six servos fit in a frame at 9600 baud: every frame that needs a value gets one
    for report in measure(plan, compiled.streams):
        assert report.coverage == 1.0
        assert report.max_error <= 0.5 + 1e-9


@HYPOTHESIS
@given(data=st.data())
def test_one_stream_per_board(two_boards, data):
    source = data.draw(gestures(list(two_boards.names)))
    compiled, _ = check_stream_invariants(two_boards, source)
    assert [s.board for s in compiled.streams] == [181, 183]


SATURATED = make_profile({181: [f"s{i}" for i in range(14)]}, name="crowded")


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_a_crowded_link_keeps_every_rule(data):
    # 14 servos on one 9600-baud board: 9 pairs fit in a frame, so not all move each frame
    check_stream_invariants(SATURATED, data.draw(gestures(list(SATURATED.names))))


def test_a_crowded_link_serves_the_servos_furthest_behind_and_says_so():
    profile = SATURATED
    source = "g: " + ", ".join(f"s{i} 180" for i in range(14)) + "\n"
    compiled, plan = check_stream_invariants(profile, source)
    (report,) = measure(plan, compiled.streams)
    assert report.coverage < 1.0
    assert report.peak_utilisation > 0.9
    # servos take turns: no servo is starved while others are served
    events = read_stream(compiled.streams[0].times.tolist(), list(compiled.streams[0].data),
                         9600)
    counts = np.bincount([sid for _, sid, _ in events], minlength=14)
    assert counts.min() >= 0.6 * counts.max()


@pytest.mark.parametrize("baud", [9600, 115200])
def test_the_last_values_are_the_final_keyframe_at_any_baud(baud):
    profile = make_profile({181: ["a", "b"]}, baud=baud)
    compiled, _ = compile_program(load("b.gest", "g: a 133, b 47 over 0.3s"), "g", profile)
    events = read_stream(compiled.streams[0].times.tolist(), list(compiled.streams[0].data),
                         baud)
    assert final_values(events, {0: 0, 1: 0}) == {0: 133, 1: 47}
