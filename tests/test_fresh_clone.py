"""What a new user tripped on from a fresh clone: each message as the user sees it."""

import os
import shlex
import subprocess
import sys

import pytest

from inmoov_dsl.cli import gestplay


def gestsim_pty(*argv: str) -> tuple[subprocess.Popen, str]:
    """A gestsim started with ``argv``, and the pseudo-terminal it prints."""
    proc = subprocess.Popen([sys.executable, "-m", "inmoov_dsl.cli.gestsim", *argv,
                             "--boot", "0.2"], stdout=subprocess.PIPE,
                            stderr=subprocess.DEVNULL, text=True)
    return proc, proc.stdout.readline().strip()


@pytest.mark.skipif(os.name != "posix", reason="gestsim serves a pseudo-terminal")
def test_the_line_to_watch_it_move_keeps_the_options_played_with(tmp_path, monkeypatch,
                                                                  capsys):
    """The gesture chosen in a file, the contact allowed, the speed and the passes are
    in the command printed, which plays as printed."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "two.gest").write_text("wave: index 90\nfist: fingers 180\n")
    argv = ["two.gest", "-g", "fist", "--allow-contact", "--speed", "0.5", "--loop", "2"]
    assert gestplay.main([*argv, "--port", "sim://"]) == 0
    line = capsys.readouterr().err.splitlines()[-1]
    assert line == ("to watch it move: run 'gestsim --view' (or --web: in 3-D, in a "
                    "browser) in another terminal, then 'gestplay two.gest -g fist "
                    "--allow-contact --speed 0.5 --loop 2 --port PTY' with the PTY it prints")
    proc, pty = gestsim_pty("--view")
    try:
        command = shlex.split(line.split("'")[3].replace("PTY", pty))
        assert gestplay.main(command[1:]) == 0, capsys.readouterr().err
        assert capsys.readouterr().out.startswith("played fist twice: ")
    finally:
        proc.kill()
        proc.wait()


def test_a_gesture_named_like_a_tool_is_watched_by_its_full_command(tmp_path, monkeypatch,
                                                                     capsys):
    """``gestplay dump.gest`` is printed as ``gestplay play ...`` when its name is a
    tool's; ``--loop`` alone (until Ctrl-C) stays alone."""
    from argparse import Namespace

    from inmoov_dsl.cli.gestplay.play import watch
    from inmoov_dsl.profiles.profile import load_profile

    args = Namespace(target="dump", gesture=None, profile=None, lib=["mine"], hand=None,
                     allow_contact=False, speed=1.0, loop=0, strict=True, audio=None)
    line = watch(args, load_profile("rhand"), {181}, posix=True)
    assert line.endswith("then 'gestplay play dump --lib mine --strict --loop --port PTY' "
                         "with the PTY it prints")
    line = watch(args, load_profile("rhand"), {181}, posix=False)
    assert line == "'gestc preview dump --lib mine --strict -o dump.gif' draws it"


def test_a_folder_given_for_a_gesture_file_is_said_to_be_one(tmp_path, monkeypatch, capsys):
    """``gestc check adir``: the folder is named as a folder (no errno), and the .gest
    files in it are what to give instead."""
    from inmoov_dsl.cli import gestc

    monkeypatch.chdir(tmp_path)
    (tmp_path / "adir").mkdir()
    assert gestc.main(["check", "adir"]) == 1
    assert capsys.readouterr().err == (
        "gestc: error: 'adir' is a folder, not a gesture file\n"
        "  hint: give a .gest file, or a library gesture's name (gestc list)\n"
        "adir: 1 error\n")
    (tmp_path / "adir" / "b.gest").write_text("b: index 90\n")
    (tmp_path / "adir" / "a.gest").write_text("a: index 90\n")
    for argv in (["show", "adir"], ["fmt", "adir"], ["preview", "--live", "adir"]):
        assert gestc.main(argv) == 1
        assert capsys.readouterr().err == (
            "gestc: error: 'adir' is a folder, not a gesture file\n"
            f"  hint: give a .gest file in it: {os.path.join('adir', 'a.gest')}, "
            f"{os.path.join('adir', 'b.gest')}\n")
    assert gestplay.main(["adir", "--port", "sim://"]) == 1
    assert "gestplay: error: 'adir' is a folder, not a gesture file\n" in capsys.readouterr().err


