"""What gestc reports per board and per warning: an idle board is said to be idle, and a
warning is told once per place in the source for a whole check."""

from pathlib import Path

from inmoov_dsl import measure
from inmoov_dsl.cli import gestc
from inmoov_dsl.compiling.compiler import compile_program
from inmoov_dsl.language.load import load

ROOT = Path(__file__).resolve().parent.parent
IDLE = "idle, none of its servos moves (it is sent CANCEL only)"


def run(capsys, *argv):
    code = gestc.main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def board_blocks(out):
    """gestc show's text per board: the block that starts with 'board N at'."""
    blocks = {}
    for block in out.split("\n\n"):
        if block.startswith("board "):
            block = block.rstrip("\n")
            blocks[int(block.split()[1])] = block
    return blocks


# -- idle boards ---------------------------------------------------------------------------
def test_show_says_a_board_the_gesture_does_not_move_is_idle(capsys):
    code, out, _ = run(capsys, "show", "hello", "--profile", "inmoov-six")
    assert code == 0
    blocks = board_blocks(out)
    assert sorted(blocks) == [181, 183, 184, 185, 186, 187]
    for board in (183, 185, 187):  # the left hand, the torso, the left arm: still
        assert blocks[board].endswith(f"servos: {IDLE}"), blocks[board]
        assert "link use" not in blocks[board] and "100%" not in blocks[board]
    for board in (181, 184, 186):  # the right hand, the head, the right arm
        assert "link use" in blocks[board] and IDLE not in blocks[board]


def test_show_of_a_gesture_that_moves_nothing_from_rest(capsys):
    # 'five' opens the hand: from the rest pose (open) no servo moves
    _, out, _ = run(capsys, "show", "five")
    assert out.rstrip().endswith(f"board 181 at 9600 baud, 6 servos: {IDLE}")


def test_compile_summary_lists_idle_boards_apart(capsys, tmp_path):
    out = tmp_path / "hello.gestc"
    code, _, err = run(capsys, "compile", "hello", "--profile", "inmoov-six", "-o", str(out))
    assert code == 0
    assert err == (f"wrote {out}: hello, 11.80 s, board 181: 1,029 bytes, board 184: "
                   f"117 bytes, board 186: 1,323 bytes; boards 183, 185, 187 idle\n")
    _, _, err = run(capsys, "compile", "five", "-o", str(tmp_path / "five.gestc"))
    assert err.endswith(": five, 0.60 s, board 181 idle\n")


def test_link_use_is_over_the_whole_gesture():
    program = load(str(ROOT / "gestures" / "body.gest"))
    compiled, plan = compile_program(program, "hello", "inmoov-six")
    reports = {r.board: r for r in measure(plan, compiled.streams)}
    assert [b for b, r in reports.items() if r.idle] == [183, 185, 187]
    for r in reports.values():
        assert r.idle == (r.values == 0)
        # a byte-time is about 1 ms: one CANCEL byte is no use of an 11.8 s gesture
        assert r.utilisation <= r.bytes * 1.1e-3 / plan.duration
    assert reports[183].utilisation < 0.001


# -- one warning per place -----------------------------------------------------------------
SLOW = """slow:
    index 180 over 0.01s
    index 0 over 0.01s

g:
    slow
    slow
    slow
"""


def warning_places(err):
    return [line.split(": warning:")[0] for line in err.splitlines() if ": warning:" in line]


def test_check_tells_a_place_once_whichever_gestures_play_it(capsys, tmp_path):
    w = tmp_path / "w.gest"
    w.write_text(SLOW)
    code, out, err = run(capsys, "check", str(w))
    assert code == 0 and out == f"{w}: ok (2 gestures, 2 warnings)\n"
    assert warning_places(err) == [f"{w}:2:20", f"{w}:3:18"]
    assert "move stretched: needs 0.52 s, asked 0.01 s" in err


def test_check_tells_a_place_once_across_files(capsys, tmp_path):
    (tmp_path / "slow.gest").write_text(SLOW.split("\n\n")[0] + "\n")
    a = tmp_path / "a.gest"
    b = tmp_path / "b.gest"
    a.write_text('use "slow.gest"\n\na:\n    slow\n    slow\n')
    b.write_text('use "slow.gest"\n\nb: slow\n')
    code, _, err = run(capsys, "check", str(a), str(b))
    assert code == 0
    slow = tmp_path / "slow.gest"
    assert warning_places(err) == [f"{slow}:2:20", f"{slow}:3:18"]


def test_distinct_warnings_at_distinct_places_are_all_told(capsys, tmp_path):
    w = tmp_path / "w.gest"
    w.write_text("a: index 180 over 0.01s\nb: middle 180 over 0.01s\n")
    _, _, err = run(capsys, "check", str(w))
    assert warning_places(err) == [f"{w}:1:19", f"{w}:2:20"]


def test_show_still_counts_the_times_a_place_is_played(capsys, tmp_path):
    w = tmp_path / "w.gest"
    w.write_text(SLOW)
    _, _, err = run(capsys, "show", str(w), "--gesture", "g")
    assert warning_places(err) == [f"{w}:2:20", f"{w}:3:18"]
    assert err.count("(3 times)") == 2


def test_strict_check_still_fails_on_a_stretch(capsys, tmp_path):
    w = tmp_path / "w.gest"
    w.write_text(SLOW)
    code, _, err = run(capsys, "check", "--strict", str(w))
    assert code == 1 and f"{w}:2:20: error: move stretched" in err


TWICE = """hello:
    index 90 over 1s
    indx 90 over 1s

hello:
    thumb 90 over 1s

pose p: index 9
pose p: index 10
group g: index, ring
group g: thumb

other:
    ring 300 over 1s
"""


def test_a_name_defined_twice_is_told_with_every_other_error(capsys, tmp_path):
    """A gesture, pose or group defined twice hid every other error of the file (in
    gestc check, the editor and the live preview): now each is told at its place."""
    file = tmp_path / "twice.gest"
    file.write_text(TWICE)
    code, out, err = run(capsys, "check", str(file))
    told = [line.split(": error: ")[1] for line in err.splitlines() if ": error: " in line]
    assert code == 1 and out == ""
    assert told == ["unknown servo or group 'indx'", "'hello' is defined twice",
                    "'p' is defined twice", "'g' is defined twice",
                    "value 300 is outside 0..180"]
    assert err.splitlines()[-1] == f"{file}: 5 errors"
    from inmoov_dsl.editor.analysis import analyse  # the editor's and the page's analysis

    found = analyse(TWICE, str(file))
    assert [d.message for d in found.diagnostics] == told
