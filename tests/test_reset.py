"""Opening a port without moving the hand: the virtual boards keep their pose across a
reset as the firmware does (EEPROM), reset only when DTR rises, the player leaves DTR
up; and RELAX, from `gestplay relax` and from a second Ctrl-C."""

import os
import signal
import subprocess
import sys
import termios
import time
from pathlib import Path

import pytest
import serial
from stopping import received, wait_for
from terminal import AtTerminal, listen_as_a_plain_program

from inmoov_dsl import load_profile
from inmoov_dsl.boards.rig.core import BoardCore
from inmoov_dsl.cli import gestplay
from inmoov_dsl.protocol import POSE_SETTLE
from inmoov_dsl.wire.ports import leave_dtr_up, open_port
from inmoov_dsl.wire.ready import ask_dump, wait_ready
from inmoov_dsl.wire.sim import VirtualBoard, settled

POSIX = pytest.mark.skipif(not hasattr(os, "openpty"), reason="pseudo-terminals are POSIX")
REST = [0, 0, 0, 0, 0, 0]


def board(stored=None):
    rhand = load_profile("rhand")
    return VirtualBoard(BoardCore.from_profile(rhand, rhand.boards[0]), 9600, stored=stored)


def send(b, data, at):
    b.write(bytes(data), at)
    b.read(at + 0.1)


# -- the virtual board's memory ------------------------------------------------------------
def test_a_pose_is_stored_once_it_has_held_for_a_second():
    b = board()
    send(b, [255, 2, 90, 3, 45], 1.0)
    b.advance(1.0 + POSE_SETTLE * 0.9)
    assert b.stored is None  # not settled yet
    b.advance(1.2 + POSE_SETTLE)
    assert b.stored == [0, 0, 90, 45, 0, 0] and b.records == 1
    send(b, [255, 2, 90], 5.0)  # the same pose again: nothing written
    b.advance(10.0)
    assert b.records == 1


def test_a_reset_starts_from_the_stored_pose_and_loses_an_unsettled_one():
    b = board()
    send(b, [255, 2, 90], 1.0)
    b.advance(3.0)  # settled
    send(b, [255, 2, 10, 4, 20], 4.0)  # moved, and reset 0.2 s later: not stored
    b.reset(4.3, boot=0.5)
    assert b.core.values == [0, 0, 90, 0, 0, 0] and b.resets == 1
    send(b, [255, 5, 5], 4.4)  # the bootloader swallows it
    assert b.swallowed == 3 and b.core.values == [0, 0, 90, 0, 0, 0]
    assert b.read(4.9) == bytes([254])  # booted: WAIT


def test_a_new_board_and_one_without_a_stored_pose_start_at_rest():
    b = board()
    send(b, [255, 2, 90], 1.0)
    b.reset(1.2, boot=0.1)
    assert b.core.values == REST
    assert board(stored=[1, 2, 3, 4, 5, 6]).core.values == [1, 2, 3, 4, 5, 6]


# -- sim:// and DTR ----------------------------------------------------------------------
def test_a_board_that_settles_after_its_port_closed_has_stored_that_pose():
    b = board()
    b.write(bytes([255, 1, 90]), 0.0)
    assert settled(b) == [0, 90, 0, 0, 0, 0]
    assert b.stored is None and b.core.values == REST  # the board itself has not moved on


def gestplay_cmd(*argv, env=None):
    return subprocess.run([sys.executable, "-m", "inmoov_dsl.cli.gestplay", *argv],
                          capture_output=True, text=True, timeout=120,
                          env={**os.environ, **(env or {})})


def dumped(done):
    """servo name -> value, from gestplay dump's lines."""
    assert done.returncode == 0, done.stderr
    return {w[0]: int(w[-1]) for w in map(str.split, done.stdout.splitlines()[1:])}


PEACE = {"wrist": 0, "thumb": 180, "index": 0, "middle": 0, "ring": 180, "pinky": 180}


def test_sim_remembers_its_pose_from_one_program_to_the_next():
    state = os.environ["INMOOV_DSL_STATE"]
    assert gestplay_cmd("peace", "--port", "sim://").returncode == 0
    assert dumped(gestplay_cmd("dump", "--port", "sim://")) == PEACE
    (kept,) = Path(state).glob("sim/*.json")
    assert kept.name == "rhand-181.json"
    if os.name == "posix":
        assert kept.stat().st_mode & 0o077 == 0 and kept.parent.stat().st_mode & 0o077 == 0
    # the next program plans from there: nothing left to move
    again = gestplay_cmd("peace", "--port", "sim://")
    assert again.stdout.startswith("played peace: 0.70 s, ")
    fresh = dumped(gestplay_cmd("dump", "--port", "sim://?fresh"))
    assert fresh == dict.fromkeys(PEACE, 0)
    assert dumped(gestplay_cmd("dump", "--port", "sim://")) == fresh  # a new board


