"""The gesture library, the profiles it plays on, and where gestures are found."""

import os
import shutil
from pathlib import Path

import numpy as np
import pytest
from boardmodel import final_values, read_stream
from conftest import WHOLE_ROBOT, early

from inmoov_dsl import GestError, clock, load_profile, measure
from inmoov_dsl.cli import gestc, gestplay, hand
from inmoov_dsl.compiling.compiler import compile_program
from inmoov_dsl.language.library import find_gesture, library_dirs, scan_library
from inmoov_dsl.language.load import load
from inmoov_dsl.wire.player import play

ROOT = Path(__file__).resolve().parent.parent
LIBRARY = scan_library([ROOT / "gestures"])
BODY = {name for name, e in LIBRARY.items() if e.path.name in WHOLE_ROBOT}
HAND = sorted(set(LIBRARY) - BODY)
FINGERS = ("thumb", "index", "middle", "ring", "pinky")

# facts.md: what each movement of the original demo ends in (0 straight, 180 curled)
ORIGINAL = {
    "reset": dict.fromkeys(("wrist", *FINGERS), 0),
    "peace": {"thumb": 180, "ring": 180, "pinky": 180, "index": 0, "middle": 0},
    "ok": {"thumb": 180, "index": 160, "middle": 0, "ring": 0, "pinky": 0},
    "grab": dict.fromkeys(FINGERS, 180),
    "fist": dict.fromkeys(FINGERS, 180),
    "rockon": {"middle": 180, "ring": 180, "thumb": 0, "index": 0, "pinky": 0},
    "count": dict.fromkeys(FINGERS, 0),  # five: every finger open at the end
    "wiggle": {"thumb": 40, "index": 0, "middle": 0, "ring": 0, "pinky": 0},
}


def decoded_final(profile, compiled):
    """Each servo's last value, as a board reading the bytes would hold it (by name)."""
    ids = {s.id: s.name for s in profile.servos}
    held = dict(zip((s.id for s in profile.servos), compiled.start, strict=True))
    for stream in compiled.streams:
        events = read_stream(stream.times, stream.data, stream.baud)
        held = final_values(events, held)
    return {ids[sid]: value for sid, value in held.items()}


def compiled_for(name, profile, start=None):
    return compile_program(load(str(LIBRARY[name].path)), name, profile, start)


@pytest.fixture(scope="module", params=["rhand", "lhand", "inmoov"])
def hand_profile(request):
    return load_profile(request.param)


def test_the_original_demo_is_all_there_and_more():
    assert set(ORIGINAL) | {"demo"} <= set(LIBRARY)
    assert len(HAND) - len(ORIGINAL) - 1 >= 12
    assert {"hello", "nod", "shrug"} <= BODY
    for entry in LIBRARY.values():
        assert entry.description, f"{entry.name} has no description"
        assert len(entry.description) < 90


@pytest.mark.parametrize("name", sorted(ORIGINAL))
def test_original_movements_end_in_their_original_pose(name, hand_profile):
    compiled, _ = compiled_for(name, hand_profile)
    final = decoded_final(hand_profile, compiled)
    by_hand_name = {name: final[hand_profile.groups.get(name, (name,))[0]]
                    for name in ("wrist", *FINGERS)}
    assert {k: by_hand_name[k] for k in ORIGINAL[name]} == ORIGINAL[name]


@pytest.mark.parametrize("name", HAND)
def test_every_hand_gesture_plays_within_the_link_and_the_limits(name, hand_profile):
    for start in (None, "hand 180"):
        compiled, plan = compiled_for(name, hand_profile, start)
        if start is None:
            assert not compiled.warnings, [w.format() for w in compiled.warnings]
        reports = measure(plan, compiled.streams)
        assert len(reports) == len(hand_profile.boards)  # a report for every board
        for report in reports:
            assert report.coverage == 1.0
            assert report.max_error <= 0.5 + early(hand_profile, report.baud)
        t = np.linspace(0, plan.duration, 4000)
        for servo, track in zip(hand_profile.servos, plan.tracks, strict=True):
            assert np.abs(track.velocity(t)).max() <= servo.max_velocity * (1 + 1e-6)
        assert all(max(s.data[1:], default=0) <= 180 for s in compiled.streams)


