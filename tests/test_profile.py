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
