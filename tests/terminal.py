"""A program at a real pseudo-terminal, for the tests that press keys."""

from __future__ import annotations

import os
import select
import subprocess
import termios
import time

import serial


class AtTerminal:
    """``argv`` running with a pseudo-terminal as its stdin, stdout and stderr."""

    def __init__(self, argv: list[str], cwd=None):
        self.master, slave = os.openpty()
        self.proc = subprocess.Popen(argv, stdin=slave, stdout=slave, stderr=slave, cwd=cwd)
        os.close(slave)
        self.out = b""

    def read_until(self, text: bytes, timeout: float = 20) -> None:
        """Read the screen until ``text`` appears (or the program ends, or time is up)."""
        deadline = time.monotonic() + timeout
        while text not in self.out and (left := deadline - time.monotonic()) > 0:
            if not select.select([self.master], [], [], min(left, 0.5))[0]:
                continue  # nothing yet: the deadline holds even when the program is quiet
            try:
                self.out += os.read(self.master, 4096)
            except OSError:  # the program has ended
                break

    def press(self, *keys: str, pause: float = 0.03) -> None:
        for key in keys:
            os.write(self.master, key.encode())
            time.sleep(pause)

    def finish(self) -> tuple[int, str]:
        """Read until the program ends: (exit status, everything it wrote)."""
        self.read_until(b"\xff never")
        os.close(self.master)
        return self.proc.wait(timeout=20), self.out.decode(errors="replace")


def listen_as_a_plain_program(path: str, hold: float = 0.55) -> tuple[serial.Serial, bytes]:
    """Open ``path`` as a program opens a real serial port (HUPCL set: DTR drops when it
    closes; a pty does not set it by itself) and listen ``hold`` s without a word: a
    board that reset says WAIT when it has booted, one that did not says nothing. What
    came while no program had the port open is dropped, as a serial driver drops it (a
    pty keeps it: a board simulated on a busy machine answers the last program late)."""
    port = serial.Serial(path, 9600, timeout=0)
    attrs = termios.tcgetattr(port.fileno())
    attrs[2] |= termios.HUPCL
    termios.tcsetattr(port.fileno(), termios.TCSANOW, attrs)
    port.reset_input_buffer()
    time.sleep(hold)
    return port, port.read(100)