def test_wiggle_swings_the_thumb_as_the_original_does():
    """As the index opens the thumb swings from 40 to 130, straightens to 0, and comes
    back to 40 as the wave runs back from the index to the pinky."""
    _, plan = compiled_for("wiggle", "rhand")
    profile = plan.profile
    t = np.arange(0, plan.duration, 0.005)
    thumb, index, pinky = (plan.tracks[profile.index(n)].position(t)
                           for n in ("thumb", "index", "pinky"))
    out = int(np.argmax(thumb))
    straight = out + int(np.argmin(thumb[out:]))
    assert round(thumb[out]) == 130 and round(thumb[straight]) == 0
    assert round(thumb[int(0.7 / 0.005)]) == 40 and round(thumb[-1]) == 40  # tucked at 40
    first_curl = int(np.argmax(index > 89))  # the wave reaches the index
    assert first_curl < out and index[out] < index[first_curl]  # opening as the thumb swings
    back = straight + int(np.argmax(index[straight:] > 89))  # the wave runs back
    assert abs(thumb[back] - 40) < 1 and pinky[back:].max() > 89


def test_fist_is_grab():
    grab, _ = compiled_for("grab", "rhand")
    fist, _ = compiled_for("fist", "rhand")
    assert fist.streams[0].data == grab.streams[0].data


def test_demo_plays_every_original_movement_with_a_pause_between():
    compiled, _ = compiled_for("demo", "rhand")
    called = []
    for step in compiled.steps:
        where = step.where.split(" > ")
        if len(where) > 1 and where[1] not in called:
            called.append(where[1])
    assert called == ["peace", "ok", "grab", "wiggle", "count", "rockon"]
    pauses = [s for s in compiled.steps if s.where == "demo" and s.kind == "hold"]
    assert [s.asked for s in pauses] == [1.0] * 5


@pytest.mark.parametrize("name", sorted(BODY))
def test_whole_robot_gestures_compile_to_one_stream_per_board(name):
    inmoov = load_profile("inmoov")
    compiled, plan = compiled_for(name, inmoov)
    assert not compiled.warnings
    assert [s.board for s in compiled.streams] == [b.id for b in inmoov.boards]
    # a jaw that talks turns quicker than its link can tell it at every turn: at some of
    # its turns the value due is the one the board already holds (docs/speaking.md)
    least = 0.98 if compiled.sounds else 1.0
    assert all(r.coverage >= least for r in measure(plan, compiled.streams))
    assert decoded_final(inmoov, compiled) == dict(zip(inmoov.names, plan.final,
                                                       strict=True))


def test_a_body_gesture_on_a_hand_names_the_robot_it_is_for():
    with pytest.raises(GestError) as info:
        compiled_for("hello", "rhand")
    first = info.value.first
    assert (first.pos.file, first.pos.line) == (str(LIBRARY["hello"].path), 3)
    assert first.message.startswith("this file is for robot 'inmoov', and profile 'rhand' "
                                    "has no r_wrist, r_thumb,")


def test_hand_gestures_play_on_the_robots_right_hand():
    rhand, _ = compiled_for("peace", "rhand")
    six, _ = compiled_for("peace", "inmoov-six")  # the right hand's own board, at 9600
    assert six.streams[0].board == 181
    assert six.streams[0].data == rhand.streams[0].data
    assert all(len(s.data) == 1 for s in six.streams[1:])  # CANCEL only
    inmoov = load_profile("inmoov")  # the right Mega: the hand among the arm's servos
    robot, _ = compiled_for("peace", inmoov)
    final = decoded_final(inmoov, robot)
    assert [final[f"r_{n}"] for n in load_profile("rhand").names] == \
        list(decoded_final(load_profile("rhand"), rhand).values())
    assert len(robot.streams[1].data) == 1  # the left Mega: CANCEL only


def test_left_hand_is_its_own_board_and_ids():
    rhand, lhand = load_profile("rhand"), load_profile("lhand")
    assert lhand.names == rhand.names
    assert [b.id for b in lhand.boards] == [183]
    assert [s.id for s in lhand.servos] == [6, 7, 8, 9, 10, 11]
    inmoov = load_profile("inmoov")
    for servo in lhand.servos:
        twin = inmoov.servos[inmoov.index(f"l_{servo.name}")]
        assert (twin.id, twin.board, twin.calibration, twin.max_velocity) == \
            (servo.id, servo.board, servo.calibration, servo.max_velocity)


