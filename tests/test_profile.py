"""Robot profiles: the shipped right hand, and what a broken profile says."""

import pytest
from conftest import board_toml, servo_toml

from inmoov_dsl import compile_source, load_profile
from inmoov_dsl.errors import GestError
from inmoov_dsl.profiles.profile import builtin_profiles, parse_profile


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
    assert len(rhand.servos) == 6
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


@pytest.mark.parametrize(("text", "message"), PROFILE_ERRORS)
def test_every_profile_error_points_at_its_key(text, message):
    with pytest.raises(GestError) as info:
        parse_profile(text, "bad.toml")
    first = info.value.first
    line = text.split("\n")[first.pos.line - 1]
    assert first.source_line == line, message
    if not (message.startswith("invalid TOML") or "at least one [[board]]" in message):
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
    from inmoov_dsl.profiles.profile import MAX_PROFILE
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


# Every error at its key: one profile with every table, and for each kind of error one
# change to it, the message, where it is (line:column) and the text the caret is under.
HAND = """\
name = "test"
description = "a hand"

[[board]]
id = 181
name = "right"
baud = 9600
servos = ["a", "b"]

[servo.a]   # the first
id = 0
range = [0, 180]
rest = 0
max_velocity = 400
max_acceleration = 8000
max_jerk = 160000
calibration = [10, 170]
reversed = false
pin = 2

[servo.b]
id = 1
max_velocity = 400
max_acceleration = 8000
max_jerk = 160000

[[glove]]
id = 182
board = 181
command_pins = [10, 11]
deadband = 2
frame_ms = 20
sensors = [
    { servo = "a", pin = 14, calibration = [500, 700] },
    { servo = "b", pin = 15, calibration = [500, 700], reversed = true },
]

[groups]
pair = ["a", "b"]
"""


def test_the_hand_of_the_key_tests_is_a_good_profile():
    profile = parse_profile(HAND, "bad.toml")
    assert profile.names == ("a", "b") and profile.groups["pair"] == ("a", "b")
    assert [s.reversed for s in profile.gloves[0].sensors] == [False, True]


def changed(old, new):
    assert HAND.count(old) == 1, old
    return HAND.replace(old, new)


def first_error_at(text, message, where, under):
    """The first error of ``text`` is ``message`` at ``where`` (line:column), and the
    caret is under ``under``."""
    with pytest.raises(GestError) as info:
        parse_profile(text, "bad.toml")
    first = info.value.first
    assert first.format().splitlines()[0] == f"bad.toml:{where}: error: {message}"
    line, column = map(int, where.split(":"))
    assert text.split("\n")[line - 1] == first.source_line
    assert first.source_line[column - 1:].startswith(under)
    return first


TOP_ERRORS = {
    "wrong type of name": (changed('name = "test"', "name = 5"),
                           "'name' must be a string, got 5", "1:1", "name"),
    "wrong type of description": (changed('description = "a hand"', "description = []"),
                                  "'description' must be a string, got []", "2:1",
                                  "description"),
    "no board": ('name = "x"\n[servo.a]\nid = 0\n', "a profile needs at least one [[board]]",
                 "1:1", "name"),
    "board not an array of tables": ('name = "x"\n\nboard = 5\n',
                                     "a profile needs at least one [[board]]", "3:1", "board"),
    "servo not a table": ('servo = 3\n[[board]]\nid = 181\n', "[servo.NAME] tables expected",
                          "1:1", "servo"),
    "groups not a table": ('groups = 3\n' + HAND.replace('[groups]\npair = ["a", "b"]\n', ""),
                           "[groups] must map a group name to a list of servo names", "1:1",
                           "groups"),
    "gloves not tables": ('glove = [1]\n' + HAND[:HAND.index("[[glove]]")]
                          + HAND[HAND.index("[groups]"):],
                          "[[glove]] tables expected", "1:1", "glove"),
}

