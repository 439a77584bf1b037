"""A PCA9685 on an I2C bus (a Raspberry Pi's ``/dev/i2c-1``): a plan as each servo's
pulse in the chip's twelve-bit ticks, written to its LEDn registers once per 20 ms
frame while a servo moves (``transactions.py`` frames the writes, ``chip.py`` is the
chip, ``bus.py`` the bus through smbus2 or the virtual chip)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from ..base import Controller, PlanLike, PoseReader, Write
from ..frames import per_frame
from . import chip as regs
from . import transactions as tx

FRAME_HZ = 50  #: the servo frame the prescale is chosen for
DEFAULT_BUS = 100_000  #: Hz, the I2C bus's clock unless the profile says otherwise
BITS_PER_BYTE = 9  #: eight data bits and the acknowledge


class PcaCore:
    """What a PCA9685 holds after the transactions it reads: the chip (by default as a
    connect leaves it: at 50 Hz, auto-incrementing, awake), and each servo's value as
    its registers say."""

    def __init__(self, controller: PcaController, chip: regs.Chip | None = None):
        self.controller, self.board_id = controller, controller.board.id
        self.servos, self.widths = controller.servos, controller.widths
        if chip is None:
            chip = regs.Chip(controller.oscillator)
            for _, register, written in tx.parse(controller.setup()):
                chip.write(register, written)
        self.chip = chip
        self._buf = bytearray()
        self.values: list[int] = [s.rest for s in self.servos]
        self.asked = None  #: (a rig's stored gestures: a PCA9685 has none)

    @property
    def pending(self) -> int | None:
        """The first byte of a transaction half read, if any."""
        return self._buf[0] if self._buf else None

    @property
    def relaxed(self) -> bool:
        """No servo of the board gets pulses."""
        return all(self.chip.pulse(s.pin) == 0 for s in self.servos)

    def restore(self, values: Sequence[int] | None) -> None:
        """The board holds ``values`` (its registers set to them; None: the rests, and
        the registers as they are)."""
        self._buf.clear()
        if values is None:
            self.values = [s.rest for s in self.servos]
            return
        self.values = list(values)
        for j, s in enumerate(self.servos):
            off = int(self.controller.ticks(j, [self.values[j]])[0])
            self.chip.registers[regs.led(s.pin):regs.led(s.pin) + 4] = bytes(
                [0, 0, off & 0xFF, off >> 8])

    def command(self, index: int, value: int) -> Write:
        """Servo ``index`` to ``value``."""
        data = self.controller.set_values({self.servos[index].id: value})
        for _, register, written in tx.parse(data):
            self.chip.write(register, written)
        self.values[index] = value
        return Write(self.servos[index].id, value, round(self.chip.pulse(
            self.servos[index].pin) * 1e6))

    def feed(self, byte: int) -> tuple[tuple[Write, ...] | None, bytes]:
        """Read one byte: the writes a whole transaction makes, or its answer."""
        self._buf.append(byte)
        if len(self._buf) < tx.length(bytes(self._buf) + bytes(40), 0):
            return None, b""
        t, self._buf = bytes(self._buf), bytearray()
        for kind, register, arg in tx.parse(t):
            if kind == tx.READ:
                return None, self.chip.read(register, arg)
            self.chip.write(register, arg)
            return self._wrote(register, len(arg)), b""
        return None, b""

    def _wrote(self, register: int, count: int) -> tuple[Write, ...]:
        writes = []
        for j, s in enumerate(self.servos):
            if register <= regs.led(s.pin) + 3 and regs.led(s.pin) < register + count:
                us = self.chip.width(s.pin) * 1e6  # (asleep: what it sends once awake)
                if us:
                    self.values[j] = self.widths[j].value(us)
                writes.append(Write(s.id, self.values[j], round(us)))
        return tuple(writes)


def pulse_ticks(leds: bytes) -> int:
    """The pulse (ticks) a channel's four LEDn registers ask for (0: none, full off)."""
    if leds[3] & regs.FULL:
        return 0
    on, off = leds[0] | (leds[1] & 0x0F) << 8, leds[2] | (leds[3] & 0x0F) << 8
    return (off - on) % regs.TICKS


