"""Invariants of every byte stream, for generated gestures, checked with a board model
written from the protocol (tests/boardmodel.py), not from the encoder."""

import json
import math

import numpy as np
import pytest
from boardmodel import final_values, read_stream
from conftest import early, library_profile, make_profile
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from inmoov_dsl import compile_source, from_json, load_profile, measure, protocol, to_json
from inmoov_dsl.compiling.compiled_reader import read_compiled
from inmoov_dsl.compiling.compiler import compile_program
from inmoov_dsl.compiling.playable import check_profile
from inmoov_dsl.errors import GestError
from inmoov_dsl.language.load import load

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
        elif draw(st.booleans()):
            text += " through"
        return text

    def together():  # two moves at once, on servos of their own
        chosen = draw(st.lists(st.sampled_from(servo_names), min_size=2, max_size=6,
                               unique=True))
        cut = draw(st.integers(1, len(chosen) - 1))
        parts = [chosen[:cut], chosen[cut:]]
        return " & ".join(", ".join(f"{n} {draw(st.integers(0, 180))}" for n in part)
                          + (f" over {draw(durations(20, 900))}" if draw(st.booleans())
                             else "") for part in parts)

    lines = []
    for _ in range(draw(st.integers(1, 5))):
        kind = draw(st.integers(0, 6))
        if kind == 6:
            lines.append(f"    {together()}")
        elif kind == 0:
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
        # every byte on the link's byte grid: a whole number of byte-times after CANCEL
        assert np.allclose(times / tau, np.rint(times / tau), rtol=0, atol=1e-6)
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
            # the plan at the moment the value arrives, rounded (the pair arrives up to
            # a byte-time before its slot, on the byte grid, with the slot's value)
            planned = float(plan.tracks[profile.index(servo.name)].position(arrival))
            assert abs(value - planned) <= 0.5 + servo.max_velocity * tau + 1e-9
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
    reports = measure(plan, compiled.streams)
    assert len(reports) == 1  # the hand's one board
    for report in reports:
        assert report.coverage == 1.0
        assert report.max_error <= 0.5 + early(rhand, report.baud)


@HYPOTHESIS
@given(data=st.data())
def test_one_stream_per_board(two_boards, data):
    source = data.draw(gestures(list(two_boards.names)))
    compiled, _ = check_stream_invariants(two_boards, source)
    assert [s.board for s in compiled.streams] == [181, 183]


SATURATED = make_profile({181: [f"s{i}" for i in range(14)]}, name="crowded")


# a value tie at half a degree, a frame apart: float noise in the plan rounded it down
# then up, a step of 9 degrees where the servo moves 8 (the plan is now exact to 1e-9)
TIE = "g:\n    s0 11, s1 0, s2 0, s3 11, s4 11, s5 98 stagger 1ms\n"


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(source=gestures(list(SATURATED.names)))
@example(source=TIE)
def test_a_crowded_link_keeps_every_rule(source):
    # 14 servos on one 9600-baud board: 9 pairs fit in a frame, so not all move each frame
    check_stream_invariants(SATURATED, source)


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



# -- compiled files: what the reader accepts keeps every rule above (issue 11) --------
def compiled_doc(source="peace: index 180, middle 180 over 0.7s", profile="rhand"):
    return json.loads(to_json(compile_source(source, profile=profile)))


def refused(doc_or_text, file="x.gestc"):
    text = doc_or_text if isinstance(doc_or_text, str | bytes) else json.dumps(doc_or_text,
                                                                                indent=1)
    with pytest.raises(GestError) as info:
        from_json(text, file)
    (d,) = info.value.diagnostics
    assert d.format().startswith(f"{file}:{d.pos.line}:{d.pos.column}: error: not a usable "
                                 f"compiled gesture: ")
    return d


def edit(change):
    doc = compiled_doc()
    change(doc)
    return doc


def stream(doc):
    return doc["streams"][0]


