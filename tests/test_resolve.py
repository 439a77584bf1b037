"""Names, poses, groups, calls, repeats and imports, and what their errors say."""

import os

import pytest

from inmoov_dsl import compile_source
from inmoov_dsl.compiling.compiler import plan_gesture
from inmoov_dsl.compiling.resolve import Resolver
from inmoov_dsl.errors import GestError
from inmoov_dsl.language.load import load, load_program, read_text


def steps_of(source, rhand, gesture="g", read=None):
    files = {"main.gest": source}
    if read:
        files.update(read)
    program = load_program("main.gest", lambda p: files[p] if p in files else _missing(p))
    return Resolver(program, rhand).gesture(gesture)


def _missing(path):
    raise FileNotFoundError(path)


def error_of(source, rhand, gesture="g", files=None):
    with pytest.raises(GestError) as info:
        steps_of(source, rhand, gesture, files)
    return info.value.format().splitlines()


def names(step, rhand):
    return [(rhand.servos[i].name, v) for i, v in step.targets]


def test_groups_poses_and_overrides(rhand):
    (step,) = steps_of("pose fist: fingers 180\ng: fist, thumb 0", rhand)
    assert names(step, rhand) == [("thumb", 0), ("index", 180), ("middle", 180),
                                  ("ring", 180), ("pinky", 180)]


def test_file_groups_keep_their_order_for_a_stagger(rhand):
    (step,) = steps_of("group wave: pinky, ring, middle, index\n"
                       "g: wave 90 stagger 80ms", rhand)
    assert [n for n, _ in names(step, rhand)] == ["pinky", "ring", "middle", "index"]
    assert step.stagger == pytest.approx(0.08)


def test_repeat_and_calls_expand_in_order(rhand):
    steps = steps_of("up: index 90\ndown: index 0\n"
                     "g:\n    repeat 3:\n        up\n        down\n    wait 1s", rhand)
    assert [s.targets for s in steps[:6]] == [((2, 90),), ((2, 0),)] * 3
    assert steps[0].where == "g > up"
    assert steps[-1].hold == pytest.approx(1.0)


def test_servos_not_named_keep_their_value(rhand):
    c = compile_source("g:\n    thumb 90\n    index 45\n    wait 100ms")
    assert c.final == (0, 90, 45, 0, 0, 0)


def test_use_imports_beside_the_file_then_the_library(rhand):
    files = {"main.gest": 'use "lib.gest"\nuse "peace.gest"\ng:\n    fist\n    peace\n',
             "lib.gest": "pose fist: fingers 180\n"}
    def read(path):
        return files[path] if path in files else read_text(path)

    program = load("main.gest", read=read)
    plan = plan_gesture(program, "g", rhand)
    assert plan.final == (0, 180, 0, 0, 180, 180)  # fist, then the library's peace


def test_start_pose_from_a_pose_or_targets(rhand):
    program = load("s.gest", "pose half: fingers 90\ng: index 0\n")
    assert plan_gesture(program, "g", rhand, start="half").start == (0, 90, 90, 90, 90, 90)
    assert plan_gesture(program, "g", rhand, start="wrist 30, thumb 10").start == (
        30, 10, 0, 0, 0, 0)


def test_lookup_says_what_a_name_is(rhand):
    from inmoov_dsl.compiling.names import Gesture, Group, Pose, Servo
    from inmoov_dsl.errors import Pos
    from inmoov_dsl.language.syntax import Name
    program = load_program("main.gest", {"main.gest": (
        "group pair: index, middle\npose fist: fingers 180\ng: pair 9\n")}.__getitem__)
    resolver = Resolver(program, rhand)
    at = Pos("main.gest", 1, 1)
    assert resolver.lookup(Name("index", at)) == Servo("index", 2)
    assert resolver.lookup(Name("pair", at)) == Group("pair", ("index", "middle"))
    assert isinstance(resolver.lookup(Name("fingers", at)), Group)  # the profile's
    assert isinstance(resolver.lookup(Name("fist", at)), Pose)
    assert isinstance(resolver.lookup(Name("g", at)), Gesture)
    with pytest.raises(GestError, match="unknown servo, group, pose or gesture 'fits'"):
        resolver.lookup(Name("fits", at))


