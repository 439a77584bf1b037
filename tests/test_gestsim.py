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
