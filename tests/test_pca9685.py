"""A PCA9685 on its I2C bus (the register model behind smbus2's calls): a chip found with
its outputs off says so at connect, and ends a gesture pulsing on the channels it names,
the others left as they were (issue 42)."""

import pytest

from inmoov_dsl import load_profile
from inmoov_dsl.boards import controller
from inmoov_dsl.boards.pca9685 import bus
from inmoov_dsl.boards.pca9685 import chip as regs
from inmoov_dsl.boards.pca9685.bus import I2CPort
from inmoov_dsl.cli import gestplay

PCA = load_profile("rhand-pca9685")
C = controller(PCA, PCA.boards[0])


class ChipBus:
    """One PCA9685 model at 0x40, called as ``smbus2.SMBus`` is."""

    def __init__(self, chip: regs.Chip):
        self.chip = chip

    def write_i2c_block_data(self, address, register, data):
        self.chip.write(register, bytes(data))

    def read_i2c_block_data(self, address, register, length):
        return list(self.chip.read(register, length))

    def close(self):
        pass


@pytest.fixture
def chip(monkeypatch):
    """The chip as it powers up, on ``i2c:1``."""
    found = regs.Chip(C.oscillator)
    monkeypatch.setattr(bus, "open_bus", lambda spec: I2CPort(ChipBus(found), 0x40, spec))
    return found


def width(chip: regs.Chip, name: str) -> float:
    """us of the named servo's pulse (0: none)."""
    return chip.pulse(next(s.pin for s in C.servos if s.name == name)) * 1e6


def test_a_chip_as_it_powers_up_warns_and_holds_what_peace_names(chip, capsys):
    assert gestplay.main(["peace", "--profile", "rhand-pca9685", "--port", "i2c:1"]) == 0
    err = capsys.readouterr().err
    assert err.count("warning") == 1
    assert "gestplay: warning: the PCA9685 of board 181 has its outputs off: wrist, thumb, " \
           "index, middle, ring, pinky limp until a gesture names them" in err
    tick = C.tick * 1e6
    for j, s in enumerate(C.servos):
        if s.name != "wrist":
            value = 0 if s.name in ("index", "middle") else 180
            assert width(chip, s.name) == pytest.approx(C.widths[j].us(value), abs=tick / 2)
    assert width(chip, "wrist") == 0  # not named: left as it was


def test_a_chip_pulsing_on_every_channel_says_nothing(chip, capsys):
    chip.write(regs.MODE1, bytes([regs.AI | regs.ALLCALL]))  # awake, auto-incrementing
    for s in C.servos:
        chip.write(regs.led(s.pin), bytes([0, 0, 0x30, 0x01]))  # 304 ticks: 1.48 ms
    assert gestplay.main(["peace", "--profile", "rhand-pca9685", "--port", "i2c:1"]) == 0
    assert "warning" not in capsys.readouterr().err


def test_the_warning_names_only_the_channels_that_send_no_pulse():
    """The probe's answer: MODE1, PRE_SCALE, then each servo's four LEDn registers;
    full off, or ON equal to OFF, is no pulse."""
    on = bytes([0, 0, 0x30, 0x01])
    leds = {"index": bytes([0, 0, 0, regs.FULL]), "ring": bytes([0x30, 0x01, 0x30, 0x01])}
    answer = bytes([regs.AI, 121]) + b"".join(leds.get(s.name, on) for s in C.servos)
    assert C.ready(answer) and not C.ready(answer[:-1])
    assert C.greeting(answer) == (
        "the PCA9685 of board 181 has its outputs off: index, ring limp until a gesture "
        "names them; the plan takes each to be at its rest (index 0, ring 0), where its "
        "first move starts")
    assert C.greeting(bytes([regs.AI, 121]) + on * len(C.servos)) is None
