"""Stopping gestplay in the middle of a gesture on a board behind a pty that logs each
byte's start on the wire (gestsim, or the firmware image in simavr), and what the board
got after the signal. Shared by the player's tests and the wire clock's.

What these tests prove does not depend on how busy the machine is: the player ends
with the status and the line a signal calls for, the board's last byte is a CANCEL, and
the hand stopped mid-gesture. How soon the CANCEL arrives depends on when each process
ran; how many bytes of the gesture still reach the board after the signal does not, but
counting them takes a board whose own time is known at the signal: the image in simavr
sends the signal itself (``simboard --control``), at a time on its own clock, and its log
is that clock (``Harness``, ``stop_on_board_time``). On the player's virtual clock the
player sends at most the horizon and then the CANCEL (test_player.py), and
benchmarks/stop.py measures it at a real board (docs/benchmarks.md).
"""

from __future__ import annotations

import queue
import subprocess
import sys
import threading
import time
from pathlib import Path

from inmoov_dsl.protocol import Signal

#: s from an event to what a program does about it that a machine with both cores busy
#: meets (the figures themselves: benchmarks/)
PROMPT = 0.5
SETTLE = 10.0  #: s; the longest a test waits for something the board is sure to log


def received(log: Path) -> tuple[list[float], list[int]]:
    """The times and bytes of the log (``<seconds> <byte>`` per line)."""
    rows = [line.split() for line in log.read_text().splitlines() if line.strip()]
    rows = [row for row in rows if len(row) == 2]  # a line being written: not yet
    return [float(t) for t, _ in rows], [int(b) for _, b in rows]


def wait_for(condition, what: str, timeout: float = SETTLE) -> None:
    """Poll ``condition()`` until it holds (a deadline, not a sleep standing in for
    it)."""
    deadline = time.monotonic() + timeout
    while not condition():
        assert time.monotonic() < deadline, f"{what}: not within {timeout} s"
        time.sleep(0.02)


def first_pair(log: Path) -> float:
    """When the first pair's ID (the thumb, 1) started on the board's wire, in the log's
    seconds (waited for: the player is starting)."""
    wait_for(lambda: 1 in received(log)[1], "the first pair", 60)
    times, data = received(log)
    return times[data.index(1)]


def stop_mid_gesture(log: Path, argv: list[str], signum: int, into: float
                     ) -> tuple[subprocess.CompletedProcess, int, list[float], list[int]]:
    """Play ``gestplay ARGV``, send ``signum`` once the board has logged a byte ``into``
    s (in its time) after its first pair's ID (the thumb, 1), wait for it to end and for
    the board to log the CANCEL: (the player's ending, how many bytes the board had
    logged when it was signalled, the log's times and bytes). A count, not a time: the
    simulated board stamps bytes left waiting in the pty from when they could have begun,
    which a busy machine makes earlier than they were written."""
    player = subprocess.Popen([sys.executable, "-m", "inmoov_dsl.cli.gestplay", *argv],
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        first = first_pair(log)
        # the gesture is well under way at the board (it lasts longer than this)
        wait_for(lambda: received(log)[0][-1] >= first + into, "the gesture under way",
                 into + SETTLE)
        signalled = len(received(log)[1])
        player.send_signal(signum)
        out, err = player.communicate(timeout=SETTLE)
    finally:
        if player.poll() is None:
            player.kill()
            player.wait()
    ended = subprocess.CompletedProcess(argv, player.returncode, out, err)
    wait_for(ended_in_cancel(log), "the CANCEL at the board, then nothing")
    times, data = received(log)
    return ended, signalled, times, data


def ended_in_cancel(log: Path, quiet: float = 0.5):
    """A condition for ``wait_for``: the board's last byte is a CANCEL, and nothing has
    come for ``quiet`` s. A run's filler is the CANCEL byte too: until the port has given
    the board all it held before the player's CANCEL, a filler can be the last byte."""
    seen = {"count": -1, "since": 0.0}

    def condition() -> bool:
        data, now = received(log)[1], time.monotonic()
        if len(data) != seen["count"]:
            seen["count"], seen["since"] = len(data), now
        return data[-1:] == [Signal.CANCEL] and now - seen["since"] >= quiet
    return condition


def after_signal(times: list[float], data: list[int], signalled: int
                 ) -> list[tuple[float, int]]:
    """What reached the board after the signal (``signalled``: the bytes it had logged
    then): it ends in the CANCEL."""
    after = list(zip(times, data, strict=True))[signalled:]
    assert after and after[-1][1] == Signal.CANCEL, (signalled, len(data), after[-8:])
    return after


class Harness:
    """simboard serving an image on a pty with ``--control``: orders on its stdin, what
    it says on its stdout (read by a thread: a line each, in order)."""

    def __init__(self, proc: subprocess.Popen):
        self.proc = proc
        self.path = proc.stdout.readline().strip()  # the pty, said first
        self._lines: queue.Queue[str] = queue.Queue()
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self) -> None:
        for line in self.proc.stdout:
            self._lines.put(line)

    def order(self, line: str) -> None:
        """Send one order (``signal SIGNUM PID [SECONDS]``)."""
        self.proc.stdin.write(line + "\n")
        self.proc.stdin.flush()

    def said(self, word: str, timeout: float = SETTLE) -> list[str]:
        """The next line it says that starts with ``word``, split (lines before it are
        dropped)."""
        deadline = time.monotonic() + timeout
        while True:
            left = deadline - time.monotonic()
            assert left > 0, f"simboard said no {word!r} within {timeout} s"
            try:
                line = self._lines.get(timeout=left)
            except queue.Empty:
                continue
            if line.split()[:1] == [word]:
                return line.split()


def stop_on_board_time(harness: Harness, log: Path, argv: list[str], signum: int,
                       into: float) -> tuple[subprocess.CompletedProcess, float, list[float],
                                             list[int]]:
    """Play ``gestplay ARGV`` to the image behind ``harness``, which sends ``signum``
    ``into`` s after its first pair's ID (the thumb, 1) started on the board's wire; wait
    for the player to end and for the harness to have taken all it wrote: (the player's
    ending, when it was signalled, the log's times and bytes), every time the board's
    own (the log's seconds)."""
    player = subprocess.Popen([sys.executable, "-m", "inmoov_dsl.cli.gestplay", *argv],
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        first = first_pair(log)
        harness.order(f"signal {int(signum)} {player.pid} {first + into:.6f}")
        signalled = float(harness.said("signalled", into + SETTLE)[1])
        out, err = player.communicate(timeout=SETTLE)
    finally:
        if player.poll() is None:
            player.kill()
            player.wait()
    ended = subprocess.CompletedProcess(argv, player.returncode, out, err)
    harness.said("closed")  # the port closed, and every byte written was taken and logged
    times, data = received(log)
    return ended, signalled, times, data