BOARD_ERRORS = {
    "id out of range": (changed("id = 181", "id = 12"),
                        "board id must be a whole number in 181..247, got 12", "5:1", "id"),
    "id of the wrong type": (changed("id = 181", 'id = "181"'),
                             "board id must be a whole number in 181..247, got '181'", "5:1",
                             "id"),
    "missing id": (changed("id = 181\n", ""),
                   "board id must be a whole number in 181..247, got None", "4:1",
                   "[[board]]"),
    "duplicate id": (changed("\n[servo.a]", '\n[[board]]\nid = 181\nservos = []\n[servo.a]'),
                     "board 181 is declared twice", "11:1", "id"),
    "not a table": (HAND[:HAND.index("[[board]]")] + "board = [5]\n"
                    + HAND[HAND.index("\n[servo.a]"):],
                    "board 1: expected a [[board]] table, got 5", "4:10", "5"),
    "baud of the wrong type": (changed("baud = 9600", "baud = 1.5"),
                               "board 181: 'baud' must be a whole number in 1..2,000,000, "
                               "got 1.5", "7:1", "baud"),
    "baud too slow": (changed("baud = 9600", "baud = 300"),
                      "board 181: baud 300 is too slow: not one servo command fits in a 20 "
                      "ms servo frame", "7:1", "baud"),
    "servos not a list": (changed('servos = ["a", "b"]', 'servos = "a"'),
                          "board 181: 'servos' must be a list of servo names", "8:1",
                          "servos"),
    "unknown servo": (changed('servos = ["a", "b"]', 'servos = ["a", "b", "c"]'),
                      "board 181 lists servo 'c' but there is no [servo.c]", "8:21", '"c"'),
    "servo listed twice": (changed('servos = ["a", "b"]', 'servos = ["a", "b", "a"]'),
                           "servo 'a' is on board 181 and board 181", "8:21", '"a"'),
    "servo on two boards": (changed("\n[servo.a]", '\n[[board]]\nid = 183\nservos = ["b"]\n'
                                    '[servo.a]'),
                            "servo 'b' is on board 181 and board 183", "12:11", '"b"'),
    "name of the wrong type": (changed('name = "right"', "name = 1"),
                               "board 181: 'name' must be a string, got 1", "6:1", "name"),
}

SERVO_ERRORS = {
    "id out of range": (changed("id = 0\n", "id = 300\n"),
                        "servo 'a': 'id' must be a whole number in 0..180, got 300", "11:1",
                        "id"),
    "missing id": (changed("id = 0\n", ""),
                   "servo 'a': 'id' must be a whole number in 0..180, got None", "10:1",
                   "[servo.a]"),
    "duplicate id": (changed("id = 1\n", "id = 0\n"),
                     "servo 'b': id 0 is already used by servo 'a'", "22:1", "id"),
    "range out of range": (changed("range = [0, 180]", "range = [0, 200]"),
                           "servo 'a': 'range' must be [low, high] with 0 <= low <= high <= "
                           "180, got [0, 200]", "12:1", "range"),
    "rest outside its range": (changed("range = [0, 180]\nrest = 0",
                                       "range = [10, 180]\nrest = 0"),
                               "servo 'a': 'rest' must be a whole number in its range "
                               "10..180, got 0", "13:1", "rest"),
    "missing limit": (changed("id = 1\nmax_velocity = 400\n", "id = 1\n"),
                      "servo 'b': missing 'max_velocity'", "21:1", "[servo.b]"),
    "limit of the wrong type": (changed("max_jerk = 160000\ncal", "max_jerk = true\ncal"),
                                "servo 'a': 'max_jerk' must be a number, got True", "16:1",
                                "max_jerk"),
    "limit not above 0": (changed("max_acceleration = 8000\nmax_jerk = 160000\ncal",
                                  "max_acceleration = 0\nmax_jerk = 160000\ncal"),
                          "servo 'a': 'max_acceleration' must be greater than 0, got 0",
                          "15:1", "max_acceleration"),
    "limit out of range": (changed("max_velocity = 400\nmax_acceleration = 8000\nmax_jerk = "
                                   "160000\ncal", "max_velocity = 1e6\nmax_acceleration = "
                                   "8000\nmax_jerk = 160000\ncal"),
                           "servo 'a': 'max_velocity' must be in 1..100,000, got 1000000.0",
                           "14:1", "max_velocity"),
    "calibration out of range": (changed("calibration = [10, 170]", "calibration = [170, 10]"),
                                 "servo 'a': 'calibration' must be [low, high] with 0 <= low "
                                 "<= high <= 180, got [170, 10]", "17:1", "calibration"),
    "reversed of the wrong type": (changed("reversed = false", 'reversed = "no"'),
                                   "servo 'a': 'reversed' must be true or false, got 'no'",
                                   "18:1", "reversed"),
    "pin out of range": (changed("pin = 2", "pin = 256"),
                         "servo 'a': 'pin' must be a whole number in 0..255, got 256", "19:1",
                         "pin"),
    "a keyword as a name": (HAND.replace('"b"]', '"wait"]', 1).replace("[servo.b]",
                                                                      "[servo.wait]"),
                            "servo 'wait': a servo name must be a word (letters, digits, _) "
                            "and not a keyword of the language", "21:1", "[servo.wait]"),
    "not a table": (board_toml(181, ["a"]) + "\n[servo]\na = 3\n",
                    "servo 'a': expected a [servo.a] table, got 3", "7:1", "a"),
    "on no board": (changed("\n[[glove]]", "[servo.c]\nid = 9\n\n[[glove]]"),
                    "servo 'c' is on no board", "26:1", "[servo.c]"),
}

