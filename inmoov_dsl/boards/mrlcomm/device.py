"""A board running MrlComm, as its messages leave it: a pure state machine fed one byte
at a time, the heart of the virtual MrlComm board behind ``sim://`` and of the drive
loop's account of what such a board holds.

Modelled from MrlComm's source (the release ``messages.RELEASE`` names): it reads a
message as its ``Msg::readMsg`` does (a first byte other than 170 is an "error serial"
and starts again; a size over 64 is dropped), acknowledges every message while acks are
on (``publishAck`` after the method ran), answers ``getBoardInfo`` with its version,
board type (a Mega) and the devices attached, and keeps servos: ``servoAttach`` makes
one (at its initial width, no pulses), ``servoAttachPin`` starts its pulses,
``servoMoveToMicroseconds`` publishes a started event, and at velocity -1 its next
update writes the width and publishes a stopped event; ``servoStop`` a stopped event
with where it is; ``servoDetachPin`` stops the pulses. A velocity limit is kept but
not simulated (the plan is the motion: gestplay sets -1). A method of the schema it does
not model is acknowledged and does nothing; a method the board does not read is an
"unknown method N"; an empty message runs the last one again, as ``readMsg`` leaves it.
A message to a device that does not exist is an error, and then the real firmware calls
the device's method through a null pointer (in simavr it crashed, docs/controllers.md):
the twin stops reading and answering until it is reset, so that no tool may do it.
Checked against MrlComm itself, built for the Mega and run in simavr: the same bytes for
every message gestplay sends. Its board info, which the real one sends by itself every
second, is ``beat`` (a virtual board sends it every ``BEAT`` s).

How fast it reads is its ``ring``'s (the virtual board reads through it, ``wire.sim``):
bytes wait in a receive buffer of 63 (an AVR's ring of 64 slots), and bytes arriving
while it is full are lost; its loop reads a message once it has done with the one
before, and each message takes it the time to send what it published for it (it waits
for each with ``Serial.flush``: a move's two servo events, 1.56 ms at 115200) and
``READ`` more. A burst of moves overflows it, as it did MrlComm in simavr: what follows
is misread, each stray byte an "error serial".
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Sequence
from dataclasses import dataclass

from ..base import Write
from ..pulses import Widths
from . import messages as m

BOARD_MEGA = 1  #: MrlComm's board type for a Mega 2560
LOOP_US = 60  #: the time of its loop it reports (MrlComm in simavr: 26..105 us)
FREE_RAM = 6400  #: the RAM it reports free with no device (in simavr: 6,393) ...
DEVICE_RAM = 54  #: ... and what each servo takes of it (6,069..6,084 with six)
RECEIVE_BUFFER = 63  #: bytes its serial receive ring holds (64 slots, one kept empty)
READ = LOOP_US * 1e-6  #: s its loop takes on a message beyond waiting out what it sent


class Ring:
    """A serial receive buffer in time, as an AVR's ``HardwareSerial`` keeps it: bytes
    arrive in it (while it is full they are lost), and the sketch reads them in order
    when its loop comes round to it (``busy``: it is doing something else until then)."""

    def __init__(self, size: int, read: float):
        self.size, self.read = size, read  #: bytes it holds; s a message takes the loop
        self.lost = 0  #: bytes that arrived while it was full
        self._bytes: deque[tuple[float, int]] = deque()  # (arrival, byte), not yet read
        self._free = -math.inf  # when the loop next reads

    def clear(self) -> None:
        """A reset: what it held is gone."""
        self._bytes.clear()
        self._free = -math.inf

    def arrive(self, at: float, byte: int) -> None:
        """``byte`` arrives at ``at`` (lost if the ring is full)."""
        if len(self._bytes) >= self.size:
            self.lost += 1
        else:
            self._bytes.append((at, byte))

    def next_read(self) -> float:
        """When the loop reads the next byte (inf: none is waiting)."""
        return max(self._bytes[0][0], self._free) if self._bytes else math.inf

    def take(self) -> tuple[float, int]:
        """When the loop reads the next byte, and the byte."""
        at = self.next_read()
        return at, self._bytes.popleft()[1]

    def busy(self, until: float) -> None:
        """The loop reads nothing more before ``until``."""
        self._free = max(self._free, until)


@dataclass
class Servo:
    """An MrlServo: its pin, width (us), whether it pulses, its velocity."""

    pin: int
    us: int
    pulsing: bool = False
    velocity: int = -1


class MrlCommCore:
    """One board running MrlComm: its devices and the message being read."""

    BEAT = 1.0  #: s between the board infos it sends by itself (MrlComm in simavr: 1.0)

    def __init__(self, board_id: int, servos: Sequence, widths: Sequence[Widths],
                 devices: Sequence[int]):
        self.board_id, self.servos, self.widths = board_id, tuple(servos), tuple(widths)
        self._index = {d: j for j, d in enumerate(devices)}
        self.devices: dict[int, Servo] = {}
        self.acks = True
        self.crashed = False  #: it ran a device's method through a null pointer
        self.version = m.VERSION  #: the MRLCOMM_VERSION it reports
        self._buf = bytearray()
        self._last = bytes([m.GET_BOARD_INFO])  # the message an empty one runs again
        self.values: list[int] = []
        self.asked = None  #: (a rig's stored gestures: MrlComm has none)
        self.ring = Ring(RECEIVE_BUFFER, READ)  #: how fast it reads (``wire.sim``)
        self.restore(None)

    @property
    def pending(self) -> int | None:
        """The size of a message half read, if any."""
        return len(self._buf) or None

    @property
    def relaxed(self) -> bool:
        """None of its servos pulses."""
        return not any(s.pulsing for s in self.devices.values())

    def restore(self, values: Sequence[int] | None) -> None:
        """A reset: no devices, acks on; the servos (limp) where ``values`` says."""
        self.values = list(values) if values is not None else [s.rest for s in self.servos]
        self.devices.clear()
        self.acks = True
        self.crashed = False
        self._buf.clear()
        self.ring.clear()

    def beat(self) -> bytes:
        """The board info it sends by itself (nothing once it has crashed)."""
        return b"" if self.crashed else self._info()

    def _info(self) -> bytes:
        free = FREE_RAM - DEVICE_RAM * len(self.devices)
        return m.message(m.BOARD_INFO, self.version, BOARD_MEGA, LOOP_US, free, 0,
                         bytes(self.devices))

    def command(self, index: int, value: int) -> Write:
        """Servo ``index`` to ``value`` (attached and pulsing, if it was not)."""
        device = next(d for d, j in self._index.items() if j == index)
        us = round(float(self.widths[index].us(value)))
        servo = self.devices.setdefault(device, Servo(self.servos[index].pin, us))
        servo.us, servo.pulsing = us, True
        return self._wrote(device)

    def feed(self, byte: int) -> tuple[tuple[Write, ...] | None, bytes]:
        """Read one byte: the writes a whole message makes, and what the board sends."""
        if self.crashed:
            return None, b""
        self._buf.append(byte)
        if len(self._buf) == 1 and byte != m.MAGIC:
            self._buf.clear()
            return None, m.message(m.ERROR, b"error serial")
        if len(self._buf) == 2 and byte > m.MOST:
            self._buf.clear()
            return None, b""
        if len(self._buf) < 2 or len(self._buf) < 2 + self._buf[1]:
            return None, b""
        body, self._buf = bytes(self._buf[2:]) or self._last, bytearray()
        self._last = body
        writes, before, after = self._run(body)
        if self.crashed:
            return None, before
        ack = m.message(m.ACK, body[0] if body else 0) if self.acks else b""
        return writes, before + ack + after

    def _run(self, body: bytes) -> tuple[tuple[Write, ...] | None, bytes, bytes]:
        """What a message does: writes, what it publishes, what the next update does."""
        method = body[0]
        if method not in m.READS:
            return None, m.message(m.ERROR, f"unknown method {method}".encode()), b""
        args = m.arguments(body)
        if args is None:  # a method of the schema not modelled (or its arguments cut)
            return None, b"", b""
        if method == m.GET_BOARD_INFO:
            return None, self._info(), b""
        if method == m.ENABLE_ACK:
            self.acks = bool(args[0])
        elif method == m.SOFT_RESET:  # its servos detached and gone; acks as they were
            self.devices.clear()
        elif method == m.DEVICE_DETACH:
            self.devices.pop(args[0], None)
        elif method == m.SERVO_ATTACH:
            return self._attach(*args)
        elif method in (m.SERVO_ATTACH_PIN, m.SERVO_DETACH_PIN, m.SERVO_SET_VELOCITY,
                        m.SERVO_MOVE_TO_MICROSECONDS, m.SERVO_STOP):
            return self._servo(method, args)
        return None, b"", b""

    def _attach(self, device: int, pin: int, us: int, velocity: int, name: bytes):
        if device in self.devices:
            return None, m.message(m.ERROR, b"device already exists"), b""
        self.devices[device] = Servo(pin, us, False, velocity)
        return None, m.message(m.ERROR, b"servo need name") if not name else b"", b""

    def _servo(self, method: int, args: tuple):
        servo = self.devices.get(args[0])
        if servo is None:  # then the method runs on a null device: it stops
            self.crashed = True
            return None, m.message(m.ERROR, b"device does not exist"), b""
        device = args[0]
        if method == m.SERVO_ATTACH_PIN:
            servo.pin, servo.pulsing = args[1], True
            return (self._wrote(device),), b"", b""
        if method == m.SERVO_DETACH_PIN:
            servo.pulsing = False
        elif method == m.SERVO_SET_VELOCITY:
            servo.velocity = args[1]
        elif method == m.SERVO_STOP:
            return None, m.message(m.SERVO_EVENT, device, m.STOPPED, servo.us, servo.us), b""
        elif method == m.SERVO_MOVE_TO_MICROSECONDS:
            started = m.message(m.SERVO_EVENT, device, m.STARTED, servo.us, args[1])
            if servo.us == args[1]:
                return None, started, m.message(m.SERVO_EVENT, device, m.STOPPED,
                                                servo.us, servo.us)
            servo.us = args[1]
            stopped = m.message(m.SERVO_EVENT, device, m.STOPPED, servo.us, servo.us)
            return ((self._wrote(device),) if servo.pulsing else None), started, stopped
        return None, b"", b""

    def _wrote(self, device: int) -> Write:
        """Servo ``device`` now sends its width: its value as the widths say."""
        j = self._index.get(device)
        servo = self.devices[device]
        if j is None:
            return Write(device, 0, servo.us)
        self.values[j] = self.widths[j].value(servo.us)
        return Write(self.servos[j].id, self.values[j], servo.us)