RESOLVE_ERRORS = [
    ("g: indx 90", None,
     ["main.gest:1:4: error: unknown servo or group 'indx'", "    g: indx 90", "       ^~~~",
      "  hint: did you mean 'index'?"]),
    ("g:\n    pece\npeace: index 9", None,
     ["main.gest:2:5: error: unknown servo, group, pose or gesture 'pece'", "        pece",
      "        ^~~~", "  hint: did you mean 'peace'?"]),
    ("g: fist 9\npose fist: all 0", None,
     ["main.gest:1:9: error: 'fist' is a pose; it takes no value"]),
    ("g:\n  q\nq:\n  g\n", None,
     ["main.gest:4:3: error: gesture 'g' calls itself: g -> q -> g"]),
    ("g: a\npose a: b\npose b: a", None,
     ["main.gest:3:9: error: pose 'a' refers to itself: a -> b -> a"]),
    ("g: index 90, index 80", None,
     ["main.gest:1:14: error: 'index' is set twice in this step"]),
    ("g: fingers", None, ["main.gest:1:4: error: group 'fingers' needs a value"]),
    ("g: index", None, ["main.gest:1:4: error: servo 'index' needs a value"]),
    ("g: index 9\ng: index 8", None,
     ["main.gest:2:1: error: 'g' is defined twice"]),
    ("g:\n  repeat 1000:\n    repeat 1000: index 9", None,
     ["main.gest:1:1: error: gesture 'g' expands to more than 100,000 steps"]),
    ("g: p, index 9\np: index 9", None,
     ["main.gest:1:4: error: 'p' is a gesture: call it on a line of its own"]),
    ("g: p over 1s\np: index 9", None,
     ["main.gest:1:11: error: a gesture call takes no timing: 'p' sets its own"]),
    ("g: pinky 90\npose index: all 0", None,
     ["main.gest:2:6: error: 'index' is the name of a servo of profile 'rhand'"]),
    ("group pair: index, midle\ng: pair 9", None,
     ["main.gest:1:20: error: unknown servo 'midle' in group 'pair'"]),
    ('use "nowhere.gest"\ng: index 9', None,
     ["main.gest:1:5: error: cannot find 'nowhere.gest'"]),
    ('use "b.gest"\ng: index 9\npose p: all 0', {"b.gest": "pose p: all 9\n"},
     ["main.gest:3:6: error: 'p' is defined twice", "    pose p: all 0", "         ^",
      "  hint: first defined at b.gest:1"]),
    ('use "b.gest"\ng: index 9', {"b.gest": "pose p: all 900\n"},
     ["b.gest:1:13: error: value 900 is outside 0..180"]),
]


@pytest.mark.parametrize(("source", "files", "expected"), RESOLVE_ERRORS)
def test_resolve_errors_say_what_and_where(rhand, source, files, expected):
    lines = error_of(source, rhand, files=files)
    assert lines[:len(expected)] == expected


def test_value_outside_a_servos_range():
    from conftest import make_profile
    profile = make_profile({181: ["a", "b"]}, limits={"lo": 10, "hi": 120})
    with pytest.raises(GestError) as info:
        compile_source("g: a 150", profile=profile, file="r.gest")
    assert info.value.format().splitlines()[0] == (
        "r.gest:1:6: error: value 150 is outside the range of 'a' (10..120)")


def test_import_cycles_are_read_once(rhand):
    files = {"main.gest": 'use "b.gest"\ng: x\n', "b.gest": 'use "main.gest"\npose x: all 9\n'}
    program = load_program("main.gest", files.__getitem__)
    assert Resolver(program, rhand).gesture("g")[0].targets[0] == (0, 9)


def test_deep_pose_nesting_is_an_error_not_a_crash(rhand):
    lines = ["pose p0: index 1"] + [f"pose p{i}: p{i - 1}" for i in range(1, 500)]
    lines = [*lines, "g: p499"]
    message = error_of("\n".join(lines), rhand)[0]
    assert message.endswith("error: poses are nested more than 100 deep")


def test_deep_calls_are_an_error_even_through_a_gesture_measured_before(rhand):
    # x79 is first measured from root at depth 1, then reached again 80 calls deep
    lines = ["x0: index 1"] + [f"x{i}:\n    x{i - 1}" for i in range(1, 80)]
    lines += ["y0:\n    x79"] + [f"y{i}:\n    y{i - 1}" for i in range(1, 80)]
    lines += ["g:\n    x79\n    y79"]
    assert error_of("\n".join(lines), rhand)[:3] == [
        "main.gest:161:5: error: calls and repeats are nested more than 100 deep",
        "        x79", "        ^~~"]


MORE_ERRORS = [
    ("g: p 9\np: index 9", ["main.gest:1:6: error: 'p' is a gesture; it takes no value"]),
    ("g: index 9 stagger 1s stagger 2s",
     ["main.gest:1:23: error: 'stagger' is given twice in this step"]),
    ("g: index 9\npose fingers: all 9",
     ["main.gest:2:6: error: 'fingers' is the name of a group of profile 'rhand'"]),
]


@pytest.mark.parametrize(("source", "expected"), MORE_ERRORS)
def test_more_errors(rhand, source, expected):
    assert error_of(source, rhand)[:len(expected)] == expected