class _Leds:
    """The LEDn registers read back as a pose."""

    def __init__(self, controller: PcaController):
        self.controller, self.data = controller, bytearray()

    def feed(self, data: bytes) -> dict[int, int] | None:
        """The pose once every servo's registers came (a channel full off: its rest)."""
        self.data += data
        servos = self.controller.servos
        if len(self.data) < 4 * len(servos):
            return None
        pose = {}
        for j, s in enumerate(servos):
            ticks = pulse_ticks(self.data[4 * j:4 * j + 4])
            us = ticks * self.controller.tick * 1e6
            pose[s.id] = self.controller.widths[j].value(us) if ticks else s.rest
        return pose


class PcaController(Controller):
    """A PCA9685: each servo's pulse as its OFF count (ON at 0), channels next to each
    other in one block write."""

    kind = "pca9685"
    serial = False
    pose_reply = "answer to the reads of its LEDn registers"
    unheard = "is the PCA9685 powered, and at this address? (i2cdetect -y BUS lists the " \
        "addresses that answer)"

    @property
    def oscillator(self) -> int:
        """Hz: the profile's measured oscillator, else the datasheet's 25 MHz."""
        return self.board.option("oscillator", regs.OSCILLATOR)

    @property
    def prescale(self) -> int:
        """PRE_SCALE for 50 Hz at its oscillator."""
        return regs.prescale(FRAME_HZ, self.oscillator)

    @property
    def tick(self) -> float:
        """Seconds per count."""
        return (self.prescale + 1) / self.oscillator

    @property
    def tau(self) -> float:
        """One byte on the bus (its nine clocks)."""
        return BITS_PER_BYTE / self.board.option("bus", DEFAULT_BUS)

    def commands(self, data: bytes) -> list[tuple[int, int]]:
        """Its transactions."""
        return tx.commands(data)

    def addressed(self, data: bytes) -> set[int]:
        """The channels whose registers its writes set."""
        return tx.channels(data)

    def open(self, spec: str):
        """Its I2C bus (``bus.open_bus``); a ``sim://`` port is its virtual chip on a
        virtual link, as every kind's twin is (None: the link edge opens it)."""
        from .bus import open_bus

        return None if spec.startswith("sim://") else open_bus(spec)

    @classmethod
    def claims(cls, spec: str) -> str | None:
        """``i2c:N``: an I2C bus, where a PCA9685 is."""
        return "an I2C bus, where a PCA9685 is" if spec.startswith("i2c:") else None

    def moves(self, data: bytes) -> list[tuple[int, int]]:
        """(servo ID, OFF count) of each servo whose registers a write sets."""
        out = []
        for kind, register, written in tx.parse(data):
            if kind != tx.WRITE:
                continue
            for s in self.servos:
                k = regs.led(s.pin) - register
                if k >= 0 and k + 4 <= len(written):
                    out.append((s.id, written[k + 2] | (written[k + 3] & 0x1F) << 8))
        return out

    @property
    def unit_us(self) -> float:  # type: ignore[override]
        """A tick, in us."""
        return self.tick * 1e6

    def units(self, index: int, values) -> np.ndarray:
        """Ticks."""
        return self.ticks(index, values)

    def ticks(self, index: int, values) -> np.ndarray:
        """Servo ``index``'s ``values`` (kept in its range) as OFF counts."""
        us = self.widths[index].us(self.limit(np.asarray(values, dtype=float), index))
        return np.clip(np.round(us * 1e-6 / self.tick), 1, regs.TICKS - 1).astype(np.int64)

    def leds(self, changed: Mapping[int, int | None]) -> bytes:
        """Channel -> OFF count (None: full off) as block writes of runs of channels."""
        out, run = bytearray(), []
        for ch in sorted(changed) + [None]:
            if run and ch != run[-1] + 1:
                data = b"".join(bytes([0, 0, 0, regs.FULL]) if changed[k] is None else
                                bytes([0, 0, changed[k] & 0xFF, changed[k] >> 8])
                                for k in run)
                out += tx.write(regs.led(run[0]), data)
                run = []
            if ch is not None:
                run.append(ch)
        return bytes(out)

    def encode(self, plan: PlanLike) -> tuple[np.ndarray, bytes]:
        """Every 20 ms frame, the counts that changed (``frames.per_frame``)."""
        return per_frame(self, plan, self.leds)

    def core(self) -> PcaCore:
        """The chip as the board's transactions leave it, from a connect's setup."""
        return PcaCore(self)

    def twin(self) -> PcaCore:
        """The virtual chip, as it powers up: asleep, every channel full off."""
        return PcaCore(self, regs.Chip(self.oscillator))

    def set_values(self, values: Mapping[int, int]) -> bytes:
        """Writes for the servos' values."""
        by_id = {s.id: j for j, s in enumerate(self.servos)}
        return self.leds({self.servos[by_id[sid]].pin: int(self.ticks(by_id[sid], [v])[0])
                          for sid, v in values.items() if sid in by_id})

    def relax(self) -> bytes:
        """Each of its channels full off."""
        return self.leds(dict.fromkeys((s.pin for s in self.servos), None))

    def ask_pose(self) -> bytes:
        """A read of each of each servo's four LEDn registers, one by one (a chip not
        yet set up does not auto-increment)."""
        return b"".join(tx.read(regs.led(s.pin) + k, 1) for s in self.servos
                        for k in range(4))

    def pose_reader(self) -> PoseReader:
        """Reads the registers back as values."""
        return _Leds(self)

    def probe(self) -> bytes:
        """Read MODE1 and PRE_SCALE, then its servos' LEDn registers (``ask_pose``): which
        outputs are off (``greeting``)."""
        return tx.read(regs.MODE1, 1) + tx.read(regs.PRESCALE, 1) + self.ask_pose()

    def ready(self, answer: bytes) -> bool:
        """All came."""
        return len(answer) >= 2 + 4 * len(self.servos)

    def greeting(self, answer: bytes) -> str | None:
        """The servos whose outputs are off (as the chip powers up, or relaxed): limp,
        and the rest the plan starts each from (``_Leds``: what the pose reads), or
        None."""
        limp = [s for j, s in enumerate(self.servos)
                if len(answer) >= 6 + 4 * j and not pulse_ticks(answer[2 + 4 * j:6 + 4 * j])]
        if not limp:
            return None
        names = ", ".join(s.name for s in limp)
        rests = ", ".join(f"{s.name} {s.rest}" for s in limp)
        return f"the PCA9685 of board {self.board.id} has its outputs off: {names} limp " \
               f"until a gesture names {'them' if len(limp) > 1 else 'it'}; the plan " \
               f"takes each to be at its rest ({rests}), where its first move starts"

    def setup(self, answer: bytes = b"", pose: Mapping[int, int] | None = None) -> bytes:
        """The prescale for 50 Hz, written while the chip sleeps, and auto-increment,
        unless the chip has both already (no glitch on the pulses then)."""
        mode, scale = (answer[0], answer[1]) if len(answer) >= 2 else (regs.SLEEP, -1)
        if scale == self.prescale and mode & regs.AI and not mode & regs.SLEEP:
            return b""
        awake = regs.AI | regs.ALLCALL
        return (tx.write(regs.MODE1, bytes([awake | regs.SLEEP]))
                + tx.write(regs.PRESCALE, bytes([self.prescale]))
                + tx.write(regs.MODE1, bytes([awake]))
                + tx.write(regs.MODE1, bytes([awake | regs.RESTART])))
