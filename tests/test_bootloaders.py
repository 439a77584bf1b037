"""The Arduinos' own bootloaders in front of our firmware, in simavr: every reset starts
the bootloader, as the BOOTRST fuse has a real board start it (``simboard
--bootloader``), and the board's port is a real one's (DTR resets it as a program
opens it; a byte sent at another baud than the bootloader's reaches it garbled). For
each of the Uno, the old Nano and the Mega, from a fresh reset: gestplay connects and
plays, ``gestplay ports`` names the board, and avrdude (a client we did not write)
reads the signature through the same port, as it would to flash the board.

The bootloaders are the hexes Debian ships (arduino-core-avr), but the Uno's: Debian's
optiboot does not fit the Uno's flash (a test below says so), and the harness runs the
same source built to fit (``make -C firmware optiboot``). The times each takes, and what
a stray byte does to each: benchmarks/boot.py and docs/benchmarks.md.

Tests that need a toolchain skip without it, except under CI=true, where a missing
toolchain is a failure.
"""

from __future__ import annotations

import contextlib
import os
import subprocess
import sys
import termios
import time
from dataclasses import dataclass
from pathlib import Path

import pytest
import serial
from toolchain import need

from inmoov_dsl import load_profile
from inmoov_dsl.boards.rig import DumpReader
from inmoov_dsl.compiling.compiler import compile_program
from inmoov_dsl.language.library import scan_library
from inmoov_dsl.language.load import load
from inmoov_dsl.protocol import ASK_POSE

ROOT = Path(__file__).resolve().parent.parent
FIRMWARE = ROOT / "firmware"
ARDUINO = Path("/usr/share/arduino/hardware/arduino/avr")
DEBIAN = ARDUINO / "bootloaders"  #: the bootloaders' hexes Debian ships
GESTURE = "rockon"  #: middle and ring curled: a pose no board starts in


@dataclass(frozen=True)
class Arduino:
    """An Arduino a profile names, with our firmware behind its bootloader."""

    sketch: str  #: the image, built by make -C firmware
    bootloader: str  #: its hex: under Debian's bootloaders/, or under the build
    profile: str  #: a profile whose board 181 is that Arduino
    baud: int  #: the profile's baud
    avrdude: tuple[str, ...]  #: how avrdude talks to the bootloader
    signature: str  #: what avrdude reads
    servos: int  #: board 181's servos


BUILT = "bootloaders/optiboot_atmega328.hex"  #: make -C firmware optiboot
ARDUINOS = {
    "uno": Arduino("servo_rhand", BUILT, "rhand", 9600,
                   ("-c", "arduino", "-p", "m328p", "-b", "115200"), "0x1e950f", 6),
    "nano": Arduino("servo_rhand", "atmega/ATmegaBOOT_168_atmega328.hex",
                    str(ROOT / "tests" / "data" / "rhand-nano.toml"), 9600,
                    ("-c", "arduino", "-p", "m328p", "-b", "57600"), "0x1e950f", 6),
    "mega": Arduino("servo_inmoov_right", "stk500v2/stk500boot_v2_mega2560.hex", "inmoov",
                    115200, ("-c", "wiring", "-p", "atmega2560", "-b", "115200", "-D"),
                    "0x1e9801", 10),
}


@pytest.fixture(scope="module")
def build(tmp_path_factory):
    """The images, the harness and the Uno's bootloader, built once for this module."""
    need("make", "avr-gcc", "avr-g++", "cc", "/usr/include/simavr/sim_avr.h",
         str(ARDUINO / "cores"), str(DEBIAN / "optiboot" / "optiboot.c"))
    where = tmp_path_factory.mktemp("bootloaders-build")
    done = subprocess.run(["make", "-C", str(FIRMWARE), "-j2", f"BUILD={where}", "servo_rhand",
                           "servo_inmoov_right", "harness", "optiboot"],
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stdout + done.stderr
    return where


def hex_of(build: Path, arduino: Arduino) -> Path:
    path = build / arduino.bootloader if arduino.bootloader == BUILT else \
        DEBIAN / arduino.bootloader
    need(str(path))
    return path


@contextlib.contextmanager
def served(build: Path, arduino: Arduino, tmp: Path):
    """The port of a board just powered up, its bootloader in front of our firmware,
    served on a pty in real time (what simavr says goes to a file: a pipe nobody reads
    could fill and stop it)."""
    said = tmp / "simboard.stderr"
    with open(said, "w") as err:
        proc = subprocess.Popen([str(build / "harness" / "simboard"),
                                 str(build / f"{arduino.sketch}.elf"), "--pty", "--baud",
                                 str(arduino.baud), "--bootloader", str(hex_of(build, arduino))],
                                stdout=subprocess.PIPE, stderr=err, text=True)
    try:
        path = proc.stdout.readline().strip()
        assert path.startswith("/dev/"), said.read_text()
        yield path
    finally:
        proc.kill()
        proc.wait()


@pytest.fixture(params=list(ARDUINOS))
def board(request, build, tmp_path):
    """(name, the Arduino, its port): a board just powered up (``served``)."""
    arduino = ARDUINOS[request.param]
    with served(build, arduino, tmp_path) as path:
        yield request.param, arduino, path


def gestplay(*argv: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "inmoov_dsl.cli.gestplay", *argv],
                          capture_output=True, text=True, timeout=90)


