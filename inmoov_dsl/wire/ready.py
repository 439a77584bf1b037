"""Waiting for a board and asking it its pose: what every command that opens a board's
port does before anything moves (``wait_ready``, ``ask_dump``), with the clock and the
sleep passed in, so tests run them on a virtual clock.

A board that opening its port reset is listened to before a word is sent
(``hear_boot``): a Mega's bootloader takes any byte in its first 0.83 s for its own
and then waits seconds of silence before it starts the sketch.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Protocol

from .. import clock
from ..boards.arduino import Bootloader
from ..boards.base import Controller
from ..boards.rig import DumpReader
from ..clock import Clock, Sleep
from ..protocol import ASK_POSE, CANCEL_PENDING, Signal
from .ports import reset_on_open

#: s; the longest we ask a board that has booted (or did not reset) to answer: it answers
#: within milliseconds; a board simulated on a machine kept busy by other programs, later
READY_TIMEOUT = 3.0
PROBE = 0.1  #: s; while waiting for a board, send it a CANCEL this often
LISTEN = 0.01  #: s; how often a waiting player looks at what the board sent
#: s; the longest we wait for a DUMP reply: a board answers within milliseconds, one in
#: a simulator on a machine kept busy by other programs took over half a second
DUMP_TIMEOUT = 1.0
class Port(Protocol):
    """What the player needs of a serial port (pyserial's, or a virtual board's)."""

    def write(self, data: bytes) -> int | None:
        """Send ``data``."""

    def read(self, size: int = 1) -> bytes:
        """Up to ``size`` bytes that have come (a port that never blocks: maybe none)."""


def drain(port: Port) -> bytes:
    """Whatever the board has sent (WAIT bytes, mostly); raises if the link is gone."""
    return port.read(4096)


def wait_ready(port: Port, now: Clock | None = None, sleep: Sleep | None = None,
               timeout: float = READY_TIMEOUT, controller: Controller | None = None,
               heard: bytearray | None = None, bootloader: Bootloader | None = None,
               patient: bool = True, say: Callable[[str], None] | None = None) -> bool:
    """Wait until the board is ready: a rig (``controller`` None or a rig's) sends WAIT
    when it has booted or answers a CANCEL with WAIT; another kind answers its
    ``probe``. ``heard``: gets what the board answered. False if it never was.

    A board that opening its port reset is first only listened to (``hear_boot``).
    Then the probe goes out every PROBE s, for ``timeout`` s (a bootloader still running
    swallows it). A bootloader that a byte traps (the Mega's: another program's byte
    at the wrong moment, ours too when an open reset the board unseen) starts the
    sketch after enough silence: so, when nothing answered on a port with a DTR line,
    the board is left alone that long and asked again (unless not ``patient``: a link
    that may not answer at all, ``--blind``); ``say`` is told once what is waited for
    then (the bootloader's ``trapped``)."""
    now, sleep = now or clock.now, sleep or clock.sleep
    boot = bootloader or (controller.bootloader() if controller else None)
    question = controller.probe() if controller else CANCEL_PENDING
    answered = controller.ready if controller else (lambda a: Signal.WAIT in a)
    answer = bytearray(hear_boot(port, boot, now, sleep))
    ready = bool(answer) and answered(bytes(answer))
    if not ready:
        ready = ask(port, question, answered, answer, now() + timeout, now, sleep)
    if not ready and patient and boot is not None and boot.trap and \
            reset_on_open(port) is not None:
        if say is not None:
            say(boot.trapped())
        answer = bytearray(_hear(port, now() + boot.trap + PROBE, now, sleep))
        ready = bool(answer) and answered(bytes(answer)) or \
            ask(port, question, answered, answer, now() + timeout, now, sleep)
    if ready and heard is not None:
        heard += answer
    return ready


def hear_boot(port: Port, boot: Bootloader | None, now: Clock | None = None,
              sleep: Sleep | None = None) -> bytes:
    """If opening ``port`` reset the board (``ports.reset_on_open``), listen without a
    word until it speaks (a rig's WAIT, MrlComm's banner) or its bootloader ``boot``
    has had its time: a byte in that window keeps a Mega's bootloader from starting the
    sketch. What it said first."""
    now, sleep = now or clock.now, sleep or clock.sleep
    if boot is None or not reset_on_open(port):
        return b""
    return _hear(port, now() + boot.window, now, sleep)


def _hear(port: Port, until: float, now: Clock, sleep: Sleep) -> bytes:
    """What the board says first before ``until``, listened to without a word."""
    while now() < until:
        if said := drain(port):
            return said
        sleep(LISTEN)
    return b""


def ask(port: Port, question: bytes, answered: Callable[[bytes], bool],
        answer: bytearray, deadline: float, now: Clock, sleep: Sleep) -> bool:
    """Ask ``question`` every PROBE s until ``deadline``: has it been answered
    (``answer``: what came since the last question)?"""
    probe = now()
    while now() < deadline:
        if now() >= probe:
            answer.clear()
            port.write(question)
            probe = now() + PROBE
        answer += drain(port)
        if answered(bytes(answer)):
            return True
        sleep(LISTEN)
    return False


def ask_dump(port: Port, board: int, now: Clock | None = None, sleep: Sleep | None = None,
             timeout: float = DUMP_TIMEOUT, controller: Controller | None = None
             ) -> dict[int, int] | None:
    """The board's servo values (ID -> value), or None if no reply: a rig's answer to
    CANCEL DUMP, another kind's to its ``ask_pose``."""
    now, sleep = now or clock.now, sleep or clock.sleep
    drain(port)
    port.write(controller.ask_pose() if controller else ASK_POSE)
    reader = controller.pose_reader() if controller else DumpReader(board)
    deadline = now() + timeout
    while now() < deadline:
        found = reader.feed(drain(port))
        if found is not None:
            return found
        more = getattr(reader, "ask", None)
        if more is not None and (question := more()):
            port.write(question)
        sleep(0.005)
    return None