GROUP_ERRORS = {
    "not a list": (changed('pair = ["a", "b"]', 'pair = "a"'),
                   "group 'pair' must be a list of servo names", "39:1", "pair"),
    "unknown servo": (changed('pair = ["a", "b"]', 'pair = ["a", "z"]'),
                      "group 'pair' names unknown servo 'z'", "39:14", '"z"'),
    "a servo's name": (changed('pair = ["a", "b"]', 'a = ["b"]'),
                       "group 'a' has the name of a servo", "39:1", "a"),
    "a keyword as a name": (changed('pair = ["a", "b"]', 'wait = ["b"]'),
                            "group 'wait': a group name must be a word (letters, digits, _) "
                            "and not a keyword of the language", "39:1", "wait"),
}

GLOVE_ERRORS = {
    "id of a board": (changed("id = 182", "id = 181"),
                      "glove id must be a board ID in 181..247 that no other board has, "
                      "got 181", "28:1", "id"),
    "missing id": (changed("id = 182\n", ""),
                   "glove id must be a board ID in 181..247 that no other board has, "
                   "got None", "27:1", "[[glove]]"),
    "unknown board": (changed("board = 181", "board = 183"),
                      "glove 182: 'board' must be the ID of a servo board of the profile, "
                      "got 183", "29:1", "board"),
    "command pins": (changed("command_pins = [10, 11]", "command_pins = [10]"),
                     "glove 182: 'command_pins' must be [rx, tx], got [10]", "30:1",
                     "command_pins"),
    "deadband out of range": (changed("deadband = 2", "deadband = 200"),
                              "glove 182: 'deadband' must be a whole number in 0..180, got "
                              "200", "31:1", "deadband"),
    "frame of the wrong type": (changed("frame_ms = 20", "frame_ms = 20.0"),
                                "glove 182: 'frame_ms' must be a whole number in 1..1000, got "
                                "20.0", "32:1", "frame_ms"),
    "baud too slow": (changed("frame_ms = 20", "frame_ms = 20\nbaud = 100"),
                      "glove 182: 'baud' must be a whole number in 300..2000000, got 100",
                      "33:1", "baud"),
    "name of the wrong type": (changed("board = 181", "board = 181\nname = false"),
                               "glove 182: 'name' must be a string, got False", "30:1",
                               "name"),
    "sensors not a list": (HAND[:HAND.index("sensors = [")] + "sensors = 1"
                           + HAND[HAND.index("\n\n[groups]"):],
                           "glove 182: 'sensors' must be a list of { servo = ..., pin = ..., "
                           "calibration = [low, high] }", "33:1", "sensors"),
    "no sensor": (HAND.replace(HAND[HAND.index("sensors = ["):HAND.index("\n\n[groups]")],
                               "sensors = []"),
                  "glove 182: a glove needs at least one sensor", "33:1", "sensors"),
}

