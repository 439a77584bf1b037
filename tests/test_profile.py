"""Robot profiles: the shipped right hand, and what a broken profile says."""

import pytest
from conftest import board_toml, servo_toml

from inmoov_dsl import compile_source, load_profile
from inmoov_dsl.errors import GestError
from inmoov_dsl.profile import builtin_profiles, parse_profile


def test_the_right_hand_is_the_original_one(rhand):
    assert rhand.names == ("wrist", "thumb", "index", "middle", "ring", "pinky")
    assert [s.id for s in rhand.servos] == [0, 1, 2, 3, 4, 5]
    (board,) = rhand.boards
    assert (board.id, board.baud) == (181, 9600)
    assert [s.calibration for s in rhand.servos] == [
        (125, 160), (50, 160), (55, 155), (35, 155), (45, 145), (55, 145)]
    assert all(s.reversed for s in rhand.servos)
    assert rhand.rest_pose == dict.fromkeys(rhand.names, 0)
    assert [s.pin for s in rhand.servos] == [2, 3, 4, 5, 6, 7]
    assert rhand.groups["fingers"] == ("thumb", "index", "middle", "ring", "pinky")
    assert rhand.groups["all"] == rhand.names


def test_limits_are_240_real_degrees_per_second_in_command_degrees(rhand):
    for servo in rhand.servos:
        span = servo.calibration[1] - servo.calibration[0]
        assert servo.max_velocity == pytest.approx(240 * 180 / span, rel=0.01)
        assert servo.max_acceleration == pytest.approx(4800 * 180 / span, rel=0.01)
        assert servo.max_jerk == pytest.approx(96000 * 180 / span, rel=0.01)


def test_builtin_profiles_are_listed():
    assert "rhand" in builtin_profiles()


def test_unknown_profile_suggests_a_name():
    with pytest.raises(GestError) as info:
        load_profile("rhnd")
    assert info.value.format() == "error: unknown profile 'rhnd'\n  hint: did you mean 'rhand'?"


def test_a_profile_from_a_path(tmp_path):
    path = tmp_path / "mine.toml"
    path.write_text(board_toml(190, ["a"]) + servo_toml("a", 9))
    profile = load_profile(str(path))
    assert profile.name == "mine" and profile.servos[0].id == 9


GLOVE = """[[glove]]
id = 182
board = 181
deadband = 2
sensors = [{ servo = "a", pin = 14, calibration = [500, 700] }]
"""

PROFILE_ERRORS = [
    (board_toml(181, ["a", "b"]) + servo_toml("a", 1) + servo_toml("b", 1),
     "servo 'b': id 1 is already used by servo 'a'"),
    (board_toml(181, ["a", "b"]) + servo_toml("a", 1),
     "board 181 lists servo 'b' but there is no [servo.b]"),
    (board_toml(181, ["a"]) + servo_toml("a", 1) + servo_toml("b", 2),
     "servo 'b' is on no board"),
    (board_toml(181, ["a"], baud=300) + servo_toml("a", 1),
     "board 181: baud 300 is too slow: not one servo command fits in a 20 ms servo frame"),
    (board_toml(12, ["a"]) + servo_toml("a", 1),
     "board id must be a whole number in 181..247, got 12"),
    (board_toml(181, ["a"]) + servo_toml("a", 1, v=-3),
     "servo 'a': 'max_velocity' must be greater than 0, got -3"),
    (board_toml(181, ["a"]) + servo_toml("a", 1, lo=100, hi=50),
     "servo 'a': 'range' must be [low, high] with 0 <= low <= high <= 180, got [100, 50]"),
    (board_toml(181, ["wait"]) + servo_toml("wait", 1),
     "servo 'wait': a servo name must be a word (letters, digits, _) and not a keyword of "
     "the language"),
    (board_toml(181, ["a"]) + servo_toml("a", 1) + '[groups]\nhand = ["a", "z"]\n',
     "group 'hand' names unknown servo 'z'"),
    ("name = \n", "invalid TOML: Invalid value"),
    (board_toml(181, ["a"]) + board_toml(181, ["b"]) + servo_toml("a", 1) + servo_toml("b", 2),
     "board 181 is declared twice"),
    (board_toml(181, ["a"]) + board_toml(183, ["a"]) + servo_toml("a", 1),
     "servo 'a' is on board 181 and board 183"),
    ('name = "x"\n', "a profile needs at least one [[board]]"),
    (board_toml(181, ["a"]) + servo_toml("a", 1).replace("rest = 0", "rest = 200"),
     "servo 'a': 'rest' must be a whole number in its range 0..180, got 200"),
    (board_toml(181, ["a"]) + servo_toml("a", 1) + GLOVE.replace("id = 182", "id = 181"),
     "glove id must be a board ID in 181..247 that no other board has, got 181"),
    (board_toml(181, ["a"]) + servo_toml("a", 1) + GLOVE.replace("board = 181", "board = 9"),
     "glove 182: 'board' must be the ID of a servo board of the profile, got 9"),
    (board_toml(181, ["a"]) + servo_toml("a", 1) + GLOVE.replace('servo = "a"', 'servo = "b"'),
     "glove 182, sensor 1: 'servo' must be a servo of board 181, got 'b'"),
    (board_toml(181, ["a"]) + servo_toml("a", 1) + GLOVE.replace("[500, 700]", "[700, 500]"),
     "glove 182, sensor 1: 'calibration' must be [low, high] readings with 0 <= low < high "
     "<= 1023, got [700, 500]"),
    (board_toml(181, ["a"]) + servo_toml("a", 1) + GLOVE.replace("deadband = 2",
                                                                 "deadband = -1"),
     "glove 182: 'deadband' must be a whole number in 0..180, got -1"),
]