def test_a_folder_given_for_any_other_file_is_said_to_be_one(tmp_path, monkeypatch,
                                                              capsys):
    """A folder where a profile, a used file, a sound or a compiled gesture is read."""
    from inmoov_dsl.cli import gestc

    monkeypatch.chdir(tmp_path)
    for folder in ("my.toml", "part.gest", "hi.wav", "done.gestc"):
        (tmp_path / folder).mkdir()
    assert gestplay.main(["peace", "--profile", "./my.toml", "--dry-run"]) == 1
    assert capsys.readouterr().err == (
        "gestplay: error: './my.toml' is a folder, not a profile file\n"
        "  hint: give a .toml file, or a built-in profile's name (rhand)\n")
    (tmp_path / "uses.gest").write_text('use "part.gest"\nx: index 90\n')
    (tmp_path / "says.gest").write_text('robot inmoov\nx: say "hi.wav"\n')
    assert gestc.main(["check", "uses.gest", "says.gest"]) == 1
    err = capsys.readouterr().err
    assert "uses.gest:1:5: error: cannot read 'part.gest': it is a folder, not a file\n" in err
    assert "says.gest:2:8: error: cannot read 'hi.wav': it is a folder, not a file\n" in err
    assert "Errno" not in err
    assert gestplay.main(["done.gestc", "--port", "sim://"]) == 1
    assert capsys.readouterr().err == (
        "gestplay: error: cannot read 'done.gestc': it is a folder, not a file\n")
    assert gestc.main(["urdf", "-o", "part.gest"]) == 1  # a folder to write
    assert capsys.readouterr().err == (
        "gestc: error: 'part.gest' is a folder, not a file\n"
        "  hint: give a file's path (one in the folder: FOLDER/NAME)\n")


def test_a_folder_given_for_the_firmware_is_said_to_be_one(tmp_path):
    """``gestc upload BOARD --hex FOLDER``: the .hex files in it are what to give."""
    from pathlib import Path

    from inmoov_dsl.errors import GestError
    from inmoov_dsl.firmware.upload import read_hex

    (tmp_path / "servo_rhand.hex").write_text(":00000001FF\n")
    with pytest.raises(GestError) as info:
        read_hex(Path(tmp_path))
    assert info.value.format() == (
        f"error: '{tmp_path}' is a folder, not a HEX file\n"
        f"  hint: give the .hex file a build wrote: {tmp_path / 'servo_rhand.hex'}")


VALUES = ("robot inmoov\ngroup g: neck, jaw\na: neck 190\nb: eyes 300\nc: jaw 300\n"
          "d: index 200\ne: g 181\n")


def test_a_value_out_of_range_is_hinted_with_its_servo_s_own_range(tmp_path, monkeypatch,
                                                                    capsys):
    """``neck 190`` on inmoov: the neck's range, not the fingers' "0 is straight"; the
    mouth's ends as its [voice] says; a group's members; the same in gestc check,
    gestc show, gestplay, --from and the repl."""
    from inmoov_dsl.cli import gestc

    monkeypatch.chdir(tmp_path)
    (tmp_path / "r.gest").write_text(VALUES)
    hints = ["  hint: neck takes 0..180 on inmoov",
             "  hint: eyes (eye_x, eye_y) take 0..180 on inmoov",
             "  hint: jaw takes 0..180 on inmoov (0 is closed, 150 open: its [voice])",
             "  hint: index (r_index) takes 0..180 on inmoov",
             "  hint: g (neck, jaw) take 0..180 on inmoov"]
    assert gestc.main(["check", "r.gest"]) == 1
    assert [h for h in capsys.readouterr().err.splitlines() if "hint" in h] == hints
    for main, argv in ((gestc.main, ["show", "r.gest", "-g", "a"]),
                       (gestplay.main, ["r.gest", "-g", "a", "--dry-run"])):
        assert main(argv) == 1
        assert [h for h in capsys.readouterr().err.splitlines() if "hint" in h] == hints
    assert gestc.main(["show", "peace", "--profile", "inmoov", "--from", "neck 190"]) == 1
    assert capsys.readouterr().err.endswith("hint: neck takes 0..180 on inmoov\n")


def test_a_value_out_of_every_range_without_a_profile_is_hinted_so():
    """The parser alone knows no servo: it says what every servo is within."""
    from inmoov_dsl.errors import GestError
    from inmoov_dsl.language.parse import parse

    with pytest.raises(GestError) as info:
        parse("a: neck 190\n", "r.gest")
    assert info.value.diagnostics[0].hint == ("no servo takes more than 0..180; its profile "
                                              "may give it less")


@pytest.mark.parametrize(("argv", "said"), [
    (["peace", "--port", "i2c:1"],
     "gestplay: error: port i2c:1 is an I2C bus, where a PCA9685 is: board 181 (right hand) "
     "of profile 'rhand' is a rig board, on a serial port\n  hint: a profile whose board is "
     "a pca9685 plays there: --profile rhand-pca9685; for board 181, give its serial port "
     "('gestplay ports' lists them)\n"),
    (["peace", "--profile", "rhand-pca9685", "--port", "i2c:1@0x99"],
     "gestplay: error: cannot open port i2c:1@0x99: 0x99 is not a PCA9685's address, which "
     "is 0x40..0x77 except 0x70\n  hint: its six address pins give 0x40..0x7F; the I2C bus "
     "reserves 0x78..0x7F, and 0x70 is the All Call address every PCA9685 answers; with no "
     "pin bridged it is 0x40: --port i2c:1\n"),
])
def test_an_i2c_port_says_what_it_needs(argv, said, capsys):
    assert gestplay.main(argv) == 1
    assert capsys.readouterr().err == said


