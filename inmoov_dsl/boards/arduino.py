"""The Arduinos a board of ours (``rig``) or MyRobotLab's (``mrlcomm``) runs on: their
MCUs and pins, read once here for the profile's checks, the firmware and the sketches."""

from __future__ import annotations

from dataclasses import dataclass

from .table import Choice, Options, Place, PlaceRule

#: (name, its MCU, its digital pins, its first analog pin, A0)
ARDUINOS = (("uno", "atmega328p", 20, 14), ("nano", "atmega328p", 20, 14),
            ("mega", "atmega2560", 70, 54))
NAMES = tuple(a[0] for a in ARDUINOS)


@dataclass(frozen=True)
class Bootloader:
    """What an Arduino's bootloader does on every reset (opening its port resets it),
    as measured with the hex Debian ships, run in simavr (docs/benchmarks.md)."""

    name: str
    hex: str  #: its file under the Arduino core's ``bootloaders/``
    #: s from the reset to the sketch's start when nothing is sent, with a margin
    window: float
    #: s of silence it waits for once a byte came in its window (0: a byte that is not
    #: one of its commands starts the sketch at once)
    trap: float = 0.0
    whose: str = "an Arduino's"  #: the board it is on, as a message names it

    def trapped(self) -> str:
        """What a host waits for when nothing answered after a byte may have trapped it
        (its ``trap``), said once while it waits."""
        return (f"nothing answered yet: {self.whose} bootloader that took a byte for its "
                f"own starts the sketch after {self.trap:g} s of silence; waiting for it")


#: each Arduino's bootloader, the sketch's first byte measured after a reset with nothing
#: sent: the Uno's optiboot 1.40 s, the old Nano's ATmegaBOOT 1.32 s (1.39 s with
#: Arduino's own hex), the Mega's STK500v2 0.84 s. A byte in that time only hurries the
#: first two; the Mega's stays in its command loop until it has heard nothing for 5 s
#: (Debian's build) or 9 s (Arduino's own, what a Mega ships with): a host must not
#: speak first
BOOTLOADERS = {
    "uno": Bootloader("optiboot", "optiboot/optiboot_atmega328.hex", 1.6, whose="an Uno's"),
    "nano": Bootloader("ATmegaBOOT", "atmega/ATmegaBOOT_168_atmega328.hex", 1.5,
                       whose="a Nano's"),
    "mega": Bootloader("STK500v2", "stk500v2/stk500boot_v2_mega2560.hex", 1.5, 9.0,
                       "a Mega's"),
}
#: what a host that does not know which Arduino it opened waits for: the slowest
ANY = Bootloader("any", "", max(b.window for b in BOOTLOADERS.values()),
                 max(b.trap for b in BOOTLOADERS.values()))


def key(default: str) -> Choice:
    """The ``arduino`` key of a board's table, ``default`` when it names none."""
    return Choice("arduino", NAMES, default)


def of(options: Options) -> tuple[str, str, int, int]:
    """The Arduino a board's options name (an Uno when they name none): (name, MCU,
    digital pins, A0's pin)."""
    return ARDUINOS[dict(options).get("arduino", 0)]


def bootloader(options: Options) -> Bootloader:
    """The bootloader of an Arduino board."""
    return BOOTLOADERS[of(options)[0]]


def mcu(options: Options) -> str:
    """The microcontroller of an Arduino board."""
    return of(options)[1]


def most_servos(options: Options) -> int:
    """The servos our firmware pulses on that Arduino (its timers: 12 on an Uno, 32 on a
    Mega; firmware/libraries/InmoovDsl/src/servo_pulses.h)."""
    return 32 if mcu(options) == "atmega2560" else 12


def pins(required: bool) -> PlaceRule:
    """The place rule of an Arduino's servos: a pin from 2 (0 and 1 are its serial port)
    to its last; ``required``: a servo must give one (MrlComm needs it at once; our
    firmware's sketch asks for it when it is built)."""
    def place(board: int, options: Options, pin: int | None) -> Place | None:
        """What is wrong with a servo on ``pin``, or None."""
        name, _, count, _ = of(options)
        if pin is None:
            return Place(f" of board {board}: give the servo's Arduino pin as 'pin'") \
                if required else None
        if 2 <= pin < count:
            return None
        where = ("pins 0 and 1 are the board's serial port" if pin in (0, 1)
                 else f"an Arduino {name.capitalize()} has pins 2..{count - 1}")
        mega = mcu(options) != "atmega2560" and 1 < pin < ARDUINOS[-1][2]
        return Place(f" of board {board}: pin {pin} cannot drive a servo: {where}",
                     'on a Mega? say arduino = "mega" in its [[board]]' if mega else None)
    return place
