"""gestplay repl as a timeline: typed lines at given times, the virtual board on the
same clock. No real time passes: the REPL's clock, its sleep and its wait for a line
are the test's."""

import os
import select
import signal
import subprocess
import sys
import time

import numpy as np
import pytest
from terminal import AtTerminal

from inmoov_dsl.boards.rig.core import BoardCore
from inmoov_dsl.cli.gestplay.repl import repl
from inmoov_dsl.profiles.profile import load_profile
from inmoov_dsl.wire.player import Link
from inmoov_dsl.wire.sim import VirtualBoard

RHAND = load_profile("rhand")
INDEX_ID = RHAND.servos[RHAND.index("index")].id


class Timeline:
    """A clock that moves only when the REPL waits, and a typist on it."""

    def __init__(self, script: list[tuple[float, str]]):
        self.t = 0.0
        self.script = [*script, (max((t for t, _ in script), default=0.0), None)]
        self.waits = 0

    def now(self) -> float:
        return self.t

    def sleep(self, seconds: float) -> None:
        """Time passes; a sleep of nothing spins for a tenth of a millisecond."""
        self.t += max(seconds, 1e-4)

    def next_line(self, timeout: float):
        """The next line if it is typed within ``timeout``; else False, that much later
        (a wait with nothing left spins: a tenth of a millisecond)."""
        self.waits += 1
        if self.script and self.script[0][0] <= self.t + max(timeout, 0.0):
            at, line = self.script.pop(0)
            self.t = max(self.t, at)
            return line
        self.t += max(timeout, 1e-4)
        return False


class ClockedPort:
    """The virtual board as a port on the timeline's clock; ``discards``: it drops
    what it holds unsent when asked (False: a USB adapter that keeps it)."""

    def __init__(self, board: VirtualBoard, timeline: Timeline, discards: bool = True):
        self.board, self.timeline, self.discards = board, timeline, discards

    def write(self, data: bytes) -> int:
        self.board.write(data, self.timeline.t)
        return len(data)

    def reset_output_buffer(self) -> None:
        if self.discards:
            self.board.discard(self.timeline.t)

    def read(self, size: int = 1) -> bytes:
        return self.board.read(self.timeline.t)[:size]


def run_repl(script, take_over=True, status=0, timeline=None):
    """Play timed lines [(seconds, line)] into the REPL; the board and its log."""
    timeline = timeline or Timeline(script)
    board = VirtualBoard(BoardCore.from_profile(RHAND, RHAND.boards[0]), 9600)
    link = Link(181, ClockedPort(board, timeline), "timeline")
    assert repl([link], RHAND, {}, timeline.next_line, take_over, now=timeline.now,
                sleep=timeline.sleep) == status
    board.advance(timeline.t + 1)
    return board, board.log


def test_the_repl_takes_over_on_the_board_without_a_jump():
    board, log = run_repl([(0.0, "index 90 over 0.6s"), (0.3, "index 180")])
    index = [(t, w.value) for t, w in log if w.id == INDEX_ID]
    values = [v for _, v in index]
    assert values[-1] == 180 and board.positions()[INDEX_ID] == 180
    assert values == sorted(values)  # never went back
    vmax = RHAND.servos[RHAND.index("index")].max_velocity
    gaps = np.diff([t for t, _ in index])
    assert np.all(np.diff(values) <= vmax * np.maximum(gaps, 0.02) + 1)  # no jump
    # around the takeover (0.3 s) the finger keeps moving: every frame a new value (the
    # take-over sends once more the value that may not have arrived: the same value)
    around = [v for t, v in index if 0.2 < t < 0.5]
    assert len(around) >= 12 and len(set(around)) >= len(around) - 1
    # before the takeover the first move was on its way to 90, not yet there
    before = [v for t, v in index if t < 0.3]
    assert 0 < before[-1] < 90


