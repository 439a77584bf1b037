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
