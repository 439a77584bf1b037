"""A board running MyRobotLab's MrlComm (most InMoov Megas): a plan as one
``servoMoveToMicroseconds`` per moving servo per frame, in the firmware's widths, the
board's own messages (``messages.py``) and its virtual twin (``device.py``)."""

from __future__ import annotations

from collections.abc import Callable, Mapping

import numpy as np

from ... import clock
from .. import arduino
from ..arduino import Bootloader
from ..base import Controller, PlanLike, PoseReader
from ..frames import per_frame
from . import messages as m
from .device import MrlCommCore

#: moves a frame at most, the furthest behind first: MrlComm built for the Mega, in
#: simavr, kept up with 6 with up to 18 servos attached, nothing lost and every servo
#: at its width, and with 9 with 18 attached; 10 or 11 overflowed its receive buffer
#: (each move costs it 1.56 ms of events it flushes) and it crashed (docs/controllers.md)
MOVES_PER_FRAME = 6

#: bytes its receive buffer holds (an AVR's ring of 64 slots, one kept empty): more
#: written than it has read is lost, and what follows is misread
RECEIVE_BUFFER = 63
EVENT = len(m.message(m.SERVO_EVENT, 0, 0, 0, 0))  #: bytes of a servo event
#: bytes MrlComm publishes for a message it reads beyond its ack, each waited out
#: (``Serial.flush``), so that its loop, not the wire, bounds how fast it reads: a move,
#: its started and stopped events (1.56 ms at 115200, as measured in simavr)
PUBLISHED = {m.SERVO_MOVE_TO_MICROSECONDS: 2 * EVENT, m.SERVO_STOP: EVENT}
ACK = len(m.message(m.ACK, 0))  #: bytes of an ack (counted on every message, as if on)
#: s of its loop the host counts on each message beyond what it publishes (MrlComm in
#: simavr reported 26-105 us a loop): with an ack counted on every message, a move is
#: 2.1 ms of the board's time by the host's account, 1.6 ms measured
LOOP = 0.0002


class _Stopped:
    """The board's pose in two questions: its board info says which servos it has
    attached (a servo it has not: its rest, as the board cannot say), then a
    ``servoStop`` to each of those, whose stopped event says where it is. A device that
    does not exist is never asked: MrlComm would run its method on a null pointer."""

    def __init__(self, controller: MrlCommController):
        self.controller, self.reader, self.pose = controller, m.Reader(), {}
        self.pending: list[int] | None = None  # servos asked, not answered yet
        self.question = b""

    def feed(self, data: bytes) -> dict[int, int] | None:
        """The pose once every servo is answered for."""
        c = self.controller
        for method, args in self.reader.feed(data):
            if args is None:
                continue
            if method == m.BOARD_INFO and self.pending is None:
                attached = set(args[5])
                self.pending = [j for j, d in enumerate(c.devices) if d in attached]
                self.pose = {s.id: s.rest for j, s in enumerate(c.servos)
                             if j not in self.pending}
                self.question = b"".join(m.message(m.SERVO_STOP, c.devices[j])
                                         for j in self.pending)
            elif method == m.SERVO_EVENT and args[1] == m.STOPPED and self.pending and \
                    args[0] in c.devices and c.devices.index(args[0]) in self.pending:
                j = c.devices.index(args[0])  # (a late event of a move: where it went)
                self.pose[c.servos[j].id] = c.widths[j].value(args[2])
                self.pending.remove(j)
        return self.pose if self.pending == [] else None

    def ask(self) -> bytes:
        """The ``servoStop``s, once the board info came."""
        question, self.question = self.question, b""
        return question


#: s without a byte from the board before it is taken as stopped: MrlComm sends its
#: board info every second, whatever else it does
SILENT = 2.5