# -- bad input found by fuzzing (issue 11) -------------------------------------------
def test_poses_built_from_each_other_cost_their_text_not_two_to_the_depth(rhand):
    import time
    lines = ["pose p0: index 1, fingers 2"] + [f"pose p{i}: p{i - 1}, p{i - 1}, thumb {i}"
                                               for i in range(1, 60)]
    started = time.process_time()
    (step,) = steps_of("\n".join([*lines, "g: p59"]), rhand)
    assert time.process_time() - started < 1.0  # CPU s (load-proof); 2^59 expansions before
    assert names(step, rhand)[:2] == [("index", 2), ("thumb", 59)]


def test_gestures_calling_each_other_twice_cost_their_output_not_two_to_the_depth(rhand):
    # one expansion pass within the step budget: 2^59 steps fail at the budget, fast
    import time
    lines = ["g0: index 1"] + [f"g{i}:\n    g{i - 1}\n    g{i - 1}" for i in range(1, 60)]
    started = time.process_time()
    assert error_of("\n".join(lines), rhand, "g59")[0] == (
        "main.gest:176:1: error: gesture 'g59' expands to more than 100,000 steps")
    steps = steps_of("\n".join(lines), rhand, "g16")  # 65,536 steps: within the budget
    assert time.process_time() - started < 5.0  # 0.85 s quiet; 2^59 steps would never end
    assert len(steps) == 2 ** 16 and {s.targets for s in steps} == {((2, 1),)}
    assert steps[0].where == steps[-1].where == "g16 > g15 > g14 > g13 > g12 > g11 > g10 > " \
        "g9 > g8 > g7 > g6 > g5 > g4 > g3 > g2 > g1 > g0"


def test_a_call_made_again_from_the_same_place_gives_the_same_steps(rhand):
    source = ("up: index 90\nupdown:\n    up\n    index 0\n"
              "g:\n    updown\n    updown\n    repeat 2: updown\n    up\n")
    steps = steps_of(source, rhand)
    assert [(s.targets, s.where) for s in steps] == [
        (((2, 90),), "g > updown > up"), (((2, 0),), "g > updown")] * 4 + [
        (((2, 90),), "g > up")]


def test_a_start_pose_error_points_into_what_was_typed(rhand):
    program = load("s.gest", "g: index 0\n")
    for start, first, caret in [
            ("wrist 30, indx 9", "--from:1:11: error: unknown servo or group 'indx'",
             "              ^~~~"),
            ("wrist 300", "--from:1:7: error: value 300 is outside 0..180", "          ^~~")]:
        with pytest.raises(GestError) as info:
            plan_gesture(program, "g", rhand, start=start)
        assert info.value.format().splitlines()[:3] == [first, f"    {start}", caret]


def test_a_deep_pose_reached_again_from_further_down_is_still_too_deep(rhand):
    # p90 is expanded first (91 deep: fine), then reached again 20 poses further down
    lines = ["pose p0: index 1"] + [f"pose p{i}: p{i - 1}" for i in range(1, 91)]
    lines += ["pose q0: p90"] + [f"pose q{i}: q{i - 1}" for i in range(1, 20)]
    lines += ["a: p90", "g: q19"]
    assert steps_of("\n".join(lines), rhand, "a")[0].targets == ((2, 1),)
    program = load_program("main.gest", {"main.gest": "\n".join(lines)}.__getitem__)
    resolver = Resolver(program, rhand)
    resolver.gesture("a")
    with pytest.raises(GestError, match="poses are nested more than 100 deep"):
        resolver.gesture("g")


def test_a_nul_in_a_use_path_is_an_error_at_the_use(rhand):
    with pytest.raises(GestError) as info:
        load("main.gest", 'use "a\x00b.gest"\ng: index 9\n', read=read_text, search=[])
    assert info.value.format().startswith(
        "main.gest:1:5: error: cannot read 'a\\x00b.gest': embedded null byte")


@pytest.mark.skipif(not __import__("os").path.exists("/dev/zero"), reason="POSIX")
def test_a_use_of_something_not_a_file_is_refused_not_read(rhand):
    with pytest.raises(GestError) as info:
        load("main.gest", 'use "/dev/zero"\ng: index 9\n', search=[])
    assert info.value.format().startswith(
        "main.gest:1:5: error: use takes a .gest file, not '/dev/zero'")


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="symlinks and FIFOs are POSIX")
def test_use_opens_only_gesture_files_and_quotes_nothing_else(tmp_path):
    secret = tmp_path / "secret.txt"
    secret.write_text("API_KEY=hunter2\n")
    (tmp_path / "evil.gest").symlink_to(secret)
    os.mkfifo(tmp_path / "fifo.gest")
    for used, why in [(secret, "use takes a .gest file"),
                      (tmp_path / "evil.gest", "which is not a .gest file"),
                      (tmp_path / "fifo.gest", "not a regular file"),
                      ("/proc/self/environ", "use takes a .gest file")]:
        with pytest.raises(GestError) as info:  # and no hang on the FIFO
            load(str(tmp_path / "main.gest"), f'use "{used}"\ng: index 9\n', search=[])
        said = info.value.format()
        assert why in said and "hunter2" not in said and "PATH=" not in said