@pytest.mark.parametrize(("text", "message"), PROFILE_ERRORS)
def test_profile_errors_name_the_problem(text, message):
    with pytest.raises(GestError) as info:
        parse_profile(text, "bad.toml")
    first = info.value.diagnostics[0]
    assert first.message == message
    assert first.pos.file == "bad.toml"


def test_the_right_hand_has_the_original_glove(rhand):
    (glove,) = rhand.gloves
    assert (glove.id, glove.board, glove.baud) == (182, 181, 9600)
    assert [s.servo for s in glove.sensors] == ["thumb", "index", "middle", "ring", "pinky"]
    assert [s.pin for s in glove.sensors] == [14, 15, 16, 17, 18]  # A0..A4
    assert [s.calibration for s in glove.sensors] == [
        (579, 713), (519, 743), (588, 793), (610, 811), (591, 806)]


def test_toml_syntax_errors_have_a_line():
    with pytest.raises(GestError) as info:
        parse_profile('name = "x"\n[[board]\n', "bad.toml")
    assert info.value.first.pos.line == 2


def test_a_profile_with_several_boards_compiles_one_stream_per_board(two_boards):
    compiled = compile_source("g: r_index 90, l_index 45 over 0.5s", profile=two_boards)
    assert [(s.board, s.baud) for s in compiled.streams] == [(181, 9600), (183, 9600)]
    right, left = compiled.streams
    assert set(right.data[1::2]) == {1} and set(left.data[1::2]) == {4}


def test_groups_of_a_profile_are_usable():
    profile = parse_profile(
        board_toml(181, ["a", "b", "c"]) + servo_toml("a", 0) + servo_toml("b", 1)
        + servo_toml("c", 2) + '[groups]\npair = ["a", "c"]\n', "g.toml")
    assert compile_source("g: pair 90", profile=profile).final == (90, 0, 90)


def test_a_compile_records_the_profile_it_used(rhand):
    import hashlib
    compiled = compile_source("g: index 90", profile=rhand)
    with open(rhand.path, encoding="utf-8") as f:
        text = f.read()
    assert compiled.profile_sha256 == hashlib.sha256(text.encode()).hexdigest()


def test_every_profile_error_points_at_its_key():
    for text, message in PROFILE_ERRORS:
        with pytest.raises(GestError) as info:
            parse_profile(text, "bad.toml")
        first = info.value.first
        line = text.split("\n")[first.pos.line - 1]
        assert first.source_line == line, message
        if message.startswith("invalid TOML") or "at least one [[board]]" in message:
            continue
        assert first.pos.line > 1 or line.startswith("[[board]]"), message


SERVO = board_toml(181, ["a"]) + servo_toml("a", 1)