@pytest.mark.parametrize(("name", "on"), [("inmoov", dict(r=181, head=183, l=183, arm=181)),
                                          ("inmoov-six", dict(r=181, head=184, l=183,
                                                              arm=186))])
def test_the_whole_robot_plays_in_lockstep_on_virtual_boards(virtual_clock, name, on):
    inmoov = load_profile(name)
    ports = hand.parse_ports(["sim://?boot=0"], inmoov)
    assert ports[on["head"]] == f"sim://{name}?boot=0&board={on['head']}"
    links = hand.connect(ports, inmoov)
    try:
        program = load("t.gest", "g: r_index 90, neck 110, l_thumb 45, r_shoulder 40 "
                                 "over 0.3s\n")
        compiled, _ = compile_program(program, "g", inmoov)
        play(compiled, links)
        boards = {link.board: link.port.board for link in links}
        for board in boards.values():
            board.advance(clock.now())
        assert boards[on["r"]].positions()[2] == 90
        assert boards[on["head"]].positions()[12] == 110
        assert boards[on["l"]].positions()[7] == 45
        assert boards[on["arm"]].positions()[22] == 40
        # one clock: every pair reached its board at its planned time plus one offset
        offsets = []
        for stream in compiled.streams:
            planned = read_stream(stream.times, stream.data, stream.baud)
            got = boards[stream.board].log
            assert [(w.id, w.value) for _, w in got] == [(i, v) for _, i, v in planned]
            offsets += [t - p for (t, _), (p, _, _) in zip(got, planned, strict=True)]
        assert max(offsets) - min(offsets) < 0.02
    finally:
        hand.close(links)


def test_a_bare_sim_port_is_the_virtual_board_of_the_profile_played(capsys):
    assert hand.parse_ports(["sim://"], load_profile("lhand")) == \
        {183: "sim://lhand?board=183"}
    custom = ROOT / "tests" / "data" / "two.toml"
    assert hand.parse_ports(["sim://"], load_profile(str(custom)))[183] == \
        f"sim://{custom.as_posix()}?board=183"
    assert gestplay.main(["dump", "--port", "sim://", "--profile", "lhand"]) == 0
    assert "board 183 (left hand): 6 servos" in capsys.readouterr().out


# -- where gestures come from --------------------------------------------------------------
def write(directory, name, text):
    directory.mkdir(parents=True, exist_ok=True)
    (directory / name).write_text(text)
    return directory / name


def test_gestures_come_from_lib_gest_path_local_and_builtin(tmp_path, monkeypatch, capsys):
    lib, env = tmp_path / "lib", tmp_path / "env"
    write(lib, "a.gest", "# from --lib\nfrom_lib: index 10\n")
    write(env, "b.gest", "# from GEST_PATH\nfrom_env: index 20\n")
    write(tmp_path / "work" / "gestures", "c.gest", "# local\nfrom_here: index 30\n")
    monkeypatch.chdir(tmp_path / "work")
    monkeypatch.setenv("GEST_PATH", f"{env}{os.pathsep}{tmp_path / 'none'}")
    dirs = [d.resolve() for d in library_dirs([lib])]
    assert dirs == [lib.resolve(), env.resolve(), (tmp_path / "work" / "gestures").resolve(),
                    (ROOT / "gestures").resolve()]  # a GEST_PATH entry that is not: skipped
    assert gestc.main(["list", "--lib", str(lib)]) == 0
    names = [line.split("\t")[0] for line in capsys.readouterr().out.splitlines()]
    assert {"from_lib", "from_env", "from_here", "peace"} <= set(names)
    assert gestc.main(["compile", "from_lib", "--lib", str(lib), "-o", "-", "-f",
                       "timed"]) == 0
    assert capsys.readouterr().out.splitlines()[-1].endswith(" 10")