SENSOR_ERRORS = {
    "not a table": (changed('{ servo = "b", pin = 15, calibration = [500, 700], reversed = '
                            'true }', "[1]"),
                    "glove 182, sensor 2: expected { servo = ..., pin = ..., calibration = "
                    "[low, high] }", "35:5", "[1]"),
    "unknown servo": (changed('servo = "a"', 'servo = "aa"'),
                      "glove 182, sensor 1: 'servo' must be a servo of board 181, got 'aa'",
                      "34:7", "servo"),
    "missing servo": (changed('servo = "a", ', ""),
                      "glove 182, sensor 1: 'servo' must be a servo of board 181, got None",
                      "34:5", "{"),
    "calibration": (changed("pin = 15, calibration = [500, 700]",
                            "pin = 15, calibration = [700, 500]"),
                    "glove 182, sensor 2: 'calibration' must be [low, high] readings with 0 "
                    "<= low < high <= 1023, got [700, 500]", "35:30", "calibration"),
    "pin out of range": (changed("pin = 14", "pin = -1"),
                         "glove 182, sensor 1: 'pin' must be a whole number in 0..255, got -1",
                         "34:20", "pin"),
    "reversed of the wrong type": (changed("reversed = true", "reversed = 1"),
                                   "glove 182, sensor 2: 'reversed' must be true or false, "
                                   "got 1", "35:56", "reversed"),
}


ERRORS_BY_TABLE = {"top": TOP_ERRORS, "board": BOARD_ERRORS, "servo": SERVO_ERRORS,
                   "group": GROUP_ERRORS, "glove": GLOVE_ERRORS, "sensor": SENSOR_ERRORS}
ERRORS = {f"{table}: {case}": error for table, cases in ERRORS_BY_TABLE.items()
          for case, error in cases.items()}


@pytest.mark.parametrize(("text", "message", "where", "under"), ERRORS.values(), ids=ERRORS)
def test_every_tables_errors_are_at_their_key(text, message, where, under):
    first_error_at(text, message, where, under)


def test_hints_are_kept_with_the_errors_at_their_key():
    slow = first_error_at(*BOARD_ERRORS["baud too slow"])
    assert slow.hint == "use 9600 or more"
    missing = first_error_at(*SERVO_ERRORS["missing limit"])
    assert missing.hint == "add max_velocity = N, in command degrees per second"
    typo = changed('servos = ["a", "b"]', 'servos = ["a", "bb"]')
    assert first_error_at(typo, "board 181 lists servo 'bb' but there is no [servo.bb]",
                          "8:16", '"bb"').hint == "did you mean 'b'?"


def test_the_caret_underlines_the_key():
    error = first_error_at(*SERVO_ERRORS["limit out of range"])
    assert error.format().splitlines()[1:3] == ["    max_velocity = 1e6", "    ^" + "~" * 11]


def test_all_the_errors_are_reported_each_at_its_key():
    text = changed("baud = 9600", "baud = 1").replace("pin = 2", "pin = -2") \
        .replace("deadband = 2", "deadband = -2")
    with pytest.raises(GestError) as info:
        parse_profile(text, "bad.toml")
    assert [(d.pos.line, d.pos.column, d.message.split(":")[0])
            for d in info.value.diagnostics] == [
        (7, 1, "board 181"), (19, 1, "servo 'a'"), (31, 1, "glove 182")]