class _Watch:
    """What a board running MrlComm says while it plays: its begin message is a board
    that started again (its power, its USB), its servos gone with it; an error is a
    board that lost or misread what it was sent ("error serial": a byte that starts no
    message; "device does not exist": a message to a device it does not have, which it
    then runs on a null pointer); nothing at all for SILENT s is a board that has
    stopped."""

    def __init__(self, board: int):
        self.board, self.reader = board, m.Reader()
        self.heard: float | None = None  # when it last sent something

    def __call__(self, data: bytes) -> str | None:
        now = clock.now()
        if data or self.heard is None:
            self.heard = now
        elif now - self.heard > SILENT:
            return (f"board {self.board} has sent nothing for {now - self.heard:.1f} s "
                    f"(MrlComm sends its board info every second): it has stopped (its "
                    f"power? a crash?)")
        for method, args in self.reader.feed(data):
            if method == m.BEGIN:
                return (f"board {self.board} started again mid-gesture (MrlComm's begin "
                        f"message: its power or its USB reset it); its servos are detached "
                        f"and limp")
            if method == m.ERROR:
                return self._error(bytes(args[0]) if args else b"")
        return None

    def _error(self, said: bytes) -> str:
        text = said.decode("ascii", "replace")
        if "does not exist" in text:
            return (f"board {self.board} has lost its servos (MrlComm: device does not "
                    f"exist): it was reset, or misread what it was sent")
        if text == "error serial":
            return (f"board {self.board} lost part of what it was sent (MrlComm: error "
                    f"serial): its servos may not be where the gesture puts them")
        return f"board {self.board} misread what it was sent (MrlComm: {text})"


