"""A PCA9685's registers, as its datasheet gives them: a pure model of the chip, the
virtual PCA9685 behind ``sim://`` and the drive loop's account of what one holds.

MODE1 (0x00: RESTART 0x80, AI 0x20 auto-increment, SLEEP 0x10, ALLCALL 0x01; 0x11 at
power-up), PRE_SCALE (0xFE: 30 at power-up, writable only while the chip sleeps: a
write while it is awake is blocked, and the model notes it in ``refused``), LEDn_ON_L,
ON_H, OFF_L, OFF_H at 0x06 + 4n (bit 4 of ON_H full on, of OFF_H full off, which wins;
every channel full off at power-up). Without AI every byte of a write goes to one
register. A channel's pulse is (OFF - ON) mod 4096 ticks of (PRE_SCALE + 1) periods of
the oscillator.
"""

from __future__ import annotations

MODE1, PRESCALE, LED0 = 0x00, 0xFE, 0x06
RESTART, AI, SLEEP, ALLCALL = 0x80, 0x20, 0x10, 0x01
FULL = 0x10  #: bit 4 of ON_H and OFF_H
CHANNELS = 16
OSCILLATOR = 25_000_000  #: Hz, the datasheet's internal oscillator
TICKS = 4096


def led(channel: int) -> int:
    """The first register (ON_L) of ``channel``."""
    return LED0 + 4 * channel


def prescale(frequency: float, oscillator: float = OSCILLATOR) -> int:
    """PRE_SCALE for a frame of ``frequency`` Hz: round(osc / (4096 f)) - 1 (121 at
    50 Hz)."""
    return round(oscillator / (TICKS * frequency)) - 1


class Chip:
    """One PCA9685: its 256 registers."""

    def __init__(self, oscillator: float = OSCILLATOR):
        self.oscillator = oscillator
        self.registers = bytearray(256)
        self.registers[MODE1] = SLEEP | ALLCALL
        self.registers[PRESCALE] = 30
        for ch in range(CHANNELS):
            self.registers[led(ch) + 3] = FULL
        self.refused: list[str] = []  #: what the datasheet forbids and was tried

    def write(self, register: int, data: bytes) -> None:
        """A write of ``data`` from ``register`` on (one register each with AI, else
        all to ``register``)."""
        for k, byte in enumerate(data):
            at = (register + k) % 256 if self.registers[MODE1] & AI else register
            if at == PRESCALE and not self.registers[MODE1] & SLEEP:
                self.refused.append("PRE_SCALE written while the chip is awake")
                continue
            self.registers[at] = byte

    def read(self, register: int, count: int) -> bytes:
        """``count`` registers from ``register`` (auto-incrementing with AI)."""
        if not self.registers[MODE1] & AI:
            return bytes([self.registers[register]]) * count
        return bytes(self.registers[(register + k) % 256] for k in range(count))

    @property
    def tick(self) -> float:
        """Seconds per count."""
        return (self.registers[PRESCALE] + 1) / self.oscillator

    def pulse(self, channel: int) -> float:
        """The width (s) of ``channel``'s pulse now (0: no pulses; the chip asleep)."""
        return 0.0 if self.registers[MODE1] & SLEEP else self.width(channel)

    def width(self, channel: int) -> float:
        """The width (s) ``channel``'s registers ask for (0: full off)."""
        r = self.registers[led(channel):led(channel) + 4]
        if r[3] & FULL:
            return 0.0
        if r[1] & FULL:
            return TICKS * self.tick
        on, off = r[0] | (r[1] & 0x0F) << 8, r[2] | (r[3] & 0x0F) << 8
        return ((off - on) % TICKS) * self.tick