@pytest.mark.parametrize(("change", "message"), [
    (lambda d: stream(d)["bytes"].__setitem__(2, 181),
     "board 181: byte 2 is 181, a value above 180"),
    (lambda d: stream(d)["bytes"].__setitem__(1, 200),
     "board 181: byte 1 is 200, a servo ID above 180"),
    (lambda d: stream(d)["bytes"].__setitem__(5, 253),  # DUMP in the middle
     "board 181: byte 5 is 253, a servo ID above 180"),
    (lambda d: stream(d)["bytes"].__setitem__(4, 256),
     "board 181: byte 5 is not a whole number in 0..255"),
    (lambda d: (stream(d)["bytes"].pop(), stream(d)["times"].pop()),
     "board 181: a stream is CANCEL (255) then whole (servo ID, value) pairs"),
    (lambda d: stream(d)["bytes"].__setitem__(0, 2),
     "board 181: a stream is CANCEL (255) then whole (servo ID, value) pairs"),
    (lambda d: stream(d)["times"].__setitem__(0, 0.001),
     "board 181: the first byte goes at 0.001 s, not 0"),
    (lambda d: stream(d)["times"].__setitem__(2, stream(d)["times"][1]),
     "board 181: two bytes closer than a byte-time (1.042 ms at 9600 baud)"),
    (lambda d: stream(d)["times"].__setitem__(-1, 1e9),
     "board 181: a byte goes at 1e+09 s, after the gesture's 0.7 s"),
    (lambda d: stream(d)["times"].__setitem__(3, "soon"),
     "board 181: send time 4 is not a finite number of seconds"),
    (lambda d: stream(d).__setitem__("bytes", 10 ** 12),
     "'bytes' must be a list, got 1000000000000"),
    (lambda d: stream(d).__setitem__("baud", 0),
     "board 181: a baud that carries a servo command per 20 ms frame is a whole number up "
     "to 2,000,000, got 0"),
    (lambda d: stream(d).__setitem__("board", 12),
     "a board ID is a whole number in 181..247, got 12"),
    (lambda d: d["streams"].append(dict(stream(d))), "board 181 has two streams"),
    (lambda d: d.__setitem__("duration", 1e6), "a duration of 1e+06 s (at most 3600 s)"),
    (lambda d: d.__setitem__("duration", 10 ** 400),
     "'duration' must be a finite number, got 1000000000000000000000000000000000000..."),
    (lambda d: d.__setitem__("start", [0] * 5),
     "'start' must be 6 whole numbers in 0..180, one per servo"),
    (lambda d: d["final"].__setitem__(0, 1.5),
     "'final' must be 6 whole numbers in 0..180, one per servo"),
    (lambda d: d.__setitem__("servos", ["a", "a"]),
     "'servos' must be the names of 1 to 181 servos, each once"),
    (lambda d: d["steps"][0].__setitem__("end", 99.0),
     "step 1 runs from 0 s to 99 s, outside the gesture's 0.7 s"),
    (lambda d: d["steps"][0].__setitem__("kind", "dance"),
     "a step's kind is 'move', 'hold' or 'say', got \"dance\""),
    (lambda d: d.pop("gesture"), "missing field 'gesture'"),
])
def test_a_compiled_file_breaking_a_rule_is_refused_at_its_place(change, message):
    d = refused(edit(change))
    assert d.message == f"not a usable compiled gesture: {message}"


def test_numbers_json_does_not_allow_and_deep_nesting_are_refused():
    text = to_json(compile_source("g: index 9"))
    for bad, message in [(text.replace('"final": [\n  0', '"final": [\n  1e999'),
                          "'final' must be 6 whole numbers in 0..180, one per servo"),
                         (text.replace('"duration": ', '"duration": Infinity, "x": '),
                          "Infinity is not a number JSON allows"),
                         ("[" * 100_000 + "]" * 100_000, "arrays or objects nested too deep"),
                         ('{"a": ' + "1" * 5000 + "}",
                          "invalid JSON (a number of thousands of digits)")]:
        assert refused(bad).message == f"not a usable compiled gesture: {message}"


def test_a_compiled_file_with_flipped_bytes_is_an_error_at_the_byte():
    data = to_json(compile_source("g: index 9")).encode()
    data = data[:40] + b"\xff" + data[41:]
    with pytest.raises(GestError) as info:
        from_json(data, "x.gestc")
    assert info.value.format().startswith("x.gestc:3:")
    assert "this file is not UTF-8 text" in info.value.first.message


def test_the_error_points_at_the_field(tmp_path):
    d = refused(edit(lambda d: stream(d)["bytes"].__setitem__(2, 181)))
    assert d.source_line.strip() == "181,"
    d = refused(edit(lambda d: d.__setitem__("duration", 1e6)))
    assert d.source_line.strip().startswith('"duration"')


