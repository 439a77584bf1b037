"""gestc and gestplay as a user meets them: outputs, messages, exit codes, no tracebacks."""

import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import pytest_lsp
from lsprotocol import types as lsp
from pytest_lsp import ClientServerConfig, LanguageClient, client_capabilities

from inmoov_dsl import compile_file, from_json, to_json
from inmoov_dsl.cli import gestc
from inmoov_dsl.editor.analysis import analyse

ROOT = Path(__file__).resolve().parent.parent
COUNT = str(ROOT / "gestures" / "count.gest")


def run(capsys, *argv):
    code = gestc.main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def write(tmp_path, name, text):
    path = tmp_path / name
    path.write_text(text)
    return str(path)


def test_compile_writes_a_file_the_player_can_load(capsys, tmp_path):
    out = tmp_path / "count.gestc"
    code, _, err = run(capsys, "compile", COUNT, "-o", str(out))
    assert code == 0
    assert err.startswith(f"wrote {out}: count, 5.00 s, board 181: ")
    compiled = from_json(out.read_text())
    assert compiled.gesture == "count" and compiled.profile == "rhand"
    assert compiled.final == (0, 0, 0, 0, 0, 0)
    assert compiled.streams[0].data[0] == 255
    assert compiled.sources[0][0] == COUNT and len(compiled.sources[0][1]) == 64