def test_the_first_place_that_defines_a_name_wins(tmp_path, capsys):
    """Like PATH: a gesture of one's own replaces the library's, and gestc list says
    where each name comes from and what it shadows."""
    mine = write(tmp_path, "mine.gest", "# my own\npeace: index 0, middle 0\n")
    builtin = LIBRARY["peace"].path
    assert find_gesture("peace", None, library_dirs([tmp_path])) == (str(mine), "peace")
    assert gestc.main(["list", "--lib", str(tmp_path)]) == 0
    out, err = capsys.readouterr()
    lines = out.splitlines()
    assert f"peace\t{mine}\trhand" in lines
    assert f"count\t{LIBRARY['count'].path}\trhand" in lines
    assert {len(line.split("\t")) for line in lines} == {3}  # machine-readable columns
    assert err == f"gestc: note: 'peace' of {mine} shadows the one in {builtin}\n"
    assert gestc.main(["list", "--long", "--lib", str(tmp_path)]) == 0
    peace = next(line for line in capsys.readouterr().out.splitlines()
                 if line.startswith("peace "))
    assert peace.endswith(f"my own  (mine.gest:2, for rhand)  (shadows {builtin})")
    assert gestc.main(["compile", "peace", "--lib", str(tmp_path), "-o", "-",
                       "-f", "timed"]) == 0
    assert capsys.readouterr().out.splitlines() == ["0.000000 255"]  # mine: nothing moves


def test_a_copy_of_the_library_in_gestures_is_no_conflict(tmp_path, monkeypatch, capsys):
    """The README's first line, from a clone's root: ./gestures is the library the
    package carries too; it wins and shadows the installed copy."""
    shutil.copytree(ROOT / "gestures", tmp_path / "gestures")
    monkeypatch.chdir(tmp_path)
    entries = scan_library(library_dirs())
    assert set(entries) == set(LIBRARY)
    assert all(e.path.parent == Path("gestures").absolute() or
               e.path.parent.resolve() == (tmp_path / "gestures").resolve()
               for e in entries.values())


def test_the_same_file_reached_twice_is_one_file(tmp_path):
    real = tmp_path / "real"
    write(real, "wave2.gest", "wave2: index 90\n")
    (tmp_path / "link").symlink_to(real)
    entries = scan_library([real, tmp_path / "link"])
    assert entries["wave2"].shadows == ()


def test_a_file_that_does_not_parse_is_a_warning_unless_it_is_asked_for(tmp_path, capsys):
    bad = write(tmp_path, "bad.gest", "oops: index 90 over\n")
    assert gestc.main(["list", "--lib", str(tmp_path)]) == 0
    out, err = capsys.readouterr()
    assert "count\t" in out  # the rest of the library is there
    assert err.startswith(f"{bad}:1:") and "warning: skipped bad.gest, it does not parse: " \
        in err
    assert gestc.main(["compile", "count", "--lib", str(tmp_path), "-o", "-"]) == 0
    assert "warning: skipped bad.gest" in capsys.readouterr().err
    assert gestc.main(["compile", "oops", "--lib", str(tmp_path), "-o", "-"]) == 1
    err = capsys.readouterr().err
    assert err.startswith(f"{bad}:1:") and ": error: " in err and "skipped" not in err


def test_a_missing_lib_directory_is_an_error(capsys):
    assert gestc.main(["list", "--lib", "/no/such/dir"]) == 1
    assert capsys.readouterr().err == ("gestc: error: library directory '/no/such/dir' not "
                                       "found\n  hint: --lib takes a directory of .gest "
                                       "files\n")