# A misspelt key is an error at it with the key meant, never a silent default (fuzzed
# profiles): the text, the message, where, the text under the caret, the hint
UNKNOWN_KEYS = {
    "a servo's": (changed("reversed = false", "revresed = false"),
                  "servo 'a': unknown key 'revresed'", "18:1", "revresed",
                  "did you mean 'reversed'?"),
    "a table's name": (HAND + "[colision]\nclearance_mm = 0\n", "unknown table 'colision'",
                       "40:1", "[colision]", "did you mean 'collision'?"),
    "a table's plural": (HAND + "[collisions]\nclearance_mm = 0\n",
                         "unknown table 'collisions'", "40:1", "[collisions]",
                         "did you mean 'collision'?"),
    "at the top": ("foo = 1\n" + HAND, "unknown key 'foo'", "1:1", "foo",
                   "a profile holds: name, description, board, servo, groups, sides, glove, "
                   "voice, collision, place"),
    "an array of tables": (HAND + "[[servos]]\nid = 3\n", "unknown table 'servos'", "40:1",
                           "[[servos]]", "did you mean 'servo'?"),
    "in [collision]": (HAND + "[collision]\nclearance = 5\n",
                       "[collision]: unknown key 'clearance'", "41:1", "clearance",
                       "did you mean 'clearance_mm'?"),
    "a board's": (changed("baud = 9600", "buad = 9600"), "board 181: unknown key 'buad'",
                  "7:1", "buad", "did you mean 'baud'?"),
    "a board's with no id": (changed("id = 181\n", "buad = 9600\n"),
                             "board 1: unknown key 'buad'", "5:1", "buad",
                             "did you mean 'baud'?"),
    "another kind's": (changed('name = "right"', 'model = "mini12"'),
                       "board 181: unknown key 'model'", "6:1", "model",
                       "only a board of kind maestro takes 'model'; this one's kind is rig"),
    "its kind's": (changed('name = "right"', 'kind = "maestro"\nmodle = "mini12"'),
                   "board 181: unknown key 'modle'", "7:1", "modle", "did you mean 'model'?"),
    "a glove's": (changed("deadband = 2", "deadbnad = 2"), "glove 182: unknown key 'deadbnad'",
                  "31:1", "deadbnad", "did you mean 'deadband'?"),
    "a sensor's": (changed("pin = 14", "pni = 14"), "glove 182, sensor 1: unknown key 'pni'",
                   "34:20", "pni", "did you mean 'pin'?"),
    "in [voice]": (HAND + '[voice]\nmouth = "a"\nclsoed = 0\n',
                   "[voice]: unknown key 'clsoed'", "42:1", "clsoed", "did you mean 'closed'?"),
    "in [sides]": (HAND + '[sides]\nright = ["a"]\nleft = ["b"]\nlfet = []\n',
                   "[sides]: unknown key 'lfet'", "43:1", "lfet", "did you mean 'left'?"),
    "with nothing close": (changed("reversed = false", "colour = 3"),
                           "servo 'a': unknown key 'colour'", "18:1", "colour",
                           "the keys it takes: id, range, rest, pin, reversed, max_velocity, "
                           "max_acceleration, max_jerk, calibration, joint, pulse"),
}


@pytest.mark.parametrize(("text", "message", "where", "under", "hint"), UNKNOWN_KEYS.values(),
                         ids=UNKNOWN_KEYS)
def test_an_unknown_key_is_an_error_at_it_with_the_key_meant(text, message, where, under,
                                                             hint):
    assert first_error_at(text, message, where, under).hint == hint


def test_every_key_a_table_reads_is_one_it_takes():
    """The keys of every table, each written once: the profile that has them all loads
    (pulse and a kind's own keys included)."""
    text = changed("pin = 2", "pin = 2\njoint = \"j\"\npulse = [1000, 2000]") \
        .replace('name = "right"', 'kind = "rig"\narduino = "uno"', 1) \
        + '[sides]\nright = ["a"]\nleft = ["b"]\n[voice]\nmouth = "a"\nclosed = 0\n' \
        'open = 90\nvoice = "en"\nspeed = 150\npitch = 40\n[collision]\nclearance_mm = 5\n'
    profile = parse_profile(text, "all.toml")
    assert profile.servos[0].pulse == (1000, 2000) and profile.voice.pitch == 40
    assert profile.clearance_mm == 5 and profile.sides["left"] == ("b",)