def test_compile_default_output_is_named_after_the_gesture(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert run(capsys, "compile", "peace")[0] == 0
    assert from_json((tmp_path / "peace.gestc").read_text()).gesture == "peace"


def test_timed_format_on_stdout(capsys):
    code, out, _ = run(capsys, "compile", COUNT, "--format", "timed", "-o", "-")
    assert code == 0
    lines = out.splitlines()
    assert lines[0] == "0.000000 255"
    stream = compile_file(COUNT).stream()
    assert [int(line.split(" ")[1]) for line in lines] == list(stream.data)
    assert [float(line.split(" ")[0]) for line in lines] == pytest.approx(
        stream.times.tolist(), abs=5e-7)


def test_the_card_warns_and_strict_fails(capsys, tmp_path):
    card = write(tmp_path, "card.gest", "peace: index 180, middle 180 over 0.4s\n")
    code, _, err = run(capsys, "compile", card, "-o", "-")
    assert code == 0
    assert f"{card}:1:35: warning: move stretched: needs 0.60 s, asked 0.40 s" in err
    code, out, err = run(capsys, "compile", card, "--strict", "-o", "-")
    assert code == 1 and out == ""
    assert f"{card}:1:35: error: move stretched: needs 0.60 s, asked 0.40 s" in err


def test_strict_fails_where_the_link_cannot_keep_up(capsys, tmp_path):
    twelve = str(ROOT / "tests" / "data" / "twelve.toml")
    sweep = write(tmp_path, "sweep.gest", "# all at once\nsweep: " +
                  ", ".join(f"s{i} 180" for i in range(12)) + "\n")
    code, out, _ = run(capsys, "check", sweep, "--profile", twelve)
    assert code == 0 and out == f"{sweep}: ok (1 gesture)\n"
    for command in (["check"], ["compile", "-o", "-"]):
        code, out, err = run(capsys, *command, sweep, "--profile", twelve, "--strict")
        assert code == 1 and out == ""
        assert err.startswith(f"{sweep}:2:1: error: gesture 'sweep': the link to board 181 "
                              "carries 82.6% of the values the plan needs (228 of 276 "
                              "servo-frames at 9600 baud)\n    sweep: s0 180")
    slow = write(tmp_path, "slow.gest", "slow: " + ", ".join(f"s{i} 180" for i in range(3))
                 + "\n")
    assert run(capsys, "check", slow, "--profile", twelve, "--strict")[0] == 0


def test_check_reports_every_file(capsys, tmp_path):
    good = write(tmp_path, "good.gest", "a: index 90\nb: index 0\n")
    bad = write(tmp_path, "bad.gest", "a: indx 90\n")
    code, out, err = run(capsys, "check", good, bad)
    assert code == 1
    assert out == f"{good}: ok (2 gestures)\n"
    code, out, _ = run(capsys, "check", COUNT)
    assert code == 0 and out == f"{COUNT}: ok (1 gesture)\n"
    assert err.splitlines() == [f"{bad}:1:4: error: unknown servo or group 'indx'",
                                "    a: indx 90", "       ^~~~", "  hint: did you mean 'index'?",
                                f"{bad}: 1 error"]  # the file's count, after its report


def test_show_tables_steps_and_link(capsys):
    code, out, _ = run(capsys, "show", COUNT)
    assert code == 0
    assert out.startswith("count: 5.000 s on profile 'rhand'")
    assert "board 181 at 9600 baud, 6 servos" in out
    assert "coverage     100.0%" in out
    steps = [line for line in out.splitlines() if line.strip()[:1].isdigit()]
    assert len(steps) == 9
    assert steps[0].split()[1:4] == ["count", "count.gest:4", "move"]
    assert "hold" in steps[1] and "0.500   0.500" in steps[1]


def test_show_marks_a_stretched_step(capsys, tmp_path):
    card = write(tmp_path, "card.gest", "peace: index 180, middle 180 over 0.4s\n")
    code, out, _ = run(capsys, "show", card)
    assert code == 0 and "  0.400   0.600  stretched" in out


def test_show_says_when_the_link_is_the_bottleneck(capsys, tmp_path):
    names = [f"s{i}" for i in range(14)]
    profile = "".join(
        [f'[[board]]\nid = 181\nbaud = 9600\nservos = {names!r}\n'.replace("'", '"')]
        + [f"[servo.{n}]\nid = {i}\nmax_velocity = 400\nmax_acceleration = 8000\n"
           f"max_jerk = 160000\n" for i, n in enumerate(names)])
    prof = write(tmp_path, "crowd.toml", profile)
    gest = write(tmp_path, "all.gest", "g: " + ", ".join(f"{n} 180" for n in names) + "\n")
    code, out, _ = run(capsys, "show", gest, "--profile", prof)
    assert code == 0
    assert "the link is the bottleneck" in out


def test_list_prints_name_tab_file(capsys):
    code, out, _ = run(capsys, "list")
    assert code == 0
    rows = {name: rest for name, *rest in (line.split("\t") for line in out.splitlines())}
    assert Path(rows["count"][0]).name == "count.gest"
    assert rows["peace"][1] == "rhand" and rows["hello"][1] == "inmoov"  # the profile it needs


def test_from_a_pose(capsys, tmp_path):
    out = tmp_path / "o.gestc"
    code, _, _ = run(capsys, "compile", "peace", "--from", "fingers 90", "-o", str(out))
    assert code == 0
    assert from_json(out.read_text()).start == (0, 90, 90, 90, 90, 90)


@pytest.mark.parametrize(("argv", "message"), [
    (["compile", "nosuch.gest"], "gestc: error: cannot find 'nosuch.gest'"),
    (["compile", "pece"], "gestc: error: no file or library gesture 'pece'\n"
                          "  hint: did you mean 'peace'?"),
    (["compile", COUNT, "--profile", "lefthand"], "gestc: error: unknown profile 'lefthand'"),
    (["compile", COUNT, "--gesture", "cont"], f"gestc: error: no gesture 'cont' in {COUNT}\n"
                                              "  hint: did you mean 'count'?"),
    (["compile", COUNT, "--from", "indx 9"], "--from:1:1: error: unknown servo or group "
                                             "'indx'\n    indx 9\n    ^~~~"),
    (["compile", COUNT, "--from", "index 0\nfoo: index 1"],
     "gestc: error: --from takes one line: a pose name or targets"),
    (["compile", COUNT, "-o", "/nonexistent/dir/x.gestc"],
     "gestc: error: cannot use '/nonexistent/dir/x.gestc': No such file or directory"),
])
def test_bad_input_is_one_clear_message(capsys, argv, message):
    code, out, err = run(capsys, *argv)
    assert code == 1
    assert err.startswith(message)
    assert "Traceback" not in err


def test_a_file_with_several_gestures_needs_a_choice(capsys, tmp_path):
    two = write(tmp_path, "two.gest", "a: index 9\nb: index 8\n")
    code, _, err = run(capsys, "compile", two)
    assert code == 1
    assert err == (f"gestc: error: {two} defines 2 gestures: a, b\n"
                   "  hint: choose one with --gesture NAME\n")


def test_several_boards_need_a_board_for_timed_output(capsys, tmp_path):
    profile = write(tmp_path, "two.toml", (ROOT / "tests" / "data" / "two.toml").read_text())
    gest = write(tmp_path, "t.gest", "g: r_index 90, l_index 90\n")
    code, _, err = run(capsys, "compile", gest, "--profile", profile, "-f", "timed", "-o", "-")
    assert code == 1
    assert err.startswith("gestc: error: profile 'two' has 2 boards (181, 183): choose one")
    code, out, _ = run(capsys, "compile", gest, "--profile", profile, "-f", "timed",
                       "--board", "183", "-o", "-")
    assert code == 0 and out.startswith("0.000000 255\n")


def test_a_broken_compiled_file_is_reported(tmp_path):
    from inmoov_dsl.errors import GestError
    with pytest.raises(GestError) as info:
        from_json('{"format": "inmoov-dsl-compiled", "version": 9}', "old.gestc")
    assert info.value.format() == (
        "old.gestc:1:35: error: not a usable compiled gesture: format version 9, this gestc "
        "reads 1\n"
        '    {"format": "inmoov-dsl-compiled", "version": 9}\n'
        "                                      ^~~~~~~~~\n"
        "  hint: compile it again with 'gestc compile'")


def script(name):
    here = Path(sys.executable).parent / name
    return str(here) if here.exists() else shutil.which(name)


@pytest.mark.parametrize("name", ["gestc", "gestplay"])
def test_console_scripts_are_installed(name):
    exe = script(name)
    assert exe, f"{name} is not installed: pip install -e ."
    done = subprocess.run([exe, "--help"], capture_output=True, text=True, timeout=60)
    assert done.returncode == 0
    assert done.stdout.startswith(f"usage: {name}")


def test_no_traceback_from_the_installed_script(tmp_path):
    bad = write(tmp_path, "bad.gest", "peace: index 900\n")
    done = subprocess.run([script("gestc"), "compile", bad], capture_output=True, text=True,
                          timeout=60, env={**os.environ, "PYTHONWARNINGS": "ignore"})
    assert done.returncode == 1
    assert done.stderr.startswith(f"{bad}:1:14: error: value 900 is outside 0..180")
    assert "Traceback" not in done.stderr


@pytest.mark.parametrize(("text", "why"), [
    ("{nope", "invalid JSON (Expecting property name enclosed in double quotes)"),
    ('{"format": "midi"}', "it is not a gestc file"),
    ('{"format": "inmoov-dsl-compiled", "version": 1}', "missing field 'streams'"),
    ('{"format": "inmoov-dsl-compiled", "version": 1, "streams": [{"board": 181, '
     '"baud": 9600, "times": [0, 1], "bytes": [255]}]}',
     "board 181 has 2 times for 1 byte"),
    ('{"format": "inmoov-dsl-compiled", "version": 1, "streams": [{"board": 181, '
     '"baud": 9600, "times": [0.5, 0.1], "bytes": [255, 1]}]}',
     "board 181: send times go backwards"),
])
def test_compiled_files_that_cannot_be_used(text, why):
    from inmoov_dsl.errors import GestError
    with pytest.raises(GestError) as info:
        from_json(text, "x.gestc")
    assert info.value.first.message == f"not a usable compiled gesture: {why}"
    assert info.value.first.pos.file == "x.gestc"


def test_the_player_checks_a_compiled_file_before_the_first_byte(tmp_path, capsys,
                                                                 monkeypatch):
    from inmoov_dsl.cli import gestplay
    from inmoov_dsl.wire import link

    sent = []
    monkeypatch.setattr(link, "open_port", lambda *a: sent.append(a))  # never reached
    good = tmp_path / "count.gestc"
    assert run(capsys, "compile", COUNT, "-o", str(good))[0] == 0
    doc = json.loads(good.read_text())
    doc["streams"][0]["bytes"][2] = 200  # a value above 180 for the thumb
    bad = tmp_path / "bad.gestc"
    bad.write_text(json.dumps(doc))
    assert gestplay.main([str(bad), "--port", "COM3"]) == 1
    err = capsys.readouterr().err
    assert err.startswith(f"{bad}:") and "not a usable compiled gesture" in err
    assert gestplay.main([str(good), "--port", "COM3", "--profile", "lhand"]) == 1
    assert "board 181" in capsys.readouterr().err
    assert sent == []


@pytest.mark.skipif(os.name != "posix", reason="symlinks")
def test_a_profile_is_a_toml_file_and_nothing_else(tmp_path, capsys):
    from inmoov_dsl.cli import gestplay

    secret = tmp_path / "secret.txt"
    secret.write_text("API_KEY=hunter2\n")
    (tmp_path / "evil.toml").symlink_to(secret)
    for profile in (str(secret), str(tmp_path / "evil.toml"), "/etc/passwd"):
        code, _, err = run(capsys, "compile", COUNT, "--profile", profile, "-o", "-")
        assert code == 1 and "a profile is a .toml file" in err and "hunter2" not in err
    good = tmp_path / "count.gestc"
    assert run(capsys, "compile", COUNT, "-o", str(good))[0] == 0
    doc = json.loads(good.read_text())
    doc["profile"]["name"] = "/etc/passwd"  # a compiled file naming what it should not
    bad = tmp_path / "bad.gestc"
    bad.write_text(json.dumps(doc))
    assert gestplay.main([str(bad), "--dry-run"]) == 1
    assert "a profile is a .toml file, not '/etc/passwd'" in capsys.readouterr().err


def test_a_compiled_file_round_trips():
    compiled = compile_file(COUNT)
    again = from_json(to_json(compiled))
    assert again.streams[0].data == compiled.streams[0].data
    assert again.streams[0].times.tolist() == pytest.approx(compiled.streams[0].times.tolist(),
                                                            abs=1e-9)
    assert (again.gesture, again.final, again.duration) == ("count", compiled.final, 5.0)
    assert again.stream(181).board == 181
    from inmoov_dsl.errors import GestError
    with pytest.raises(GestError, match="no board 190 in profile 'rhand'"):
        again.stream(190)


def test_a_file_without_gestures(capsys, tmp_path):
    poses = write(tmp_path, "poses.gest", "pose fist: fingers 180\n")
    code, _, err = run(capsys, "compile", poses)
    assert code == 1 and err == f"gestc: error: {poses} defines no gesture\n"


def test_a_name_in_two_library_files_names_both(tmp_path):
    from inmoov_dsl import load_library
    from inmoov_dsl.errors import GestError
    (tmp_path / "a.gest").write_text("wave: index 90\n")
    (tmp_path / "b.gest").write_text("wave: index 0\n")
    with pytest.raises(GestError) as info:
        load_library([tmp_path])
    assert info.value.first.message == (
        f"gesture 'wave' is defined in two library files of {tmp_path}: a.gest and b.gest")


def test_gestc_knows_each_command_by_its_module_and_lists_them_all(capsys):
    for name in gestc.COMMANDS:  # a command line that names one builds that one alone
        assert list(gestc.parser(name)._subparsers._group_actions[0].choices) == [name]
    with pytest.raises(SystemExit):
        gestc.main(["--help"])
    listed = capsys.readouterr().out
    assert all(f"    {name} " in listed for name in gestc.COMMANDS)
    with pytest.raises(SystemExit) as exit_:
        gestc.main(["compil", "x"])
    assert exit_.value.code == 2
    assert "invalid choice: 'compil' (choose from 'compile', 'check'," in \
        capsys.readouterr().err


@pytest.mark.parametrize("tool", ["gestc", "gestplay", "gestsim"])
def test_every_tool_tells_its_version(capsys, tool):
    import importlib

    from inmoov_dsl import __version__

    main = importlib.import_module(f"inmoov_dsl.cli.{tool}").main
    with pytest.raises(SystemExit) as exit_:
        main(["--version"])
    assert exit_.value.code == 0
    assert capsys.readouterr().out == f"{tool} {__version__}\n"


def test_a_gesture_named_like_a_bench_tool_plays_with_play(tmp_path, capsys):
    from inmoov_dsl.cli import gestplay

    (tmp_path / "mine.gest").write_text("dump: index 90 over 0.5s\n")
    assert gestplay.main(["play", "dump", "--lib", str(tmp_path), "--dry-run"]) == 0
    schedule = capsys.readouterr().out.splitlines()
    assert schedule[0] == "0.000000 255" and schedule[-1].endswith(" 90")
    # the same first word without 'play' is the bench tool, which wants a port
    with pytest.raises(SystemExit):
        gestplay.main(["dump", "--lib", str(tmp_path)])
    assert "the following arguments are required: --port" in capsys.readouterr().err
    # and 'gestplay GESTURE' is still short for 'gestplay play GESTURE'
    assert gestplay.main(["peace", "--dry-run"]) == 0
    assert capsys.readouterr().out.startswith("0.000000 255\n")


def test_gestc_and_gestplay_load_a_gesture_alike(tmp_path, capsys, monkeypatch):
    """One target loader (cli/target.py): the same file or library gesture, the same
    gesture picked, the same words when there is none to pick."""
    from inmoov_dsl.cli import gestplay
    from inmoov_dsl.compiling.compiled import to_timed

    monkeypatch.chdir(tmp_path)
    (tmp_path / "both.gest").write_text("open: index 0\nshut: index 90\n")

    def gestplay_run(*argv):
        return (gestplay.main(list(argv)), *capsys.readouterr())

    for argv, said in [
        (["both.gest"], "error: both.gest defines 2 gestures: open, shut\n"
         "  hint: choose one with --gesture NAME\n"),
        (["both.gest", "-g", "shutt"], "error: no gesture 'shutt' in both.gest\n"
         "  hint: did you mean 'shut'?\n"),
        (["nosuch"], "error: no file or library gesture 'nosuch'"),
    ]:
        compiled = run(capsys, "compile", *argv, "-o", "-")
        played = gestplay_run(*argv, "--dry-run")
        assert compiled[0] == played[0] == 1
        assert compiled[2].startswith(f"gestc: {said}")
        assert played[2].startswith(f"gestplay: {said}")
    compiled = from_json(run(capsys, "compile", "both.gest", "-g", "shut", "-o", "-")[1])
    assert compiled.gesture == "shut"
    assert gestplay_run("both.gest", "-g", "shut", "--dry-run")[1] == \
        to_timed(compiled.streams[0])


def test_check_reports_every_error_of_a_file(tmp_path, capsys):
    """Three typos in two gestures: three errors, each at its place and with its hint,
    and the gesture that is right is not an error."""
    mine = tmp_path / "typos.gest"
    mine.write_text("a:\n    indx 90, midle 90\n    index 90 over 1s\nb: thum 90\nc: ring 90\n")
    assert gestc.main(["check", str(mine)]) == 1
    err = capsys.readouterr().err
    places = re.findall(rf"^{re.escape(str(mine))}:(\d+):(\d+): error: (.*)$", err, re.M)
    assert places == [("2", "5", "unknown servo or group 'indx'"),
                      ("2", "14", "unknown servo or group 'midle'"),
                      ("4", "4", "unknown servo or group 'thum'")]
    assert err.count("hint: did you mean") == 3


EVERY_ERROR = [  # tests/data/every_error.gest: (line, column, message)
    ("3", "4", "unknown servo or group 'wrsit'"),
    ("3", "20", "value 200 is outside 0..180"),
    ("5", "11", "value 200 is outside 0..180"),
    ("6", "19", "unknown unit 'h'"),
    ("8", "15", "unknown servo or group 'indx'"),
    ("9", "23", "unknown unit 'sec'"),
    ("11", "11", "value 200 is outside 0..180"),
    ("11", "22", "value 300 is outside 0..180"),
    ("11", "33", "value 999 is outside 0..180"),
    ("13", "13", "unexpected end of line; expected ':'"),
    ("14", "9", "unknown servo or group 'indx'"),
    ("15", "11", "unexpected name 's'; expected '&', ',', 'over', 'stagger', 'through' or "
                 "the end of the line"),
    ("17", "3", "unexpected name 'index'; expected ':'")]


def test_check_tells_every_error_of_every_step_in_one_pass(capsys):
    """Names, values, units and colons, several to a step and in any order: each told at
    its place in one pass (an error in a step leaves the rest of the text checked), and
    the gesture that is right is not an error."""
    mine = Path(__file__).parent / "data" / "every_error.gest"
    assert gestc.main(["check", str(mine)]) == 1
    err = capsys.readouterr().err
    assert re.findall(rf"^{re.escape(str(mine))}:(\d+):(\d+): error: (.*)$", err,
                      re.M) == EVERY_ERROR
    assert "did you mean 'wrist'?" in err and "did you mean 'wait'?" in err
    found = analyse(mine.read_text(), str(mine))  # what an editor is told: the same
    assert [(str(d.pos.line), str(d.pos.column), d.message) for d in found.diagnostics] \
        == EVERY_ERROR
    assert list(found.plans) == ["ok"]  # the steps with errors are not planned, the rest is


def test_check_tells_syntax_and_name_errors_together(tmp_path, capsys):
    """A gesture that does not parse hides neither another's unknown name nor a
    warning; a gesture that calls the one that does not parse is not checked (its
    errors are that syntax error's); a robot line that does not parse leaves only
    itself to tell."""
    mine = tmp_path / "mixed.gest"
    mine.write_text("pose p: index 9\na: indx 90\nb: index 9 ove 1s\nc: b, p\n"
                    "d: p, thum 90\ne: index 90 over 0.05s\n")
    assert gestc.main(["check", str(mine)]) == 1
    err = capsys.readouterr().err
    told = re.findall(rf"^{re.escape(str(mine))}:(\d+):\d+: (error|warning): (.*)$", err,
                      re.M)
    assert [(line, kind, message.split(";")[0]) for line, kind, message in told] == [
        ("6", "warning", "move stretched: needs 0.31 s, asked 0.05 s"),
        ("2", "error", "unknown servo or group 'indx'"),
        ("3", "error", "unexpected name 'ove'"),
        ("5", "error", "unknown servo or group 'thum'")]  # none for c
    mine.write_text("robot inmoov extra\nn: nek 90\n")
    assert gestc.main(["check", str(mine)]) == 1
    err = capsys.readouterr().err
    assert err.count("error:") == 1 and ":1:" in err  # not 'nek' for the wrong robot


def test_a_play_tells_its_result_on_stdout_and_the_rest_on_stderr():
    """``gestplay peace --port sim:// > log.txt`` keeps what was played and the pose the
    hand ends in; where to watch it move is advice, on stderr."""
    done = subprocess.run([sys.executable, "-m", "inmoov_dsl.cli.gestplay", "peace",
                           "--port", "sim://"], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    out = done.stdout.splitlines()
    assert out[0].startswith("played peace: 0.70 s, 201 bytes, worst lateness ")
    assert out[1:] == ["sim://rhand?board=181 now holds (board 181, right hand):",
                       "  wrist        0", f"  thumb      180  {'#' * 30}", "  index        0",
                       "  middle       0", f"  ring       180  {'#' * 30}",
                       f"  pinky      180  {'#' * 30}"]
    assert "played" not in done.stderr and "now holds" not in done.stderr
    assert done.stderr.startswith("to watch it move: run 'gestsim --view'")


@pytest.mark.parametrize(("argv", "said"), [
    (["relax", "--port", "sim://"], "board 181 on sim://rhand?board=181: relaxed, its "
                                    "servos are limp until the next command\n"),
    (["dump", "--port", "sim://"], "board 181 (right hand): 6 servos\n"),
])
def test_the_bench_tools_tell_their_result_on_stdout(argv, said, capsys):
    from inmoov_dsl.cli import gestplay

    assert gestplay.main(argv) == 0
    out, err = capsys.readouterr()
    assert out.startswith(said) and err == ""


def helped(capsys, main, *argv) -> str:
    """What ``main([*argv, "--help"])`` prints (it exits 0), its lines joined and its
    spaces single (argparse wraps it to the terminal's width)."""
    with pytest.raises(SystemExit) as exit_:
        main([*argv, "--help"])
    assert exit_.value.code == 0
    return capsys.readouterr().out


def flat(text: str) -> str:
    """``text`` on one line, one space between its words."""
    return " ".join(text.split())


def described(text: str) -> str:
    """The description a --help gives: the paragraph after the usage (empty if none)."""
    after = text.split("\n\n")[1]
    return "" if after.startswith(("positional arguments:", "options:")) else flat(after)


def test_gestplay_help_lists_every_tool_and_each_usage_names_its_tool(capsys):
    from inmoov_dsl.cli import gestplay

    listed = helped(capsys, gestplay.main)
    assert all(f"    {name} " in listed for name in gestplay.TOOLS)
    assert all(name in described(helped(capsys, gestplay.main, "play"))
               for name in gestplay.TOOLS)  # the bench tools, serve and stored too
    for name in gestplay.TOOLS:
        assert helped(capsys, gestplay.main, name).startswith(f"usage: gestplay {name} ")
    assert helped(capsys, gestplay.main, "peace").startswith("usage: gestplay play ")


def test_every_command_says_what_it_does_in_its_help(capsys):
    from inmoov_dsl.cli import gestplay

    for main, names in ((gestc.main, gestc.COMMANDS), (gestplay.main, gestplay.TOOLS)):
        for name in names:
            text = helped(capsys, main, name)
            assert text.startswith(f"usage: {main.__module__.rpartition('.')[2]} {name} ")
            assert described(text), f"{name} --help has no description"
    assert described(helped(capsys, gestc.main, "check")).startswith(
        "Check .gest files as gestc compile would, writing nothing: every error and "
        "warning of each file")
    assert described(helped(capsys, gestc.main, "lsp")).startswith(
        "The language server of .gest files, for editors")
    assert described(helped(capsys, gestplay.main, "ports")) == \
        "The serial ports on this machine, and who answers."


@pytest.mark.parametrize("argv", [["gestplay", "play"], ["gestplay", "dump"],
                                  ["gestplay", "relax"], ["gestplay", "repl"],
                                  ["gestplay", "teach"], ["gestplay", "serve"],
                                  ["gestplay", "stored"], ["gestc", "upload"]])
def test_the_port_help_shows_a_port_per_board(argv, capsys):
    import importlib

    main = importlib.import_module(f"inmoov_dsl.cli.{argv[0]}").main
    text = flat(helped(capsys, main, argv[1]))
    port = text[text.index("--port PORT ", text.index("options:")):]
    assert "right=COM3,left=COM4" in port.split(" -p PROFILE")[0]


def test_gestc_lsp_takes_stdio_as_editors_pass_it(capsys):
    assert "--stdio " in helped(capsys, gestc.main, "lsp")
    for argv in (["lsp"], ["lsp", "--stdio"]):
        args = gestc.parser("lsp").parse_args(argv)
        assert args.command == "lsp" and args.func.__module__ == "inmoov_dsl.cli.gestc.lsp"


@pytest_lsp.fixture(config=ClientServerConfig(server_command=[
    sys.executable, "-m", "inmoov_dsl.cli.gestc", "lsp", "--stdio"]))
async def stdio_client(lsp_client: LanguageClient):
    yield


@pytest.mark.asyncio
async def test_the_language_server_starts_with_stdio(stdio_client: LanguageClient):
    """Started as a generic LSP client starts it (``gestc lsp --stdio``), it answers."""
    import asyncio

    result = await asyncio.wait_for(stdio_client.initialize_session(
        lsp.InitializeParams(capabilities=client_capabilities("neovim"))), 60)
    assert result.capabilities.document_formatting_provider
    await asyncio.wait_for(stdio_client.shutdown_session(), 60)