def test_list_long_shows_what_each_gesture_does(capsys):
    assert gestc.main(["list", "--long"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert len(lines) == len(LIBRARY)
    peace = next(line for line in lines if line.startswith("peace "))
    assert peace.split()[1:4] == ["the", "V", "sign,"]
    assert peace.endswith("(peace.gest:3, for rhand)")
    assert next(line for line in lines if line.startswith("nod ")).endswith(", for inmoov)")


def test_the_repl_knows_the_first_definition_of_each_name(tmp_path):
    from inmoov_dsl.cli.gestplay.repl import library_program

    write(tmp_path, "mine.gest", "peace: index 0, middle 0\npose open2: fingers 0\n")
    write(tmp_path, "bad.gest", "oops: index 90 over\n")
    program = library_program(library_dirs([tmp_path]))
    assert program.gestures["peace"].name.pos.file == str((tmp_path / "mine.gest").resolve())
    assert "count" in program.gestures and "open2" in program.poses


@pytest.mark.parametrize("argv", [["gestc", "show", "hello"],
                                  ["gestc", "check", str(ROOT / "gestures" / "talk.gest")],
                                  ["gestplay", "hello", "--dry-run"],
                                  ["gestplay", "hello", "--port", "sim://"]])
def test_every_command_plays_a_body_gesture_on_the_robot_its_file_names(argv, capsys):
    tool = gestc if argv[0] == "gestc" else gestplay
    assert tool.main(argv[1:]) == 0, capsys.readouterr().err
    assert tool.main([*argv[1:], "--profile", "rhand"]) == 1
    err = capsys.readouterr().err
    assert "error: this file is for robot 'inmoov', and profile 'rhand' has no " in err
    if argv[1] == "check":  # the file's count ends gestc check's report
        assert err.endswith(": 1 error\n")
        err = err[:err.rstrip("\n").rfind("\n") + 1]
    assert err.endswith("  hint: play it on 'inmoov', or on a profile with all of its "
                        "servos and groups\n")


def test_the_repl_names_the_profile_a_servo_is_in(rhand):
    from inmoov_dsl.live.drive import library_program
    from inmoov_dsl.live.session import line_steps

    with pytest.raises(GestError) as info:
        line_steps("rothead 90", library_program(None), rhand)
    assert info.value.first.hint == ("'rothead' is in profile 'inmoov': a file for that "
                                     "robot starts with the line  robot inmoov")


@pytest.mark.parametrize("target", ["peace.gest", "peace", str(ROOT / "gestures" / "peace")])
def test_a_library_file_named_on_the_command_line_plays_its_gesture(target, tmp_path,
                                                                     monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)  # no peace.gest here: the library's
    assert gestplay.main([target, "--dry-run"]) == 0
    assert capsys.readouterr().out.splitlines()[-1] == "0.690625 180"


@pytest.mark.parametrize("target, hint", [
    ("gestures/wave.gest", "'wave' is a library gesture: give its name alone, wave"),
    ("gestures/wave", "'wave' is a library gesture: give its name alone, wave"),
    ("gestures/wav.gest", "did you mean 'wave'? (a library gesture: give its name alone)"),
])
def test_a_path_that_is_nowhere_hints_at_the_gesture_meant(target, hint, capsys):
    for main, argv in ((gestplay.main, [target, "--port", "sim://"]),
                       (gestc.main, ["show", target])):
        assert main(argv) == 1
        assert capsys.readouterr().err.splitlines()[-2:] == [
            f"{'gestplay' if main is gestplay.main else 'gestc'}: error: cannot find "
            f"'{target}'", f"  hint: {hint}"]


def test_a_file_of_several_gestures_asks_which(capsys):
    assert gestplay.main([str(ROOT / "gestures" / "motion.gest"), "--port", "sim://"]) == 1
    err = capsys.readouterr().err
    assert "motion.gest defines 4 gestures: drum, bye, beckon, wave" in err
    assert err.endswith("hint: choose one with --gesture NAME\n")


def test_a_file_name_typed_at_the_repl_hints_at_its_gesture(rhand):
    from inmoov_dsl.live.drive import library_program
    from inmoov_dsl.live.session import line_steps

    with pytest.raises(GestError) as info:
        line_steps("peace.gest", library_program(None), rhand)
    assert info.value.first.hint == "a step names a gesture, not its file: peace"


def test_a_library_gesture_named_in_a_file_says_which_use_line_brings_it(tmp_path, capsys):
    mine = tmp_path / "both.gest"
    mine.write_text("both: peace & nod\n")
    assert gestc.main(["check", str(mine), "--profile", "inmoov"]) == 1
    *_, hint, count = capsys.readouterr().err.splitlines()
    assert hint == ("  hint: 'peace' is a library gesture, defined in peace.gest: add the "
                    "line  use \"peace.gest\"  to this file")
    assert count == f"{mine}: 1 error"
    mine.write_text('use "peace.gest"\nuse "body.gest"\nboth: peace & nod\n')
    assert gestc.main(["check", str(mine), "--profile", "inmoov"]) == 0