class MrlCommController(Controller):
    """A Mega (or any Arduino) running MrlComm at its release's version."""

    kind = "mrlcomm"
    unit_us = 1.0
    address = "device"
    pose_reply = "board info (getBoardInfo)"
    unheard = "is the board running MrlComm, and at this baud?"
    receive_buffer = RECEIVE_BUFFER

    @property
    def devices(self) -> list[int]:
        """The device number of each servo of the board (1, 2, ... in its order)."""
        return list(range(1, len(self.servos) + 1))

    def commands(self, data: bytes) -> list[tuple[int, int]]:
        """Its messages."""
        return m.commands(data)

    def addresses(self) -> set[int]:
        """Its servos' device numbers."""
        return set(self.devices)

    def addressed(self, data: bytes) -> set[int]:
        """The device numbers its moves address."""
        return {args[0] for method, args in m.Reader().feed(data)
                if method == m.SERVO_MOVE_TO_MICROSECONDS and args}

    def moves(self, data: bytes) -> list[tuple[int, int]]:
        """(servo ID, us) of each move of ``data`` to a servo of the board."""
        ids = dict(zip(self.devices, (s.id for s in self.servos), strict=True))
        return [(ids[args[0]], args[1]) for method, args in m.Reader().feed(data)
                if method == m.SERVO_MOVE_TO_MICROSECONDS and args and args[0] in ids]

    def cost(self, command: bytes) -> float:
        """What it publishes for ``command`` (an ack counted, as if acks were on), which
        it waits to see out, and its loop."""
        method = command[2] if len(command) > 2 else None
        if method == m.GET_BOARD_INFO:  # its board info, listing every device
            published = len(m.message(m.BOARD_INFO, 0, 0, 0, 0, 0, bytes(len(self.servos))))
        else:
            published = PUBLISHED.get(method, 0)
        return (published + ACK) * self.tau + LOOP

    def key(self, command: bytes) -> tuple[int, int] | None:
        """A move's device: a newer move of it makes an older one needless."""
        if len(command) > 3 and command[2] == m.SERVO_MOVE_TO_MICROSECONDS:
            return m.SERVO_MOVE_TO_MICROSECONDS, command[3]
        return None

    def answer(self, command: bytes) -> tuple[int, int] | None:
        """A move's started event (MrlComm publishes it as it reads the move)."""
        if len(command) > 3 and command[2] == m.SERVO_MOVE_TO_MICROSECONDS:
            return m.STARTED, command[3]
        return None

    def answers(self) -> Callable[[bytes], list[tuple[int, int]]]:
        """Its started events, as (``STARTED``, device)."""
        reader = m.Reader()
        return lambda data: [(m.STARTED, args[0]) for method, args in reader.feed(data)
                             if method == m.SERVO_EVENT and args and args[1] == m.STARTED]

    def units(self, index: int, values) -> np.ndarray:
        """Whole microseconds (what a move carries)."""
        us = self.widths[index].us(self.limit(np.asarray(values, dtype=float), index))
        return np.round(us).astype(np.int64)

    def _moves(self, changed: Mapping[int, int]) -> bytes:
        by_pin = {s.pin: d for s, d in zip(self.servos, self.devices, strict=True)}
        return b"".join(m.message(m.SERVO_MOVE_TO_MICROSECONDS, by_pin[pin], us)
                        for pin, us in sorted(changed.items()))

    def encode(self, plan: PlanLike) -> tuple[np.ndarray, bytes]:
        """Every frame, a move for each servo whose width changed (at most
        ``MOVES_PER_FRAME``, the furthest behind first)."""
        return per_frame(self, plan, self._moves, MOVES_PER_FRAME)

    def core(self) -> MrlCommCore:
        """The board's account: its servos attached and pulsing at their rests, acks
        off (as a connect leaves it)."""
        core = self.twin()
        for byte in self.setup(b"", {s.id: s.rest for s in self.servos}):
            core.feed(byte)
        return core

    def twin(self) -> MrlCommCore:
        """The virtual board as it starts: no devices, acks on."""
        return MrlCommCore(self.board.id, self.servos, self.widths, self.devices)

    def hello(self) -> bytes:
        """Its banner, then its begin message with its version."""
        return m.BANNER + m.message(m.BEGIN, m.VERSION)

    def set_values(self, values: Mapping[int, int]) -> bytes:
        """Moves for the servos' values."""
        j = {s.id: k for k, s in enumerate(self.servos)}
        return b"".join(m.message(m.SERVO_MOVE_TO_MICROSECONDS, self.devices[j[sid]],
                                  int(self.units(j[sid], [v])[0]))
                        for sid, v in sorted(values.items()) if sid in j)

    def relax(self) -> bytes:
        """Each servo's pin detached: no pulses."""
        return b"".join(m.message(m.SERVO_DETACH_PIN, d) for d in self.devices)

    def ask_pose(self) -> bytes:
        """``getBoardInfo``: the servos attached, each then asked where it is
        (``pose_reader``)."""
        return m.message(m.GET_BOARD_INFO)

    def pose_reader(self) -> PoseReader:
        """Reads the stopped events as values."""
        return _Stopped(self)

    def watch(self) -> _Watch:
        """A reset, or servos gone, while it plays."""
        return _Watch(self.board.id)

    def bootloader(self) -> Bootloader:
        """Its Arduino's (``arduino`` in its ``[[board]]``)."""
        return arduino.bootloader(self.board.options)

    def probe(self) -> bytes:
        """``getBoardInfo``, as MyRobotLab asks."""
        return m.message(m.GET_BOARD_INFO)

    def ready(self, answer: bytes) -> bool:
        """Its board info came."""
        return any(method == m.BOARD_INFO for method, _ in m.Reader().feed(answer))

    def refusal(self, answer: bytes) -> str | None:
        """A board of another MrlComm version than the one supported."""
        for method, args in m.Reader().feed(answer):
            if method == m.BOARD_INFO and args and args[0] != m.VERSION:
                return f"board {self.board.id} runs MrlComm version {args[0]}; this " \
                       f"speaks version {m.VERSION}, as {m.RELEASE} ships it"
        return None

    def setup(self, answer: bytes = b"", pose: Mapping[int, int] | None = None) -> bytes:
        """Acks off; each servo not yet attached attached at its pin, from ``pose``
        (else its rest), velocity -1 (the plan is the motion); every servo's pulses
        started: one a relax detached holds its last width again, as our firmware's
        servos do at the next command (on a servo pulsing, the Servo library changes
        nothing)."""
        attached = set()
        for method, args in m.Reader().feed(answer):
            if method == m.BOARD_INFO and args:
                attached = set(args[5])
        out = bytearray(m.message(m.ENABLE_ACK, 0))
        for s, d, j in zip(self.servos, self.devices, range(len(self.servos)), strict=True):
            if d in attached:
                out += m.message(m.SERVO_ATTACH_PIN, d, s.pin or 0)
                continue
            value = (pose or {}).get(s.id, s.rest)
            out += m.message(m.SERVO_ATTACH, d, s.pin or 0, int(self.units(j, [value])[0]),
                             -1, s.name.encode()[:20])
            out += m.message(m.SERVO_SET_VELOCITY, d, -1)
            out += m.message(m.SERVO_ATTACH_PIN, d, s.pin or 0)
        return bytes(out)
