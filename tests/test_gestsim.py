"""gestsim as a user starts it: what it says it is, and what it draws before any
program has opened its port."""

import os
import select
import subprocess
import sys
import time

import pytest

POSIX = pytest.mark.skipif(not hasattr(os, "openpty"), reason="gestsim needs a pty")
WAIT = 20  #: s; the longest a test waits for gestsim to say or draw something
RHAND_SERVOS = ["wrist", "thumb", "index", "middle", "ring", "pinky"]


def gestsim(*argv, stderr=subprocess.PIPE):
    return subprocess.Popen([sys.executable, "-m", "inmoov_dsl.cli.gestsim", *argv],
                            stdout=subprocess.PIPE, stderr=stderr, text=True)


def stopped(proc):
    proc.kill()
    proc.wait()


@POSIX
def test_the_live_view_draws_the_rest_pose_at_once():
    """On a terminal, every servo's line is drawn before any program opens the port:
    the board is on the desk, at rest."""
    master, slave = os.openpty()
    proc = gestsim(stderr=slave)
    os.close(slave)
    screen = ""
    try:
        path = proc.stdout.readline().strip()
        assert path.startswith("/dev/")
        deadline = time.monotonic() + WAIT
        while not screen.rstrip().endswith("pinky        0") and time.monotonic() < deadline:
            if select.select([master], [], [], max(0.0, deadline - time.monotonic()))[0]:
                screen += os.read(master, 4096).decode(errors="replace")
    finally:
        stopped(proc)
        os.close(master)
    drawn = [line.replace("\x1b[2K", "").split() for line in screen.splitlines()[1:]]
    assert drawn == [[name, "0"] for name in RHAND_SERVOS]


@POSIX
@pytest.mark.parametrize("board", [[], ["--board", "182"]])
def test_a_glove_says_it_is_the_glove(board):
    proc = gestsim("--glove", "wiggle", "--quiet", *board)
    try:
        path = proc.stdout.readline().strip()
        said = [proc.stderr.readline(), proc.stderr.readline()]
    finally:
        stopped(proc)
    assert said == [f"gestsim: glove 182 (right flex glove) of profile 'rhand' on {path} at "
                    "9600 baud; Ctrl-C stops\n",
                    "gestsim: its fingers perform 'wiggle' from the moment the port opens\n"]


def test_a_glove_that_is_not_there_is_named():
    done = subprocess.run([sys.executable, "-m", "inmoov_dsl.cli.gestsim", "--glove",
                           "wiggle", "--board", "181"], capture_output=True, text=True,
                          timeout=WAIT)
    assert (done.returncode, done.stdout) == (1, "")
    assert done.stderr == ("gestsim: error: --board 181: profile 'rhand' has no glove 181\n"
                           "  hint: its gloves: 182 or 'right flex glove'\n")


@POSIX
def test_the_page_port_is_spelled_as_gestplay_serve_spells_it(monkeypatch, capsys):
    """``--http PORT`` (gestplay serve's option, a bare PORT on 127.0.0.1); the old
    ``--http-port N`` still works, hidden from --help, after a one-line notice."""
    from inmoov_dsl.cli import gestsim as tool

    monkeypatch.setitem(sys.modules, "viser", None)  # the page stops there: no pty
    viser = ("gestsim: error: gestsim --web needs viser and yourdfpy (viser is not "
             "installed)\n  hint: pip install 'inmoov-dsl[web]'\n")
    assert tool.main(["--web", "--http", "0", "--quiet"]) == 1
    assert capsys.readouterr() == ("", viser)
    assert tool.main(["--web", "--http-port", "0", "--quiet"]) == 1
    assert capsys.readouterr() == ("", "gestsim: warning: --http-port is deprecated: use "
                                   "--http 0\n" + viser)
    assert tool.main(["--web", "--http", "0.0.0.0:8080", "--quiet"]) == 1
    assert capsys.readouterr() == ("", (
        "gestsim: error: --http 0.0.0.0:8080: gestsim's page is for this computer only "
        "(127.0.0.1)\n  hint: --http 8080; gestplay serve serves the hand to other "
        "computers (docs/service.md)\n"))
    with pytest.raises(SystemExit):
        tool.main(["--help"])
    helped = capsys.readouterr().out
    assert "--http PORT" in helped and "--http-port" not in helped


# --- a profile of several boards: one gestsim is the whole robot