def test_the_repl_runs_library_gestures_and_reports_errors(capsys):
    board, _ = run_repl([(0.0, "indx 3"), (0.0, "peace"), (0.0, "where")])
    out, err = capsys.readouterr()
    assert "<repl>:1:1: error: unknown servo or group 'indx'" in err
    assert "hint: did you mean 'index'?" in err
    assert out.startswith("wrist 0  thumb 0  index 0")
    assert board.positions() == {0: 0, 1: 180, 2: 0, 3: 0, 4: 180, 5: 180}


@pytest.mark.parametrize(("take_over", "peak"), [(False, 90), (True, 0)])
def test_typed_lines_take_over_and_scripts_wait(take_over, peak):
    board, log = run_repl([(0.0, "index 90 over 0.3s"), (0.0, "index 0")], take_over)
    index = [w.value for _, w in log if w.id == INDEX_ID]
    assert max(index, default=0) == peak and board.positions()[INDEX_ID] == 0


def test_a_wait_typed_while_the_hand_moves_starts_when_the_move_ends():
    board, log = run_repl([(0.0, "index 90 over 0.4s"), (0.1, "wait 1s"), (0.2, "index 0")],
                          take_over=False)
    index = [(t, w.value) for t, w in log if w.id == INDEX_ID]
    reached = next(t for t, v in index if v == 90)
    leaves = next(t for t, v in index if t > reached and v < 90)
    assert 1.0 <= leaves - reached < 1.1  # the wait, after the move, before the next one
    assert board.positions()[INDEX_ID] == 0


PEACE = "wrist 0  thumb 180  index 0  middle 0  ring 180  pinky 180"


class Printed:
    """Standard output, each write with the timeline's time."""

    def __init__(self, timeline: Timeline):
        self.timeline, self.lines = timeline, []

    def write(self, text: str) -> int:
        self.lines += [(self.timeline.t, line) for line in text.splitlines() if line]
        return len(text)

    def flush(self) -> None:
        pass


def test_in_a_script_where_answers_once_the_steps_before_it_are_done(monkeypatch):
    timeline = Timeline([(0.0, "index 90"), (0.0, "wait 1s"), (0.0, "where"),
                         (0.0, "peace"), (0.0, "where")])
    printed = Printed(timeline)
    monkeypatch.setattr("sys.stdout", printed)
    _, log = run_repl(None, take_over=False, timeline=timeline)
    (t1, first), (_, second) = printed.lines
    assert first == "wrist 0  thumb 0  index 90  middle 0  ring 0  pinky 0"
    assert second == PEACE
    reached = next(t for t, w in log if w.id == INDEX_ID and w.value == 90)
    assert t1 >= reached + 1.0  # after the wait too


def test_at_a_terminal_where_answers_at_once(monkeypatch):
    timeline = Timeline([(0.0, "index 90 over 1s"), (0.5, "where")])
    printed = Printed(timeline)
    monkeypatch.setattr("sys.stdout", printed)
    run_repl(None, timeline=timeline)
    ((t, answer),) = printed.lines
    index = int(answer.split()[5])
    assert t == pytest.approx(0.5, abs=0.01) and 0 < index < 90  # on its way


@pytest.mark.parametrize(("take_over", "file"), [(False, "<stdin>"), (True, "<repl>")])
def test_errors_name_the_line_of_the_input_they_are_on(capsys, take_over, file):
    run_repl([(0.0, "index 90"), (0.1, ""), (0.2, "# a comment"), (0.3, "where"),
              (0.4, "indx 3")], take_over, status=int(not take_over))
    assert f"{file}:5:1: error: unknown servo or group 'indx'" in capsys.readouterr().err


@pytest.mark.parametrize(("take_over", "status"), [(False, 1), (True, 0)])
def test_a_script_with_a_failing_line_carries_on_and_exits_1(capsys, take_over, status):
    board, _ = run_repl([(0.0, "index 90"), (0.0, "indx 3"), (0.0, "middle 45")], take_over,
                        status)
    assert board.positions()[RHAND.servos[RHAND.index("middle")].id] == 45  # carried on
    assert "error: unknown servo or group 'indx'" in capsys.readouterr().err