def test_a_lone_surrogate_in_a_comment_compiles(rhand):
    import hashlib
    text = "# \ud800 a lone surrogate\ng: index 9\n"
    compiled = compile_source(text, file="s.gest")
    assert compiled.sources == (
        ("s.gest", hashlib.sha256(text.encode("utf-8", "surrogatepass")).hexdigest()),)


def test_a_file_that_is_not_utf8_is_an_error_at_the_byte(tmp_path):
    path = tmp_path / "latin.gest"
    path.write_bytes(b"# caf\xe9\ng: index 9\n")
    with pytest.raises(GestError) as info:
        load(str(path))
    assert info.value.format().splitlines()[0] == (
        f"{path}:1:6: error: this file is not UTF-8 text: invalid continuation byte "
        f"(byte 0xe9)")


def test_a_file_too_large_to_parse_is_refused_before_it_is_read(tmp_path):
    from inmoov_dsl.language.parse import MAX_SOURCE
    path = tmp_path / "huge.gest"
    path.write_bytes(b"g: index 9\n" * (4 * MAX_SOURCE // 11 + 1))
    with pytest.raises(GestError) as info:
        load(str(path))
    assert info.value.format().splitlines()[0] == (
        f"{path}:1:1: error: the file is longer than {MAX_SOURCE:,} characters: it is not read")


def test_the_gestures_of_one_program_expand_to_a_bounded_total(rhand, monkeypatch):
    from inmoov_dsl.compiling import resolve
    monkeypatch.setattr(resolve, "MAX_TOTAL_STEPS", 25)
    source = "big:\n    repeat 10: index 9\n" + "".join(f"c{i}: big\n" for i in range(3))
    program = load_program("main.gest", {"main.gest": source}.__getitem__)
    shared = resolve.resolver(program, rhand)
    assert resolve.resolver(program, rhand) is shared  # one per program and profile
    shared.gesture("big")
    shared.gesture("big")  # a gesture compiled again is counted once
    shared.gesture("c0")
    with pytest.raises(GestError) as info:
        shared.gesture("c1")
    assert info.value.format().splitlines()[0] == (
        "main.gest:4:1: error: with 'c1', the gestures of this program expand to more than "
        "25 steps in all")


def test_a_long_call_chain_is_abbreviated(rhand):
    names_ = [f"{c * 60}" for c in "abcd"]
    source = "".join(f"{a}: {b}\n" for a, b in zip(names_, names_[1:], strict=False))
    (step,) = steps_of(source + f"{names_[-1]}: index 9\n", rhand, names_[0])
    assert len(step.where) <= 120
    assert step.where.startswith("a" * 10) and " > ... > " in step.where


def test_checking_every_gesture_of_a_file_does_the_shared_work_once(rhand):
    # what made gestc check quadratic: per gesture, the profile read again, every name
    # checked again, the whole text hashed again
    from inmoov_dsl.compiling.compiler import compile_program
    from inmoov_dsl.profiles.profile import load_profile
    program = load("many.gest", "".join(f"g{i}: index {i}\n" for i in range(50)))
    for name in program.own:
        compile_program(program, name, "rhand")
    assert list(program.resolvers.values())[0].profile is load_profile("rhand")
    assert len(program.resolvers) == 1 and list(program.digests) == ["many.gest"]


def test_each_step_of_a_call_knows_where_the_call_is_written(tmp_path, rhand):
    """The resolver carries each call's place (the call in the gesture resolved, the
    outermost one when calls nest) to its planned steps, and marks where each play of it
    begins: the editor's inlay hints and the live page read them, not the expansion
    counted again."""
    path = tmp_path / "calls.gest"
    path.write_text("two:\n    index 90 over 0.5s\n    index 0 over 0.5s\n"
                    "outer: two\n"
                    "g:\n    thumb 90\n    repeat 2: two\n    outer\n    two\n")
    plan = plan_gesture(load(str(path)), "g", rhand)
    marked = [(s.call.line if s.call else None, s.opens) for s in plan.steps]
    assert marked == [(None, False),  # thumb 90: its own step
                      (7, True), (7, False), (7, True), (7, False),  # repeat 2: two
                      (8, True), (8, False),  # outer (two inside it): the call of outer
                      (9, True), (9, False)]  # two again, from another line
    assert all(s.call.file == str(path) for s in plan.steps[1:])