def test_gestc_check_refuses_a_profile_with_a_misspelt_key(tmp_path, capsys):
    """The fuzzer's four profiles: each loaded with exit 0 before; now each is an error
    at its key, with the key meant."""
    from pathlib import Path

    from inmoov_dsl.cli import gestc

    rhand = Path(load_profile("rhand").path).read_text(encoding="utf-8")
    gesture = tmp_path / "curl.gest"
    gesture.write_text("curl: index 90\n")
    bad = {"revresed": rhand.replace("reversed = true", "revresed = true", 1),
           "colision": rhand + "\n[colision]\nclearance_mm = 0\n",
           "collisions": rhand + "\n[collisions]\nclearance_mm = 0\n",
           "foo": "foo = 1\n" + rhand}
    for key, text in bad.items():
        path = tmp_path / f"{key}.toml"
        path.write_text(text)
        assert gestc.main(["check", "--profile", str(path), str(gesture)]) == 1, key
        err = capsys.readouterr().err
        line = next(n for n, row in enumerate(text.split("\n"), 1)
                    if row.startswith((key, f"[{key}]")))
        assert f"{path}:{line}:1: error: " in err and "unknown " in err, err
        assert ("hint: did you mean" in err) == (key != "foo"), err


# TOML's other ways of writing the same tables: the key is found in each
KEY_LAYOUTS = {
    "dotted keys": ('[[board]]\nid = 181\nservos = ["a"]\n[servo]\na.id = 0\n'
                    'a.max_velocity = 1\na.max_acceleration = 1\na.max_jerk = -1\n',
                    "servo 'a': 'max_jerk' must be greater than 0, got -1", "8:1", "a.max_jerk"),
    "an inline table": ('[[board]]\nid = 181\nservos = ["a"]\n[servo]\na = { id = 0, '
                        'max_velocity = 1, max_acceleration = 1, max_jerk = 1, rest = 300 }\n',
                        "servo 'a': 'rest' must be a whole number in its range 0..180, got 300",
                        "5:69", "rest"),
    "quoted keys and spaces": ('[[ board ]]\n"id" = 181\nservos = [ "a" ]\n[ servo . "a" ]\n'
                               "  'id'   =  400\n",
                               "servo 'a': 'id' must be a whole number in 0..180, got 400",
                               "5:3", "'id'"),
    "a string that looks like tables": ('description = """\n[[board]]\nid = 5\n"""\n'
                                        '[[board]]\nid = 5\n',
                                        "board id must be a whole number in 181..247, got 5",
                                        "6:1", "id"),
    "comments with brackets": ('[[board]]  # [[board]] ]\nid = 181  # id = 1 ]\nservos = [ # [\n'
                               '  "a", # "b" }\n  "c",\n]\n[servo.a]\nid = 0\nmax_velocity = 1\n'
                               'max_acceleration = 1\nmax_jerk = 1\n',
                               "board 181 lists servo 'c' but there is no [servo.c]", "5:3",
                               '"c"'),
    "CRLF line ends": (HAND.replace("\n", "\r\n").replace("pin = 2", "pin = 2.5"),
                       "servo 'a': 'pin' must be a whole number in 0..255, got 2.5", "19:1",
                       "pin"),
}


@pytest.mark.parametrize(("text", "message", "where", "under"), KEY_LAYOUTS.values(),
                         ids=KEY_LAYOUTS)
def test_keys_are_found_however_the_toml_writes_them(text, message, where, under):
    first_error_at(text, message, where, under)


def walk(value, path=()):
    """Every key and array element of TOML data, by path, with its value."""
    if isinstance(value, dict):
        for key, item in value.items():
            yield (*path, key), item
            yield from walk(item, (*path, key))
    elif isinstance(value, list):
        for n, item in enumerate(value):
            yield (*path, n), item
            yield from walk(item, (*path, n))