# -- gestplay repl as a person or a script uses it --------------------------------------
def test_gestplay_repl_reads_steps_from_a_pipe():
    done = subprocess.run([sys.executable, "-m", "inmoov_dsl.cli.gestplay", "repl", "--port",
                           "sim://?boot=0.05"], input="ring 45 over 0.2s\nwhere\nquit\n",
                          capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("wrist 0  thumb 0  index 0  middle 0  ring 45  pinky 0")


def test_a_piped_script_says_where_at_its_point_names_lines_and_fails():
    done = subprocess.run([sys.executable, "-m", "inmoov_dsl.cli.gestplay", "repl", "--port",
                           "sim://?boot=0"],
                          input="index 90\nwait 1s\nwhere\npeace\nindx 3\nwhere\n",
                          capture_output=True, text=True, timeout=60)
    assert done.stdout.splitlines() == [
        "wrist 0  thumb 0  index 90  middle 0  ring 0  pinky 0", PEACE]
    assert done.stderr.startswith("<stdin>:5:1: error: unknown servo or group 'indx'")
    assert done.returncode == 1


def test_a_script_saved_by_notepad_starts_with_its_first_step():
    done = subprocess.run([sys.executable, "-m", "inmoov_dsl.cli.gestplay", "repl", "--port",
                           "sim://?boot=0"], input=b"\xef\xbb\xbfindex 90\r\nwhere\r\n",
                          capture_output=True, timeout=60)
    assert done.returncode == 0, done.stderr
    assert done.stdout.decode().splitlines() == [
        "wrist 0  thumb 0  index 90  middle 0  ring 0  pinky 0"]


@pytest.mark.skipif(not hasattr(os, "openpty"), reason="pseudo-terminals are POSIX")
def test_at_a_terminal_each_reply_comes_before_the_next_prompt():
    term = AtTerminal([sys.executable, "-m", "inmoov_dsl.cli.gestplay", "repl", "--port",
                       "sim://?boot=0"])
    term.read_until(b"gest> ")
    term.press("indx 3\r")
    term.read_until(b"did you mean 'index'?")
    term.press("where\r")
    term.read_until(b"pinky 0")
    term.press("\x04")
    code, screen = term.finish()
    assert code == 0, screen
    typed, answer = screen.split("gest> indx 3", 1)[1], screen.split("gest> where", 1)[1]
    assert typed.index("error: unknown servo or group 'indx'") < typed.index("gest> ")
    assert answer.index("wrist 0  thumb 0") < answer.index("gest> ")


@pytest.mark.skipif(not hasattr(os, "openpty"), reason="pseudo-terminals are POSIX")
def test_keys_typed_after_a_ctrl_c_are_left_for_the_shell():
    import termios

    master, slave = os.openpty()  # the test keeps the terminal open, as the shell does
    proc = subprocess.Popen([sys.executable, "-m", "inmoov_dsl.cli.gestplay", "repl",
                             "--port", "sim://?boot=0"], stdin=slave, stdout=slave,
                            stderr=slave)
    screen = b""

    def read_until(text: bytes) -> None:
        """Read the screen until ``text`` shows, or the program ends (or 20 s pass)."""
        nonlocal screen
        deadline = time.monotonic() + 20
        while text not in screen and proc.poll() is None and time.monotonic() < deadline:
            if select.select([master], [], [], 0.1)[0]:
                screen += os.read(master, 4096)

    try:
        read_until(b"gest> ")
        proc.send_signal(signal.SIGINT)
        read_until(b"Ctrl-C again to relax it")
        os.write(master, b"echo typed\n")  # within the second after the Ctrl-C
        read_until(b"\xff never")
        assert proc.wait(timeout=20) == 130, screen
        modes = termios.tcgetattr(slave)[3]
        assert modes & termios.ICANON and modes & termios.ECHO  # the terminal as it was
        os.set_blocking(slave, False)
        try:
            left = os.read(slave, 100)
        except BlockingIOError:
            left = b""
        assert left == b"echo typed\n"  # what the shell reads next
    finally:
        if proc.poll() is None:
            proc.kill()
        os.close(master)
        os.close(slave)