def test_each_board_of_a_profile_remembers_its_own_pose():
    assert gestplay_cmd("hello", "--profile", "inmoov-six", "--port", "sim://").returncode == 0
    head = dumped(gestplay_cmd("dump", "--profile", "inmoov-six", "--port", "184=sim://"))
    assert head["neck"] == 90 and set(head) == {"neck", "rothead", "jaw", "eye_x", "eye_y"}
    assert dumped(gestplay_cmd("dump", "--port", "sim://")) == dict.fromkeys(PEACE, 0)


@pytest.mark.parametrize("text", ["", "{", "[]", '{"servos": [0, 1, 2, 3, 4, 5], "pose": '
                                  '[0, 0, 0, 0, 0, 999]}', '{"servos": [9], "pose": [1]}',
                                  "\x00" * 5000])
def test_a_memory_that_cannot_be_read_is_a_new_board(text):
    kept = Path(os.environ["INMOOV_DSL_STATE"]) / "sim"
    kept.mkdir(mode=0o700)
    (kept / "rhand-181.json").write_text(text)
    (kept / "rhand-181.json").chmod(0o600)
    done = gestplay_cmd("dump", "--port", "sim://")
    assert dumped(done) == dict.fromkeys(PEACE, 0) and "Traceback" not in done.stderr


@POSIX
def test_a_memory_others_could_write_is_not_read():
    kept = Path(os.environ["INMOOV_DSL_STATE"]) / "sim"
    kept.mkdir(mode=0o700)
    for mode, pose in ((0o666, 0), (0o600, 9)):
        (kept / "rhand-181.json").write_text('{"servos": [0, 1, 2, 3, 4, 5], '
                                             '"pose": [9, 9, 9, 9, 9, 9]}')
        (kept / "rhand-181.json").chmod(mode)
        assert dumped(gestplay_cmd("dump", "--port", "sim://")) == dict.fromkeys(PEACE, pose)


def test_sim_resets_only_when_an_open_raises_dtr():
    url = "sim://rhand?boot=0.05"
    raw = serial.serial_for_url(url, 9600, timeout=0)  # HUPCL set: DTR drops on close
    first = raw.board
    assert first.resets == 0  # powered up
    wait_ready(raw)
    raw.write(bytes([255, 2, 90]))
    time.sleep(0.05)
    raw.close()
    port = open_port(url, 9600)  # DTR rose: a reset, from the rest pose (90 never settled)
    assert port.board is first and first.resets == 1
    assert ask_dump(port, 181) is None  # the bootloader is still running...
    assert wait_ready(port)
    assert ask_dump(port, 181) == dict.fromkeys(range(6), 0)
    port.write(bytes([255, 3, 120]))
    time.sleep(0.05)
    port.close()  # HUPCL cleared by open_port: DTR stays up
    again = open_port(url, 9600)
    assert again.board.resets == 1  # no reset
    assert ask_dump(again, 181)[3] == 120  # at once: no boot to wait for
    again.close()


def test_a_posix_port_is_left_with_dtr_up():
    master, slave = os.openpty()
    try:
        port = serial.Serial(os.ttyname(slave), 9600, timeout=0)
        attrs = termios.tcgetattr(port.fileno())
        attrs[2] |= termios.HUPCL  # a serial device's default
        termios.tcsetattr(port.fileno(), termios.TCSANOW, attrs)
        assert leave_dtr_up(port)
        assert not termios.tcgetattr(port.fileno())[2] & termios.HUPCL
        port.close()
        assert not leave_dtr_up(serial.serial_for_url("loop://"))  # no terminal: nothing
    finally:
        os.close(master)
        os.close(slave)


# -- gestsim on a pty -------------------------------------------------------------------
def gestplay_run(*argv, timeout=60):
    return subprocess.run([sys.executable, "-m", "inmoov_dsl.cli.gestplay", *argv],
                          capture_output=True, text=True, timeout=timeout)


