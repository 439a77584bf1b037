"""A Pololu Maestro as its serial commands leave it (``commands.py``): a pure state
machine fed one byte at a time, the heart of the virtual Maestro behind ``sim://`` and
of the drive loop's account of what a Maestro holds.

What it models, from Pololu's documentation: the compact and the Pololu protocol
(its device number), Set Target (clamped to the channel's minimum and maximum; 0 stops
the pulses), Set Multiple Targets (Minis only), Set Speed and Set Acceleration (kept;
the plan is the motion, so they are set to 0 and the virtual Maestro follows each
target at once, as a real one does with both 0), Get Position, Get Moving State, Get
Errors (and clearing them), Go Home. Errors as a Maestro flags them: a data byte where
a command byte is due, a command cut short by another, a command it does not know (the
virtual one does not run scripts, PWM or Mini SSC), a channel it does not have; on an
error its channels go home (their pulses off, as the factory setting does).
"""

from __future__ import annotations

from collections.abc import Sequence

from ..base import Write
from ..pulses import Widths
from . import commands as c

MODELS = {"micro6": 6, "mini12": 12, "mini18": 18, "mini24": 24}  #: channels of each
#: us; a channel's limits once set up as docs/controllers.md says (the factory's
#: 992..2000 would clamp the Servo library's 544..2400)
MIN_US, MAX_US = 500, 2500


class MaestroCore:
    """One Maestro: its channels' targets and settings, the servos on them, the command
    being read, the error register."""

    def __init__(self, board_id: int, servos: Sequence, widths: Sequence[Widths],
                 model: str = "mini12", device: int = c.DEFAULT_DEVICE,
                 limits: tuple[int, int] = (MIN_US, MAX_US)):
        self.board_id, self.servos, self.widths = board_id, tuple(servos), tuple(widths)
        self.model, self.device = model, device
        self.channels = MODELS[model]
        self.low, self.high = (limits[0] * c.QUARTERS, limits[1] * c.QUARTERS)
        self.targets = [0] * self.channels  #: quarter-us; 0: no pulses
        self.speeds = [0] * self.channels
        self.accelerations = [0] * self.channels
        self.errors = 0
        self._by_channel = {s.pin: j for j, s in enumerate(self.servos)}
        self._buf = bytearray()
        self.values: list[int] = []  #: each servo's value as its target says
        self.asked = None  #: (a rig's stored gestures: a Maestro has none)
        self.restore(None)

    @property
    def pending(self) -> int | None:
        """The command byte of a command half read, if any."""
        return self._buf[0] if self._buf else None

    @property
    def relaxed(self) -> bool:
        """No servo of the board gets pulses."""
        return all(self.targets[s.pin] == 0 for s in self.servos)

    def restore(self, values: Sequence[int] | None) -> None:
        """Power up: each servo at ``values`` (None: its rest), nothing half read."""
        self.values = list(values) if values is not None else [s.rest for s in self.servos]
        for j, s in enumerate(self.servos):
            self.targets[s.pin] = round(float(self.widths[j].us(self.values[j])) * c.QUARTERS)
        self._buf.clear()

    def command(self, index: int, value: int) -> Write:
        """Servo ``index`` to ``value`` (a whole value: the firmware's width)."""
        us = float(self.widths[index].us(value))
        return self._target(self.servos[index].pin, round(us * c.QUARTERS))

    def feed(self, byte: int) -> tuple[Write | tuple[Write, ...] | None, bytes]:
        """Read one byte: the servo writes a command it completes does, and the reply."""
        if byte & 0x80 and self._buf:
            self._error()  # a command cut short by the next
            self._buf.clear()
        if not byte & 0x80 and not self._buf:
            self._error()  # a data byte where a command byte is due
            return None, b""
        self._buf.append(byte)
        if len(self._buf) < c.length(bytes(self._buf) + bytes(64), 0):
            return None, b""
        cmd, self._buf = bytes(self._buf), bytearray()
        if cmd[0] == c.POLOLU:
            if cmd[1] != self.device:
                return None, b""  # for another device on the line
            cmd = bytes([cmd[2] | 0x80]) + cmd[3:]
        return self._run(cmd)

    def _run(self, cmd: bytes) -> tuple[Write | tuple[Write, ...] | None, bytes]:
        code = cmd[0]
        if code == c.GET_ERRORS:
            errors, self.errors = self.errors, 0
            return None, bytes([errors & 0xFF, errors >> 8])
        if code == c.GET_MOVING_STATE:
            return None, b"\x00"  # it follows each target at once
        if code == c.GO_HOME:
            return self._home(), b""
        if code == c.SET_MULTIPLE_TARGETS and self.model != "micro6":
            count, first = cmd[1], cmd[2]
            if first + count > self.channels:
                return self._error()
            return tuple(self._target(first + k, cmd[3 + 2 * k] | cmd[4 + 2 * k] << 7)
                         for k in range(count)), b""
        if code not in (c.SET_TARGET, c.SET_SPEED, c.SET_ACCELERATION, c.GET_POSITION) or \
                cmd[1] >= self.channels:
            return self._error()
        channel = cmd[1]
        if code == c.GET_POSITION:
            q = self.targets[channel]
            return None, bytes([q & 0xFF, q >> 8])
        value = cmd[2] | cmd[3] << 7
        if code == c.SET_SPEED:
            self.speeds[channel] = value
        elif code == c.SET_ACCELERATION:
            self.accelerations[channel] = value
        else:
            return self._target(channel, value), b""
        return None, b""

    def _target(self, channel: int, quarters: int) -> Write | None:
        """Channel ``channel`` to ``quarters`` (0: off), within its limits."""
        if quarters:
            quarters = min(max(quarters, self.low), self.high)
        self.targets[channel] = quarters
        j = self._by_channel.get(channel)
        if j is None:
            return None
        if quarters:
            self.values[j] = self.widths[j].value(quarters / c.QUARTERS)
        return Write(self.servos[j].id, self.values[j], round(quarters / c.QUARTERS))

    def _home(self) -> tuple[Write, ...]:
        """Every channel goes home: its pulses off."""
        return tuple(w for ch in range(self.channels) if (w := self._target(ch, 0)))

    def _error(self) -> tuple[None, bytes]:
        self.errors |= c.PROTOCOL_ERROR
        self._home()
        return None, b""