def test_a_value_typed_at_the_repl_is_hinted_with_its_servo_s_range():
    from inmoov_dsl.errors import GestError
    from inmoov_dsl.language.load import load
    from inmoov_dsl.live.session import line_steps
    from inmoov_dsl.profiles.profile import load_profile

    program = load("<repl>", "", search=[])
    with pytest.raises(GestError) as info:
        line_steps("neck 190", program, load_profile("inmoov"))
    assert info.value.format().splitlines() == [
        "<repl>:1:6: error: value 190 is outside 0..180", "    neck 190", "         ^~~",
        "  hint: neck takes 0..180 on inmoov"]


@pytest.mark.skipif(os.name != "posix", reason="gestsim serves a pseudo-terminal")
def test_gestsim_takes_a_board_by_its_name_as_port_does():
    proc = subprocess.Popen([sys.executable, "-m", "inmoov_dsl.cli.gestsim", "--profile",
                             "inmoov", "--board", "left", "--quiet"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        pty = proc.stdout.readline().strip()
        assert proc.stderr.readline() == (f"gestsim: board 183 (left) of profile 'inmoov' on "
                                          f"{pty} at 115200 baud; Ctrl-C stops\n")
    finally:
        proc.kill()
        proc.wait()


@pytest.mark.parametrize(("main", "argv", "said"), [
    ("gestsim", ["--profile", "inmoov", "--board", "185"],
     "gestsim: error: --board 185: profile 'inmoov' has no board 185 (boards: 181 or "
     "'right', 183 or 'left')\n  hint: profile 'inmoov-six' has board 185: add --profile "
     "inmoov-six\n"),
    ("gestsim", ["--profile", "inmoov", "--board", "lft"],
     "gestsim: error: --board lft: profile 'inmoov' has no board 'lft' (boards: 181 or "
     "'right', 183 or 'left')\n  hint: did you mean 'left'?\n"),
    ("gestplay", ["dump", "--port", "183=sim://"],
     "gestplay: error: --port 183=sim://: profile 'rhand' has no board 183 (boards: 181 or "
     "'right hand')\n  hint: profiles inmoov, inmoov-mrlcomm, inmoov-six and lhand have "
     "board 183: add --profile with one of them (--profile inmoov)\n"),
    ("gestplay", ["dump", "--port", "left=sim://"],
     "gestplay: error: --port left=sim://: profile 'rhand' has no board 'left' (boards: 181 "
     "or 'right hand')\n  hint: profiles inmoov and inmoov-mrlcomm have board 'left': add "
     "--profile with one of them (--profile inmoov)\n"),
])
def test_a_board_the_profile_does_not_have_lists_its_boards_and_who_has_it(main, argv,
                                                                             said, capsys):
    from inmoov_dsl.cli import gestsim

    assert {"gestsim": gestsim, "gestplay": gestplay}[main].main(argv) == 1
    assert capsys.readouterr().err == said


def test_a_play_that_finds_the_board_in_its_pose_says_so(capsys):
    """``gestplay peace --port sim://`` twice: the second finds the virtual board in the
    peace pose, which its one byte says; a gesture that moves no servo does not."""
    assert gestplay.main(["peace", "--port", "sim://"]) == 0
    assert capsys.readouterr().out.startswith("played peace: 0.70 s, 201 bytes, worst ")
    assert gestplay.main(["peace", "--port", "sim://"]) == 0
    assert capsys.readouterr().out.startswith(
        "played peace: 0.70 s, 1 byte (the board already held its pose), worst lateness ")
    assert gestplay.main(["hello", "--port", "sim://"]) == 0
    capsys.readouterr()
    assert gestplay.main(["hello", "--port", "sim://"]) == 0
    assert "(the boards already held its pose)" not in capsys.readouterr().out  # it moves


def test_a_gesture_that_moves_nothing_is_not_said_to_be_held(tmp_path, capsys):
    still = tmp_path / "still.gest"
    still.write_text("still: wait 0.1s\n")
    assert gestplay.main([str(still), "--port", "sim://"]) == 0
    assert capsys.readouterr().out.startswith("played still: 0.10 s, 1 byte, worst ")


def test_the_live_preview_s_address_is_last_on_its_line(tmp_path):
    """A terminal that makes links of addresses takes nothing after it (no ``;``)."""
    import re

    from test_web import Lines, need_viser

    need_viser()
    path = tmp_path / "w.gest"
    path.write_text("w: index 90 over 0.5s\n")
    proc = subprocess.Popen([sys.executable, "-m", "inmoov_dsl.cli.gestc", "preview", "--live",
                             str(path), "--no-open"], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE)
    try:
        line = Lines(proc.stderr).until(r"^(gestc: the live preview .*)$", 60)
        assert re.fullmatch(rf"gestc: the live preview of {re.escape(str(path))} \(Ctrl-C "
                            r"stops\) at http://127\.0\.0\.1:\d+/", line), line
    finally:
        proc.terminate()
        proc.communicate(timeout=30)


@pytest.mark.parametrize("argv", [["dump"], ["peace"]])
def test_a_trapped_mega_s_wait_is_said_once_while_it_happens(virtual_clock, capsys, argv):
    """A Mega whose bootloader another program's byte trapped answers after 9 s of
    silence: what is waited for is said once, on standard error, as the wait starts."""
    from test_boot import MEGA, mega, probing_at_once

    from inmoov_dsl.wire.ports import open_port

    kind = mega(MEGA)
    port = open_port(MEGA, kind.board.baud)
    probing_at_once(port, virtual_clock.now, virtual_clock.sleep)  # trapped
    port.close()
    assert gestplay.main([*argv, "--profile", "rhand-mrlcomm", "--port", MEGA]) == 0
    where = MEGA if argv == ["dump"] else f"board 181 on {MEGA}"
    assert capsys.readouterr().err.splitlines()[0] == (
        f"gestplay: {where}: nothing answered yet: a Mega's bootloader that took a byte "
        "for its own starts the sketch after 9 s of silence; waiting for it")


@pytest.mark.parametrize(("profile", "said"), [
    ("rhand", "no DUMP reply from loop://\n  hint: is the board powered, and at this baud?"),
    ("rhand-maestro", "no answer to Get Position from loop://\n  hint: is the Maestro "
     "powered, and this its Command Port (the first of its two), in serial mode USB Dual "
     "Port?"),
    ("rhand-mrlcomm", "no board info (getBoardInfo) from loop://\n  hint: is the board "
     "running MrlComm, and at this baud?"),
])
def test_a_board_that_does_not_tell_its_pose_is_told_in_its_kind_s_words(profile, said,
                                                                         capsys):
    assert gestplay.main(["dump", "--profile", profile, "--port", "loop://"]) == 1
    assert capsys.readouterr().err == f"gestplay: error: {said}\n"


def test_list_long_says_a_gesture_s_first_sentence_whole(tmp_path, capsys, monkeypatch):
    """A description whose first sentence goes on over the comment's next line is shown
    whole, not cut where the line ends; on a terminal it wraps under its column, at
    word ends."""
    from inmoov_dsl.cli import gestc

    (tmp_path / "mine.gest").write_text(
        "# tap2: the index taps twice, as if on a screen, the second tap a\n"
        "# little lighter than the first. Then it rests.\ntap2: index 60 over 250ms\n")
    assert gestc.main(["list", "--long", "--lib", str(tmp_path)]) == 0
    tap = next(line for line in capsys.readouterr().out.splitlines()
               if line.startswith("tap2 "))
    assert tap.split(None, 1)[1] == ("the index taps twice, as if on a screen, the second "
                                     "tap a little lighter than the first.  (mine.gest:3, "
                                     "for rhand)")
    monkeypatch.setattr(sys.stdout, "isatty", lambda: True)
    monkeypatch.setattr("shutil.get_terminal_size", lambda: os.terminal_size((60, 24)))
    assert gestc.main(["list", "--long", "--lib", str(tmp_path)]) == 0
    out = capsys.readouterr().out.splitlines()
    at = next(k for k, line in enumerate(out) if line.startswith("tap2 "))
    column = len("look_around  ")  # the longest name, and two spaces
    assert all(len(line) <= 60 for line in out)
    assert out[at:at + 3] == [
        "tap2         the index taps twice, as if on a screen, the",
        "             second tap a little lighter than the first.",
        "             (mine.gest:3, for rhand)"]
    assert out[at + 1][:column].isspace() and not out[at + 1][column].isspace()


@pytest.mark.parametrize(("make", "why"), [("folder", "it is a folder, not a file"),
                                           ("empty", "it is empty")])
def test_a_token_file_that_is_no_token_says_why(tmp_path, capsys, make, why):
    token = tmp_path / "token"
    token.mkdir() if make == "folder" else token.write_text("")
    assert gestplay.main(["serve", "--port", "sim://", "--token-file", str(token)]) == 1
    assert capsys.readouterr().err == (
        f"gestplay: error: cannot read the token from {token}: {why}\n"
        "  hint: give a file whose first line is the token\n")