# the text, the message, the line the error is on (fuzzed profiles: issue 11)
TYPED_ERRORS = [
    (SERVO.replace("max_velocity = 400.0", "max_velocity = 1e-09"),
     "servo 'a': 'max_velocity' must be in 1..100,000, got 1e-09", "max_velocity = 1e-09"),
    (SERVO.replace("max_jerk = 160000.0", "max_jerk = inf"),
     "servo 'a': 'max_jerk' must be in 1..1,000,000,000, got inf", "max_jerk = inf"),
    (SERVO.replace("max_acceleration = 8000.0", "max_acceleration = nan"),
     "servo 'a': 'max_acceleration' must be greater than 0, got nan", "max_acceleration = nan"),
    (SERVO.replace("max_velocity = 400.0", 'max_velocity = "fast"'),
     "servo 'a': 'max_velocity' must be a number, got 'fast'", 'max_velocity = "fast"'),
    (SERVO.replace("baud = 9600", "baud = 1.5"),
     "board 181: 'baud' must be a whole number in 1..2,000,000, got 1.5", "baud = 1.5"),
    (SERVO.replace("id = 181", "id = true"),
     "board id must be a whole number in 181..247, got True", "id = true"),
    (SERVO.replace("id = 1\n", "id = 1.0\n"),
     "servo 'a': 'id' must be a whole number in 0..180, got 1.0", "id = 1.0"),
    (SERVO.replace('servos = ["a"]', 'servos = "a"'),
     "board 181: 'servos' must be a list of servo names", 'servos = "a"'),
    (SERVO + "reversed = 3\n", "servo 'a': 'reversed' must be true or false, got 3",
     "reversed = 3"),
    (SERVO + "pin = -1\n", "servo 'a': 'pin' must be a whole number in 0..255, got -1",
     "pin = -1"),
    ('board = 5\n' + servo_toml("a", 1), "a profile needs at least one [[board]]",
     "board = 5"),
    ("name = 5\n" + SERVO, "'name' must be a string, got 5", "name = 5"),
    (SERVO + '[groups]\nwait = ["a"]\n',
     "group 'wait': a group name must be a word (letters, digits, _) and not a keyword of "
     "the language", 'wait = ["a"]'),
    (SERVO + "[[glove]]\nid = 182\nboard = 181\nsensors = 1.5\n",
     "glove 182: 'sensors' must be a list of { servo = ..., pin = ..., calibration = "
     "[low, high] }", "sensors = 1.5"),
    (SERVO + "[[glove]]\nid = 182\nboard = 181\nsensors = [1]\n",
     "glove 182, sensor 1: expected { servo = ..., pin = ..., calibration = [low, high] }",
     "sensors = [1]"),
    (board_toml(181, ["a"]) + "[servo]\na = 3\n",
     "servo 'a': expected a [servo.a] table, got 3", "a = 3"),
    (SERVO + "x = " + "9" * 5000 + "\n", "invalid TOML: a number of thousands of digits",
     "x = " + "9" * 5000),
]


@pytest.mark.parametrize(("text", "message", "line"), TYPED_ERRORS)
def test_wrong_types_and_insane_limits_are_errors_at_their_key(text, message, line):
    with pytest.raises(GestError) as info:
        parse_profile(text, "bad.toml")
    first = info.value.first
    assert first.message == message
    assert first.source_line == line
    assert text.split("\n")[first.pos.line - 1] == line
    assert info.value.format().startswith(f"bad.toml:{first.pos.line}:")


def test_the_key_of_the_right_table_is_found():
    text = board_toml(181, ["a"]) + board_toml(183, ["b"], baud=1) + servo_toml("a", 1) \
        + servo_toml("b", 2, v=0)
    with pytest.raises(GestError) as info:
        parse_profile(text, "bad.toml")
    lines = text.split("\n")
    baud, velocity = info.value.diagnostics
    assert baud.pos.line == lines.index("baud = 1") + 1  # the second [[board]]'s
    assert velocity.pos.line == len(lines) - lines[::-1].index("max_velocity = 0")


def test_deep_nesting_in_toml_is_an_error():
    with pytest.raises(GestError) as info:
        parse_profile("x = " + "[" * 100_000 + "]" * 100_000 + "\n", "deep.toml")
    assert info.value.first.message == "invalid TOML: arrays or tables nested too deep"


def test_a_profile_that_is_not_utf8_is_an_error_at_the_byte(tmp_path):
    path = tmp_path / "latin.toml"
    path.write_bytes(b'name = "caf\xe9"\n' + SERVO.encode())
    with pytest.raises(GestError) as info:
        load_profile(str(path))
    assert info.value.format().splitlines()[0] == (
        f"{path}:1:12: error: this file is not UTF-8 text: invalid continuation byte "
        f"(byte 0xe9)")


def test_a_profile_too_large_is_not_read(tmp_path):
    from inmoov_dsl.profile import MAX_PROFILE
    path = tmp_path / "huge.toml"
    path.write_bytes(SERVO.encode() + b"#" * MAX_PROFILE)
    with pytest.raises(GestError, match="larger than 1,000,000 bytes: it is not read"):
        load_profile(str(path))
    with pytest.raises(GestError, match="longer than 1,000,000 characters"):
        parse_profile(SERVO + "#" * MAX_PROFILE)


def test_a_profile_is_checked_once_per_text(tmp_path):
    assert load_profile("rhand") is load_profile("rhand")
    path = tmp_path / "mine.toml"
    path.write_text(SERVO)
    first = load_profile(str(path))
    path.write_text(SERVO.replace("id = 1\n", "id = 7\n"))
    assert load_profile(str(path)).servos[0].id == 7 and first.servos[0].id == 1


def test_a_board_knows_where_it_is_defined(rhand):
    from pathlib import Path
    lines = Path(rhand.path).read_text(encoding="utf-8").split("\n")
    (board,) = rhand.boards
    assert lines[board.pos.line - 1] == "id = 181"