def dump(path: str, baud: int, board: int = 181, timeout: float = 5.0) -> dict[int, int]:
    """The board's pose, asked with DUMP on a port that does not reset it (the last
    program left DTR up)."""
    port = serial.Serial(path, baud, timeout=0)
    try:
        port.write(ASK_POSE)
        reader, deadline = DumpReader(board), time.monotonic() + timeout
        while time.monotonic() < deadline:
            if (found := reader.feed(port.read(4096))) is not None:
                return found
            time.sleep(0.01)
    finally:
        port.close()
    raise AssertionError(f"board {board} did not answer DUMP in {timeout} s")


def final_pose(profile_name: str, board: int = 181) -> dict[int, int]:
    """Servo ID -> value of ``board``'s servos at the end of GESTURE."""
    profile = load_profile(profile_name)
    source = scan_library([ROOT / "gestures"])[GESTURE].path
    compiled, _ = compile_program(load(str(source)), GESTURE, profile)
    return {s.id: v for s, v in zip(profile.servos, compiled.final, strict=True)
            if s.board == board}


def test_the_port_opens_as_a_serial_device_does(build, tmp_path):
    """A program that reads the port's settings right after opening it finds what a
    serial driver sets (HUPCL: DTR drops when it closes; 9600 baud), not a pty's."""
    with served(build, ARDUINOS["uno"], tmp_path) as path:
        port = os.open(path, os.O_RDWR | os.O_NOCTTY | os.O_NONBLOCK)
        try:
            attrs = termios.tcgetattr(port)
        finally:
            os.close(port)
    assert attrs[2] & termios.HUPCL
    assert attrs[4] == attrs[5] == termios.B9600


def test_debians_optiboot_does_not_fit_an_uno(build):
    """Debian's optiboot_atmega328.hex (gcc-avr 5.4) runs 20 bytes past the end of the
    ATmega328P's flash, over the 512-byte boot section (Debian bug #985578; avrdude
    refuses to burn it): the harness refuses it too, and the Uno runs the same source
    built to fit (make -C firmware optiboot)."""
    debian = DEBIAN / "optiboot" / "optiboot_atmega328.hex"
    need(str(debian))
    done = subprocess.run([str(build / "harness" / "simboard"), str(build / "servo_rhand.elf"),
                           "--bootloader", str(debian)], input="", capture_output=True,
                          text=True, timeout=60)
    assert done.returncode == 1
    assert f"simboard: {debian} does not fit the flash of an atmega328p" in done.stderr
    built = (build / BUILT).read_text().splitlines()
    ends = [int(line[3:7], 16) + int(line[1:3], 16) for line in built if line[7:9] == "00"]
    assert max(ends) <= 0x8000  # the built one ends within the flash


def test_a_play_from_a_fresh_reset_connects_and_plays(board):
    """The port's first open resets the board into its bootloader: gestplay waits it
    out (the Mega's traps a byte sent too early), plays, and the board holds the
    gesture's pose."""
    name, arduino, path = board
    done = gestplay(GESTURE, "--profile", arduino.profile, "--port", path)
    assert done.returncode == 0, f"{name}: {done.stderr}"
    assert done.stdout.startswith(f"played {GESTURE}: "), done.stdout
    assert dump(path, arduino.baud) == final_pose(arduino.profile)


def test_gestplay_ports_names_the_board_behind_its_bootloader(board):
    name, arduino, path = board
    done = gestplay("ports", "--port", path)
    assert done.returncode == 0, f"{name}: {done.stderr}"
    said = f"board 181, {arduino.servos} servos"
    if arduino.baud != 9600:
        said += f" at {arduino.baud} baud"
    assert said in done.stdout, f"{name}: {done.stdout}{done.stderr}"


def test_avrdude_reads_the_signature_from_the_bootloader(board):
    """avrdude resets the board as it opens the port (its own DTR pulse cannot reach a
    pty: the open is what resets it) and reads the signature; -n writes nothing."""
    need("avrdude")
    name, arduino, path = board
    done = subprocess.run(["avrdude", *arduino.avrdude, "-P", path, "-n"],
                          capture_output=True, text=True, timeout=90)
    assert done.returncode == 0, f"{name}: {done.stderr}"
    assert f"device signature = {arduino.signature}" in done.stderr, done.stderr


def test_avrdude_after_a_play_once_a_close_has_dropped_dtr(build, tmp_path):
    """gestplay leaves DTR up (it clears HUPCL): avrdude's open then makes no edge, and
    its own DTR pulse cannot reach a pty (on a real port it resets the board). A program
    that closes the port with HUPCL set drops DTR, however briefly it had it open (stty
    hupcl), and avrdude's open resets the board into its bootloader."""
    need("avrdude")
    arduino = ARDUINOS["uno"]
    with served(build, arduino, tmp_path) as path:
        done = gestplay(GESTURE, "--port", path)
        assert done.returncode == 0, done.stderr
        port = os.open(path, os.O_RDWR | os.O_NOCTTY | os.O_NONBLOCK)  # as stty hupcl does
        try:
            attrs = termios.tcgetattr(port)
            attrs[2] |= termios.HUPCL
            termios.tcsetattr(port, termios.TCSANOW, attrs)
        finally:
            os.close(port)
        # the harness sees the port hung up when its thread next looks at the pty, which on
        # a machine whose cores are taken may be later than a tenth of a second; avrdude's
        # open must come after it to be the edge that resets the board
        time.sleep(1.0)
        done = subprocess.run(["avrdude", *arduino.avrdude, "-P", path, "-n"],
                              capture_output=True, text=True, timeout=90)
    assert done.returncode == 0, done.stderr
    assert f"device signature = {arduino.signature}" in done.stderr
