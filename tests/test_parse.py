"""The language's syntax: what parses, and what each syntax error says and where."""

import pytest

from inmoov_dsl import syntax as ast
from inmoov_dsl.errors import GestError
from inmoov_dsl.parse import parse, parser


def test_the_calling_card_parses_exactly_as_written():
    module = parse("peace: index 180, middle 180 over 0.4s", "card.gest")
    (gesture,) = module.items
    assert isinstance(gesture, ast.GestureDef)
    assert gesture.name.text == "peace"
    (move,) = gesture.steps
    assert [(t.name.text, t.value) for t in move.targets] == [("index", 180), ("middle", 180)]
    assert move.over.seconds == pytest.approx(0.4)
    assert move.stagger is None
    assert (move.over.pos.line, move.over.pos.column) == (1, 35)


def test_every_construct_of_a_file():
    text = (
        "# a comment line\n"
        'use "other.gest"\n'
        "group pair: index, middle\n"
        "pose fist: fingers 180   # inline comment\n"
        "\n"
        "count:\n"
        "    thumb 180, index 0\n"
        "    wait 500ms\n"
        "    hold 1 s\n"
        "    pair 90 over 300ms stagger 50ms\n"
        "    repeat 2:\n"
        "        index 90\n"
        "\n"
        "        # a comment inside a block\n"
        "        index 0\n"
        "    repeat 3: fist\n"
        "    fist, thumb 0\n"
    )
    items = parse(text, "f.gest").items
    use, group, pose, count = items
    assert use.path == "other.gest"
    assert [m.text for m in group.members] == ["index", "middle"]
    assert pose.targets[0].value == 180
    steps = count.steps
    assert [type(s).__name__ for s in steps] == ["Move", "Wait", "Wait", "Move", "Repeat",
                                                 "Repeat", "Move"]
    assert steps[1].duration.seconds == pytest.approx(0.5)
    assert steps[2].duration.seconds == pytest.approx(1.0)
    assert steps[3].over.seconds == pytest.approx(0.3)
    assert steps[3].stagger.seconds == pytest.approx(0.05)
    assert steps[4].count == 2 and len(steps[4].body) == 2
    assert steps[5].count == 3 and steps[5].body[0].targets[0].name.text == "fist"
    assert [t.name.text for t in steps[6].targets] == ["fist", "thumb"]


def test_windows_line_ends_and_no_final_newline():
    module = parse("a:\r\n    index 90\r\n    index 0", "w.gest")
    assert len(module.items[0].steps) == 2


def test_the_parser_is_built_once():
    assert parser() is parser()


# source, the error's first line, the caret line
ERRORS = [
    ("peace index 180",
     "e.gest:1:7: error: unexpected name 'index'; expected ':'", "          ^~~~~"),
    ("p: index 90 middle 90",
     "e.gest:1:13: error: unexpected name 'middle'; expected ',', 'over', 'stagger' or the "
     "end of the line", "                ^~~~~~"),
    ("p: index 200", "e.gest:1:10: error: value 200 is outside 0..180", "             ^~~"),
    ("p: index -5", "e.gest:1:10: error: value -5 is outside 0..180", "             ^~"),
    ("p: index 90.5", "e.gest:1:10: error: values are whole degrees, got 90.5",
     "             ^~~~"),
    ("p: index 90 over 3", "e.gest:1:18: error: the duration 3 needs a unit",
     "                     ^"),
    ("p: index 90 over 3sec", "e.gest:1:19: error: unknown unit 'sec'",
     "                      ^~~"),
    ("p: index 90 over 0s", "e.gest:1:18: error: a duration must be greater than 0, got 0s",
     "                     ^~"),
    ("p: wait 9999s", "e.gest:1:9: error: duration 9999s is too long (at most 600 s per step)",
     "            ^~~~~"),
    ("p: repeat 0: index 9",
     "e.gest:1:11: error: repeat count must be a whole number from 1 to 1000, got 0",
     "              ^"),
    ("p: repeat 5000: index 9",
     "e.gest:1:11: error: repeat count must be a whole number from 1 to 1000, got 5000",
     "              ^~~~"),
    ("p: index @", "e.gest:1:10: error: unexpected character '@'", "             ^"),
    ("p: index 9 over 1s over 2s", "e.gest:1:25: error: 'over' is given twice in this step",
     "                            ^~"),
    ("p: index 90 over", "e.gest:1:17: error: unexpected end of line; expected a number",
     "                    ^"),
    ("p:\nindex 9", "e.gest:2:1: error: unexpected name 'index'; expected an indented line",
     "    ^~~~~"),
    ("p:\n    index 90\n  middle 9",
     "e.gest:3:3: error: this line's indentation matches no enclosing block", "      ^"),
    ("p:\n  index 90\n\n  # c\n    middle 9",
     "e.gest:5:5: error: unexpected indentation; expected 'hold', a name, 'repeat', 'wait' "
     "or the end of the indented block", "        ^"),
]


@pytest.mark.parametrize(("source", "first", "caret"), ERRORS)
def test_syntax_errors_say_what_and_where(source, first, caret):
    with pytest.raises(GestError) as info:
        parse(source, "e.gest")
    lines = info.value.format().splitlines()
    assert lines[0] == first
    assert lines[2] == caret
    # the offending line is shown above the caret
    line_no = int(first.split(":")[1])
    assert lines[1] == "    " + source.splitlines()[line_no - 1]


@pytest.mark.parametrize(("source", "hint"), [
    ("peace index 180", "a gesture starts with its name and ':', as in  peace: index 180"),
    ("p: index 90 middle 90", "separate the servos of a step with ',': index 90, middle 90"),
    ("p: index 90.5", "use 90 or 91"),
    ("p: index 90 over 3", "write 3s or 3ms"),
    ("p: index 90 over 3sec", "use s or ms, as in 3s or 3ms"),
])
def test_syntax_errors_suggest_a_fix(source, hint):
    with pytest.raises(GestError) as info:
        parse(source, "e.gest")
    assert info.value.format().splitlines()[-1] == f"  hint: {hint}"