BOTH_ARMS = "robot inmoov\n\nboth:\n    r_omoplate 80, l_omoplate 80 over 1.5s\n"


def read_screen(master, screen: bytearray, until, timeout: float = WAIT) -> None:
    """Read what gestsim draws on ``master`` into ``screen`` until ``until(text)``."""
    deadline = time.monotonic() + timeout
    while not until(screen.decode(errors="replace")) and time.monotonic() < deadline:
        if select.select([master], [], [], max(0.0, deadline - time.monotonic()))[0]:
            screen.extend(os.read(master, 65536))


@POSIX
def test_one_gestsim_serves_every_board_of_the_profile(tmp_path):
    """``gestsim --profile inmoov`` is both Megas, each on a pty: the first line is what
    --port takes, a gesture of both arms plays there, and each board holds its arm."""
    proc = gestsim("--profile", "inmoov", "--quiet", "--boot", "0.1")
    try:
        ports = proc.stdout.readline().strip()
        said = [proc.stderr.readline() for _ in range(3)]
        (right, left) = [p.split("=")[1] for p in ports.split(",")]
        assert ports == f"181={right},183={left}" and right.startswith("/dev/")
        assert said == [
            f"gestsim: board 181 (right) of profile 'inmoov' on {right} at 115200 baud\n",
            f"gestsim: board 183 (left) of profile 'inmoov' on {left} at 115200 baud\n",
            f"gestsim: play to them all with --port {ports}; Ctrl-C stops\n"]
        (tmp_path / "both.gest").write_text(BOTH_ARMS)
        play = subprocess.run([sys.executable, "-m", "inmoov_dsl.cli.gestplay",
                               str(tmp_path / "both.gest"), "--port", ports],
                              capture_output=True, text=True, timeout=60)
        assert play.returncode == 0, play.stderr
        dump = subprocess.run([sys.executable, "-m", "inmoov_dsl.cli.gestplay", "dump",
                               "--profile", "inmoov", "--port", ports],
                              capture_output=True, text=True, timeout=60)
        assert dump.returncode == 0, dump.stderr
    finally:
        stopped(proc)
    held = {words[0]: words[-1] for line in dump.stdout.splitlines()
            if (words := line.split())[-2:-1] == ["value"]}
    assert (held["r_omoplate"], held["l_omoplate"], held["neck"]) == ("80", "80", "90")


@POSIX
def test_the_live_view_shows_every_board_s_servos():
    """On a terminal, the bars of both boards' servos, the right arm's and the head's,
    drawn at once."""
    master, slave = os.openpty()
    proc = gestsim("--profile", "inmoov", stderr=slave)
    os.close(slave)
    screen = bytearray()
    try:
        proc.stdout.readline()
        read_screen(master, screen, lambda text: "low_stom" in text)
    finally:
        stopped(proc)
        os.close(master)
    text = screen.decode(errors="replace")
    for servo in ("r_index", "r_omoplate", "l_omoplate", "neck", "jaw", "low_stom"):
        assert f"  {servo} " in text


@pytest.mark.parametrize("option", [["--log", "x.log"], ["--store", "wave"]])
def test_what_is_one_board_s_needs_board_on_a_profile_of_several(option, capsys):
    from inmoov_dsl.cli import gestsim as tool

    assert tool.main(["--profile", "inmoov", *option]) == 1
    assert capsys.readouterr() == ("", (
        f"gestsim: error: {option[0]} is for one board, and profile 'inmoov' has 2: "
        "gestsim is all of them unless --board names one\n"
        "  hint: add --board 181 (or 'right')\n"))


@POSIX
def test_after_a_whole_robot_play_the_hint_names_the_robot_it_played_on(capsys):
    """gestplay nod (body.gest, the head: board 183 alone) on the virtual robot: to
    watch it, one gestsim of the whole robot, and the same play with the ports it
    prints (the options played with kept)."""
    from inmoov_dsl.cli import gestplay

    assert gestplay.main(["nod", "--port", "sim://", "--allow-contact"]) == 0
    assert capsys.readouterr().err.splitlines()[-1] == (
        "to watch it move: run 'gestsim --view --profile inmoov' (or --web: in 3-D, in a "
        "browser) in another terminal: the whole robot, its 2 boards; then 'gestplay nod "
        "--allow-contact --port PORTS' with the PORTS it prints (181=PTY181,183=PTY183)")