def test_every_key_and_item_of_the_built_in_profiles_is_found_where_it_is():
    import tomllib

    from inmoov_dsl.profiles.keys import KeyIndex
    from inmoov_dsl.profiles.profile import find_profile

    names = builtin_profiles()
    assert {"rhand", "lhand", "inmoov"} <= set(names)
    for name in names:
        text = find_profile(name).read_text(encoding="utf-8")
        index = KeyIndex(text, name)
        found = list(walk(tomllib.loads(text)))
        assert ("board", 0, "id") in dict(found)  # into the arrays of tables too
        for path, value in found:
            pos, line = index.find(path)
            there = line[pos.column - 1:]
            if isinstance(path[-1], str):  # the key, or the (first) header of its table
                assert there.startswith(path[-1]) or there.startswith("[") and \
                    path[-1] in there.split("]")[0], path
            elif isinstance(value, dict | list):  # a [[table]]'s header, or [ or {
                assert there[0] in "[{", path
            else:
                assert there.startswith(str(value) if isinstance(value, int)
                                        else f'"{value}"'), path


def test_the_inmoov_is_two_megas_on_the_pins_myrobotlab_gives_it():
    inmoov = load_profile("inmoov")
    assert [(b.name, b.baud, b.kind, len(b.servos)) for b in inmoov.boards] == \
        [("right", 115200, "rig", 10), ("left", 115200, "rig", 18)]
    pin = {s.name: s.pin for s in inmoov.servos}
    assert [pin[n] for n in ("r_thumb", "r_index", "r_middle", "r_ring", "r_pinky",
                             "r_wrist", "r_bicep", "r_rotate", "r_shoulder",
                             "r_omoplate")] == list(range(2, 12))
    assert [pin[n] for n in ("neck", "rothead", "eye_x", "eye_y", "jaw", "top_stom",
                             "mid_stom", "low_stom")] == [12, 13, 22, 24, 26, 27, 28, 29]
    # the same robot, whatever carries it: every servo as in the six-board layout but
    # its pin, and the same on MrlComm
    for other in ("inmoov-six", "inmoov-mrlcomm"):
        them = load_profile(other)
        assert sorted(s.name for s in them.servos) == sorted(s.name for s in inmoov.servos)
        for mine in inmoov.servos:
            theirs = them.servos[them.index(mine.name)]
            assert mine == theirs.__class__(**{**theirs.__dict__, "pin": mine.pin,
                                               "board": mine.board})
    assert {b.kind for b in load_profile("inmoov-mrlcomm").boards} == {"mrlcomm"}


@pytest.mark.parametrize(("board", "pin", "message"), [
    ("", 26, "servo 'index' of board 181: pin 26 cannot drive a servo: an Arduino Uno has "
             "pins 2..19"),
    ('arduino = "mega"\n', 1, "servo 'index' of board 181: pin 1 cannot drive a servo: "
                              "pins 0 and 1 are the board's serial port"),
    ('arduino = "mega"\n', 70, "an Arduino Mega has pins 2..69"),
    ('arduino = "mgea"\n', 4, "'arduino' must be one of uno, nano, mega, got 'mgea'"),
])
def test_a_servo_is_on_a_pin_its_arduino_has(board, pin, message):
    text = (f'[[board]]\nid = 181\n{board}servos = ["index"]\n'
            f"[servo.index]\nid = 2\npin = {pin}\nmax_velocity = 400\n"
            "max_acceleration = 8000\nmax_jerk = 160000\n")
    with pytest.raises(GestError) as info:
        parse_profile(text, "p.toml")
    assert message in info.value.first.message
    if pin == 26:
        assert info.value.first.hint == 'on a Mega? say arduino = "mega" in its [[board]]'
    assert parse_profile(text.replace(f"pin = {pin}", "pin = 9"), "p.toml") \
        if "mgea" not in board else True