def test_every_library_gesture_reads_back():
    from inmoov_dsl import load_library
    from inmoov_dsl.compiling.compiler import compile_file
    library = load_library()
    assert {"peace", "count", "hello"} <= set(library)  # the hand's and the body's
    for name, path in library.items():
        profile = library_profile(path)
        compiled = compile_file(path, name, profile)
        again = from_json(to_json(compiled))
        assert [s.data for s in again.streams] == [s.data for s in compiled.streams]
        assert again.sounds == compiled.sounds


def test_read_compiled_caps_the_size_before_reading(tmp_path, monkeypatch):
    from inmoov_dsl.compiling import compiled_reader as module
    path = tmp_path / "g.gestc"
    path.write_text(to_json(compile_source("g: index 9")), encoding="utf-8")
    assert read_compiled(path).final == (0, 0, 9, 0, 0, 0)
    monkeypatch.setattr(module, "MAX_COMPILED", 100)
    with pytest.raises(GestError, match="larger than 100 bytes: it is not read"):
        read_compiled(path)
    with pytest.raises(GestError, match="cannot find"):
        read_compiled(tmp_path / "none.gestc")
    with pytest.raises(GestError, match="cannot read"):
        read_compiled(tmp_path)


def test_check_profile_refuses_boards_ids_and_bauds_the_profile_has_not(rhand, two_boards):
    peace = from_json(to_json(compile_source("peace: index 180, middle 180 over 0.7s")))
    check_profile(peace, rhand)
    with pytest.raises(GestError) as info:
        check_profile(peace, load_profile("lhand"))
    assert info.value.first.message == (
        "'peace' has a stream for board 181, and profile 'lhand' has no board 181 (its "
        "boards: 183)")
    assert info.value.first.pos.line > 1  # lhand's [[board]]
    with pytest.raises(GestError) as info:
        check_profile(peace, two_boards)  # board 181 has servo IDs 0..2 there
    assert info.value.first.message == (
        "'peace' commands servo ID 3 on board 181, which profile 'two' does not give that "
        "board")
    fast = make_profile({181: list(rhand.names)}, baud=115200, name="fast")
    quick = compile_source("g: wrist 90", profile=fast)
    with pytest.raises(GestError) as info:
        check_profile(quick, rhand)
    assert info.value.first.message == (
        "'g' is timed for board 181 at 115200 baud, and profile 'rhand' runs that board "
        "at 9600")


def _edited(compiled, edit):
    """``compiled``'s file with its stream's times and bytes changed by ``edit``, read
    back."""
    doc = json.loads(to_json(compiled))
    stream = doc["streams"][0]
    edit(stream["times"], stream["bytes"])
    return from_json(json.dumps(doc))


def _twice(times, data):
    """The first pair moved to just before the second: two in one frame."""
    tau = 1 / 960
    times[1], times[2] = times[3] - 2 * tau, times[3] - tau


def _jump(times, data):
    """The first value made 180: from 0 in one frame."""
    data[2] = 180


@pytest.mark.parametrize(("edit", "message"), [
    (_twice, "'g' sends index (ID 2) two values in the servo frame ending at 0.06 s"),
    (_jump, "'g' moves index (ID 2) from 0 to 180 between 0.000 s and 0.0"),
])
def test_a_compiled_file_that_breaks_its_servos_limits_is_refused_before_a_byte(
        rhand, edit, message):
    """A compiled file is a file people share: one that sends a servo more than the
    compiler would (twice in a frame, or faster than its max_velocity) is refused
    against the profile, as gestplay reads it, before anything is sent."""
    compiled = compile_source("g: index 40 over 1s")
    check_profile(from_json(to_json(compiled)), rhand)
    with pytest.raises(GestError) as info:
        check_profile(_edited(compiled, edit), rhand)
    assert info.value.first.message.startswith(message), info.value.first.message
    assert info.value.first.pos.line > 1  # the servo's board in the profile
    assert "compile it again" in info.value.first.hint


@pytest.mark.parametrize("version", ["true", "1.0", '"1"'])
def test_a_version_that_is_not_the_integer_1_is_refused(version):
    text = to_json(compile_source("g: index 9")).replace('"version": 1,',
                                                         f'"version": {version},')
    with pytest.raises(GestError) as info:
        from_json(text, "g.gestc")
    assert info.value.first.message.startswith("not a usable compiled gesture: format "
                                               "version ")
    assert info.value.first.message.endswith("this gestc reads 1")