def settle(log: Path, quiet: float = 0.3) -> None:
    """Wait until the board has logged nothing new for ``quiet`` s."""
    seen = [-1, time.monotonic()]

    def still() -> bool:
        size = log.stat().st_size if log.exists() else 0
        if size != seen[0]:
            seen[:] = [size, time.monotonic()]
        return time.monotonic() - seen[1] >= quiet

    wait_for(still, "the board reading what gestplay sent")


@POSIX
def test_gestplay_leaves_the_board_running_and_in_its_pose(gestsim):
    _, path, log = gestsim
    done = gestplay_run("rockon", "--port", path)
    assert done.returncode == 0, done.stderr
    settle(log)  # the board has read all gestplay sent (a simulated one may lag)
    # the next program finds the board as gestplay left it: no reset, the rockon pose
    port, heard = listen_as_a_plain_program(path)
    assert heard == b""
    assert ask_dump(port, 181) == {0: 0, 1: 0, 2: 0, 3: 180, 4: 180, 5: 0}
    time.sleep(POSE_SETTLE)  # the pose has held for a second: the board stores it
    port.close()  # this one drops DTR: the next open resets, from the pose stored
    time.sleep(0.1)
    port, heard = listen_as_a_plain_program(path)
    assert heard == bytes([254])
    assert ask_dump(port, 181) == {0: 0, 1: 0, 2: 0, 3: 180, 4: 180, 5: 0}
    port.close()


# -- relax ------------------------------------------------------------------------------
def test_gestplay_relax_stops_the_pulses_until_the_next_command(capsys):
    url = "sim://rhand?boot=0.05"
    assert gestplay.main(["relax", "--port", url]) == 0
    assert capsys.readouterr().out == (f"board 181 on {url}: relaxed, its servos are limp "
                                       "until the next command\n")
    port = open_port(url, 9600)
    assert ask_dump(port, 181) == dict.fromkeys(range(6), 0)  # it still answers
    assert port.board.core.relaxed and port.board.resets == 0
    port.write(bytes([255, 2, 90]))
    time.sleep(0.05)
    port.read(100)  # the board has read the command
    assert not port.board.core.relaxed  # driving again
    port.close()


@POSIX
def test_a_second_ctrl_c_relaxes_the_hand(gestsim):
    _, path, log = gestsim
    term = AtTerminal([sys.executable, "-m", "inmoov_dsl.cli.gestplay", "count", "--port",
                       path])
    term.read_until(b"step", timeout=30)  # playing
    term.proc.send_signal(signal.SIGINT)
    term.read_until(b"Ctrl-C again")
    term.proc.send_signal(signal.SIGINT)
    code, out = term.finish()
    assert code == 130, out
    assert "CANCEL sent, the hand holds its pose (Ctrl-C again to relax it)" in out
    assert "gestplay: relaxed: the servos are limp until the next command" in out
    assert "Traceback" not in out
    # CANCEL, then CANCEL RELAX CANCEL (the board logs them as it reads them)
    wait_for(lambda: received(log)[1][-4:] == [255, 255, 248, 255], "the relax at the board")


@POSIX
def test_one_ctrl_c_at_a_terminal_holds_the_pose(gestsim):
    _, path, log = gestsim
    term = AtTerminal([sys.executable, "-m", "inmoov_dsl.cli.gestplay", "count", "--port",
                       path])
    term.read_until(b"step", timeout=30)
    term.proc.send_signal(signal.SIGINT)
    code, out = term.finish()
    assert code == 130 and "relaxed" not in out
    wait_for(lambda: received(log)[1][-1:] == [255], "the CANCEL at the board")
    assert 248 not in received(log)[1]


@pytest.mark.parametrize("url, said", [
    ("sim://lhnd", ["cannot open port sim://lhnd: unknown profile 'lhnd'",
                    "hint: did you mean 'lhand'?"]),
    ("sim://?frsh", ["cannot open port sim://rhand?frsh&board=181: unknown option 'frsh'",
                     "hint: did you mean 'fresh'?"]),
    ("sim://rhand?board=9", ["cannot open port sim://rhand?board=9: profile 'rhand' has no "
                             "board 9", "hint: its boards: 181"]),
    ("sim://?boot=-1", ["cannot open port sim://rhand?boot=-1&board=181: boot=-1: not a "
                        "number of seconds from 0 to 60", "hint: boot=0.2 (an Uno's or a "
                        "Nano's)"])])
def test_a_sim_url_that_names_no_board_says_what_it_meant(url, said, capsys):
    assert gestplay.main(["peace", "--port", url]) == 1
    err = capsys.readouterr().err.splitlines()
    assert [line.strip() for line in err] == [f"gestplay: error: {said[0]}", said[1]]
