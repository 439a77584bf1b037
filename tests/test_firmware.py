"""The firmware: its protocol core on this computer (the board's conformance vectors, a
fuzz run, the glove), the constants against Python's, the generated settings, the build
for the ATmega328P, and the built image running in simavr on library streams and on a
pseudo-terminal that gestplay plays to.

Tests that need a toolchain skip without it, except under CI=true, where a missing
toolchain is a failure.
"""

import itertools
import json
import re
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest
import serial
from conftest import WHOLE_ROBOT
from toolchain import need

from inmoov_dsl import load_profile, to_timed
from inmoov_dsl.boards.pulses import PULSE_MAX, PULSE_MIN, pulse_us
from inmoov_dsl.boards.rig.core import BoardCore, BoardServo
from inmoov_dsl.compiling.compiler import compile_program
from inmoov_dsl.errors import GestError
from inmoov_dsl.firmware.sketches import sketches
from inmoov_dsl.language.library import scan_library
from inmoov_dsl.language.load import load
from inmoov_dsl.protocol import FIRST_BOARD_ID, MAX_SERVO_ID, MAX_VALUE, POSE_SETTLE, Signal
from inmoov_dsl.wire.player import Link, play
from inmoov_dsl.wire.ready import ask_dump, wait_ready
from inmoov_dsl.wire.sim import VirtualBoard

ROOT = Path(__file__).resolve().parent.parent
FIRMWARE = ROOT / "firmware"
CORE = FIRMWARE / "libraries" / "InmoovDsl" / "src"
VECTORS = json.loads((ROOT / "tests" / "vectors" / "board.json").read_text())
LIBRARY = scan_library([ROOT / "gestures"])
SHIPPED = ("rhand", "lhand", "inmoov")


def make(build, *targets, **variables):
    need("make")
    args = ["make", "-C", str(FIRMWARE), "-j2", f"BUILD={build}", *targets,
            *(f"{k}={v}" for k, v in variables.items())]
    return subprocess.run(args, capture_output=True, text=True, timeout=600)


@pytest.fixture(scope="session")
def build(tmp_path_factory):
    """A build directory of this run's own: every board is built from scratch."""
    return tmp_path_factory.mktemp("firmware-build")


@pytest.fixture(scope="session")
def driver(build):
    need("g++", "make")
    done = make(build, "host")
    assert done.returncode == 0, done.stderr
    return build / "host" / "core_driver"


@pytest.fixture(scope="session")
def boards(build):
    need("avr-gcc", "avr-g++", "make", "/usr/share/arduino/hardware/arduino/avr/cores")
    done = make(build, "all")
    assert done.returncode == 0, done.stdout + done.stderr
    return done.stdout


@pytest.fixture(scope="session")
def simboard(build, boards):
    need("/usr/include/simavr/sim_avr.h", "cc")
    done = make(build, "harness")
    assert done.returncode == 0, done.stderr
    return build / "harness" / "simboard"


# -- the protocol constants, once in Python and once in the firmware -----------------
def test_the_constants_are_the_same_in_python_and_cpp():
    header = (CORE / "inmoov_protocol.h").read_text()
    signals = dict(re.findall(r"^\s+([A-Z]+) = (\d+),", header, re.M))
    assert {name: int(v) for name, v in signals.items()} == {s.name: int(s) for s in Signal}
    consts = dict(re.findall(r"const uint8_t (\w+) = (\w+);", header))
    assert int(consts["MAX_VALUE"]) == MAX_VALUE
    assert int(consts["MAX_SERVO_ID"]) == MAX_SERVO_ID
    assert int(consts["FIRST_BOARD_ID"]) == FIRST_BOARD_ID
    settle = re.search(r"const uint16_t POSE_SETTLE_MS = (\d+);", header)
    assert int(settle[1]) == round(POSE_SETTLE * 1000)
    core = (CORE / "servo_core.h").read_text()
    pulse = dict(re.findall(r"const uint16_t (PULSE_M\w+_US) = (\d+);", core))
    assert (int(pulse["PULSE_MIN_US"]), int(pulse["PULSE_MAX_US"])) == (PULSE_MIN, PULSE_MAX)


# -- the settings come from the profiles ---------------------------------------------
@pytest.mark.parametrize("name", SHIPPED)
def test_the_committed_sketches_are_generated_from_the_profiles(name):
    profile = load_profile(name)
    made = sketches(profile)
    assert len(made) == len(profile.boards) + len(profile.gloves)  # one for each
    for folder, files in made.items():
        for file, text in files.items():
            path = FIRMWARE / folder / file
            assert path.is_file(), f"{path} is missing: gestc firmware {name}"
            assert path.read_text() == text, f"{path} is stale: run gestc firmware {name}"


def test_firmware_check_finds_a_stale_header(tmp_path, capsys):
    from inmoov_dsl.cli import gestc

    assert gestc.main(["firmware", "rhand", "-o", str(tmp_path)]) == 0
    assert (tmp_path / "libraries" / "InmoovDsl" / "src" / "servo_core.cpp").is_file()
    assert (tmp_path / "Makefile").is_file()
    assert gestc.main(["firmware", "rhand", "-o", str(tmp_path), "--check"]) == 0
    settings = tmp_path / "servo_rhand" / "settings.h"
    settings.write_text(settings.read_text().replace("{2, 4, 55, 155", "{2, 4, 60, 155"))
    capsys.readouterr()
    assert gestc.main(["firmware", "rhand", "-o", str(tmp_path), "--check"]) == 1
    assert capsys.readouterr().out == (f"{settings}: out of date (gestc firmware rhand -o "
                                       f"{tmp_path})\n")


def test_a_board_of_ours_has_no_more_servos_than_its_timers_pulse():
    from conftest import make_profile

    crowded = make_profile({181: [f"s{i}" for i in range(13)]}, name="crowded")
    with pytest.raises(GestError) as info:
        sketches(crowded)
    assert info.value.first.message == ("profile 'crowded': board 181 has 13 servos, and our "
                                        "firmware pulses at most 12 on an Arduino Uno (its "
                                        "timers)")
    assert info.value.first.hint == 'a Mega pulses 32: arduino = "mega" in its [[board]]'


def test_settings_say_what_the_board_needs():
    rhand = load_profile("rhand")
    files = sketches(rhand, baud=115200)
    assert set(files) == {"servo_rhand", "glove_rhand"}
    servo = files["servo_rhand"]["settings.h"]
    assert "const uint8_t BOARD_ID = 181;" in servo
    assert "const long BAUD = 115200;" in servo
    assert "{2, 4, 55, 155, 1, 0},  // index" in servo
    glove = files["glove_rhand"]["settings.h"]
    assert "{1, 14, 579, 713, 0},  // thumb" in glove
    assert "const long BOARD_BAUD = 115200;" in glove
    assert set(sketches(load_profile("inmoov-six"))) == {
        "servo_inmoov_six_right_hand", "servo_inmoov_six_left_hand", "servo_inmoov_six_head",
        "servo_inmoov_six_torso", "servo_inmoov_six_right_arm", "servo_inmoov_six_left_arm"}
    megas = sketches(load_profile("inmoov"))
    assert set(megas) == {"servo_inmoov_right", "servo_inmoov_left"}
    left = megas["servo_inmoov_left"]
    assert left["board.mk"].endswith("\nMCU = atmega2560\n")  # make builds it for a Mega
    assert "const uint8_t SERVO_COUNT = 18;" in left["settings.h"]
    assert "{14, 26, 10, 25, 0, 0},  // jaw" in left["settings.h"]
    # the Arduino IDE refuses it for any other board, and says which to choose
    assert ('#if defined(__AVR__) && !defined(__AVR_ATmega2560__)\n#error "board 183 (left) '
            'is an Arduino Mega 2560: choose Tools > Board > Arduino Mega or Mega 2560"') in \
        left["settings.h"]
    assert "board.mk" not in files["servo_rhand"] and "#error" not in servo


# -- the core on this computer --------------------------------------------------------
def board_script(servos=VECTORS["servos"], board=VECTORS["board"], pins=range(2, 100)):
    lines = [f"board {board}"]
    lines += [f"servo {s['id']} {pin} {s['calibration'][0]} {s['calibration'][1]} "
              f"{int(s['reversed'])} {s['default']}" for s, pin in zip(servos, pins, strict=False)]
    return lines


def run_driver(driver, mode, lines, *args):
    done = subprocess.run([str(driver), mode, *map(str, args)], input="\n".join(lines) + "\n",
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stdout + done.stderr
    return done.stdout.splitlines()


def test_the_core_passes_the_boards_conformance_vectors(driver):
    cases = VECTORS["cases"]
    out = run_driver(driver, "servo", board_script() + [
        "case " + " ".join(map(str, c["in"])) for c in cases])
    assert len(out) == len(cases)
    for case, line in zip(cases, out, strict=True):
        writes, sent, relaxed = line.split(" | ")
        numbers = list(map(int, writes.split()[1:]))
        assert [numbers[k:k + 3] for k in range(0, len(numbers), 3)] == case["writes"], \
            case["name"]
        assert list(map(int, sent.split()[1:])) == case["out"], case["name"]
        assert relaxed == f"relaxed {int(case.get('relaxed', False))}", case["name"]


def test_the_core_maps_values_to_angles_and_pulses_as_python_does(driver):
    """Every value on every calibration shape: the angle of Arduino's map() and the
    pulse of the Servo library, in C++ and in Python alike."""
    shapes = [(0, 180, 0), (125, 160, 1), (50, 160, 1), (35, 155, 0), (0, 0, 1), (7, 173, 1)]
    servos = [{"id": k, "calibration": [lo, hi], "reversed": bool(rev), "default": 0}
              for k, (lo, hi, rev) in enumerate(shapes)]
    out = run_driver(driver, "servo", board_script(servos) + [
        "begin" + f" {value}" * len(shapes) for value in range(181)])
    for value, line in enumerate(out):
        expected = []  # servo index, angle, pulse in us
        for index, s in enumerate(servos):
            servo = BoardServo(s["id"], tuple(s["calibration"]), s["reversed"])
            expected += [index, servo.angle(value), servo.pulse(value)]
        assert list(map(int, line.split()[1:])) == expected, value
    assert pulse_us(0) == 544 and pulse_us(90) == 1472 and pulse_us(180) == 2400
    rests = [dict(s, default=30 * k) for k, s in enumerate(servos)]  # no pose: the rests
    (line,) = run_driver(driver, "servo", board_script(rests) + ["begin"])
    assert list(map(int, line.split()[1:])) == [
        n for k, s in enumerate(rests) for n in (k, BoardServo(
            s["id"], tuple(s["calibration"]), s["reversed"]).angle(30 * k),
            BoardServo(s["id"], tuple(s["calibration"]), s["reversed"]).pulse(30 * k))]


# -- the pose kept in EEPROM, on this computer ----------------------------------------
RHAND_SERVOS = board_script()[1:]


def store(driver, *lines, board=181, servos=RHAND_SERVOS):
    return run_driver(driver, "store", [f"board {board}", *servos, *lines])


def test_a_new_eeprom_holds_no_pose_and_a_settled_pose_is_kept(driver):
    out = store(driver, "boot",
                "write 0 10 20 30 40 50 60", "run 999", "wear",  # not settled yet
                "run 1100", "wear",                               # a second: one record
                "boot",                                           # a reset
                "write 5000 10 20 30 40 50 60", "run 9000", "wear",  # the same pose: nothing
                "write 9500 11 20 30 40 50 60", "run 10400", "boot")
    assert out == ["boot none", "wear 0 0", "wear 10 1", "boot 10 20 30 40 50 60 seq 1",
                   "wear 10 1", "boot 10 20 30 40 50 60 seq 1"]  # 10.4 s: not settled


def test_a_record_cut_short_by_a_power_loss_is_never_read_back(driver):
    for written in range(10):  # the power fails after this many bytes of the new record
        out = store(driver, "boot", "write 0 10 20 30 40 50 60", "run 1100",
                    "write 2000 90 90 90 90 90 90", f"cut {written}", "run 4000", "boot")
        assert out[-1] == "boot 10 20 30 40 50 60 seq 1", written
    out = store(driver, "boot", "write 0 10 20 30 40 50 60", "run 1100",
                "write 2000 90 90 90 90 90 90", "cut 10", "run 4000", "boot")
    assert out[-1] == "boot 90 90 90 90 90 90 seq 2"


def test_records_go_round_the_eeprom_so_every_cell_wears_alike(driver):
    """300 poses: a record of 10 bytes in each of 102 slots in turn, so no cell is
    written more than three times (each byte only when it changes)."""
    lines = ["boot"]
    for k in range(300):
        lines += [f"write {2000 * k} " + " ".join(str((k + i) % 181) for i in range(6)),
                  f"run {2000 * k + 1500}"]
    out = store(driver, *lines, "wear", "boot")
    total, most = map(int, out[-2].split()[1:])
    assert most == 3 and 2000 < total <= 3000
    assert out[-1] == "boot " + " ".join(str((299 + i) % 181) for i in range(6)) + " seq 300"


def test_the_newest_record_is_found_when_the_sequence_wraps(driver):
    """65,540 poses: the sequence number passes 65535 and starts at 0 again."""
    lines = ["boot"]
    for k in range(65540):
        lines += [f"write {1100 * k} {k % 2} 0 0 0 0 {k % 7}", f"run {1100 * k + 1050}"]
    out = store(driver, *lines, "boot")
    assert out[-1] == "boot 1 0 0 0 0 5 seq 4"  # k = 65,539; 65,540 records % 65,536


def test_rubbish_and_another_boards_records_are_no_pose(driver):
    out = store(driver, "fill 0", "boot", "fill 255", "boot", "fill 90", "boot")
    assert out == ["boot none"] * 3
    written = store(driver, "boot", "write 0 1 2 3 4 5 6", "run 1100", "boot")
    assert written[-1] == "boot 1 2 3 4 5 6 seq 1"
    # the same EEPROM read by a board with another ID, or other servos: no pose
    other = store(driver, "boot", "write 0 1 2 3 4 5 6", "run 1100", "board 183", "boot")
    assert other[-1] == "boot none"


def test_fuzz_the_core_never_writes_out_of_range_and_recovers_after_cancel(driver):
    for seed in (1, 2, 3):
        assert run_driver(driver, "fuzz", board_script(), 300_000, seed) == [
            "ok 300000 bytes"]


GLOVE = ["deadband 2", "sensor 1 14 579 713 0", "sensor 2 15 519 743 0",
         "sensor 3 16 588 793 1"]


def test_the_glove_maps_sends_what_changed_and_ignores_noise(driver):
    out = run_driver(driver, "glove", GLOVE + [
        "read 579 519 793",   # first reading: every sensor, thumb 0, index 0, middle (rev.) 0
        "read 580 520 792",   # noise under the dead-band: nothing
        "read 646 631 690",   # thumb and index half way, middle (reversed) half way
        "read 647 631 690",   # one degree: nothing
        "read 713 743 588",   # the ends: 180, 180, and reversed 180
        "read 900 100 1000",  # beyond the calibration: clamped
    ])
    assert out == [
        "sent 255 1 0 2 0 3 0",
        "sent",
        "sent 255 1 90 2 90 3 91",
        "sent",
        "sent 255 1 180 2 180 3 180",
        "sent 255 2 0 3 0",
    ]


def test_the_glove_captures_its_calibration_from_min_and_max(driver):
    out = run_driver(driver, "glove", GLOVE + [
        "read 100 200 300",
        "host 250",          # MIN: these readings are now 0 (and everything is resent)
        "read 100 200 300",
        "read 400 500 600",
        "host 249",          # MAX: these are now 180
        "read 400 500 600",
        "read 250 350 450",
        "host 255",          # anything else from the computer: ignored
        "read 250 350 450",
    ])
    assert out[2] == "sent 255 1 0 2 0 3 180"  # middle is reversed
    assert out[5] == "sent 255 1 180 2 180 3 0"
    assert out[6] == "sent 255 1 90 2 90 3 90"
    assert out[7:] == ["sent", "sent"]


def test_the_python_glove_answers_like_the_firmware_glove(driver):
    """The same readings and commands into the C++ core and the Python one (the virtual
    glove of gestsim --glove): the same bytes."""
    import random

    from inmoov_dsl.wire.glove import GloveCore as PythonGlove

    rng = random.Random(5)
    script = []
    for _ in range(400):
        if rng.random() < 0.05:
            script.append(f"host {rng.choice([249, 250, 255, 7])}")
        else:
            script.append("read " + " ".join(str(rng.randint(400, 900)) for _ in range(3)))
    cpp = run_driver(driver, "glove", GLOVE + script)
    python = PythonGlove([1, 2, 3], [(579, 713), (519, 743), (588, 793)], [False, False, True],
                         2)
    readings = [0, 0, 0]
    expected = []
    for line in script:
        kind, *numbers = line.split()
        if kind == "read":
            readings = list(map(int, numbers))
            sent = python.update(readings)
        else:
            python.feed(int(numbers[0]), readings)
            sent = b""
        expected.append(" ".join(["sent", *map(str, sent)]))
    assert cpp == expected


# -- the build ----------------------------------------------------------------------
ORIGINAL_FLASH = 3872  # bytes: the original servo firmware with the real Servo library


def test_every_board_builds_and_says_what_it_uses(build, boards):
    names = sorted(folder for name in SHIPPED for folder in sketches(load_profile(name)))
    for name in names:
        assert (build / f"{name}.elf").is_file() and (build / f"{name}.hex").is_file()
        flash, ram = (253952, 8192) if "inmoov" in name else (30720, 2048)  # Megas, Unos
        assert re.search(rf"^{name}: flash \d+ of {flash} bytes \(\d+%\), RAM \d+ of {ram} "
                         rf"bytes \(\d+%\)$", boards, re.M), (name, boards)
    # built for the microcontroller of its board: the ELF header's machine flags
    for name, mach in (("servo_rhand", 5), ("servo_inmoov_left", 6)):  # avr5, avr6
        assert (build / f"{name}.elf").read_bytes()[36] & 0x7F == mach
    # the right hand's board, servo driver and stored pose included, is smaller than the
    # original firmware was with the Arduino Servo library, and leaves RAM to spare
    flash, ram = map(int, re.search(r"^servo_rhand: flash (\d+) of \d+ bytes \(\d+%\), "
                                    r"RAM (\d+)", boards, re.M).groups())
    assert flash < ORIGINAL_FLASH and ram <= 400, (flash, ram)


def test_a_board_that_does_not_fit_fails_the_build(boards, tmp_path):
    done = make(tmp_path, "servo_rhand", FLASH_MAX=1000)
    assert done.returncode != 0
    assert re.search(r"^servo_rhand: does not fit: \d+ bytes of flash over$", done.stdout,
                     re.M), done.stdout
    assert not (tmp_path / "servo_rhand.hex").exists()
    done = make(tmp_path, "servo_rhand", RAM_MAX=400)
    assert done.returncode != 0
    assert re.search(r"^servo_rhand: does not fit: \d+ bytes of RAM leave less than 256 for "
                     r"the stack$", done.stdout, re.M), done.stdout


# -- the image in the simulator --------------------------------------------------------
def simulate(simboard, elf, timed: str, *options, baud=9600):
    """Run ``timed`` on the image in simavr: its replies, bytes read, the DUMP at the
    end, every pin's pulses, every EEPROM byte written."""
    done = subprocess.run([str(simboard), str(elf), "--baud", str(baud), *map(str, options)],
                          input=timed, capture_output=True, text=True, errors="replace",
                          timeout=300)
    assert done.returncode == 0, done.stderr
    result = {"out": [], "pins": {}, "pulses": [], "eeprom": []}
    for line in done.stdout.splitlines():
        key, *rest = line.split()
        if key == "out":
            result["out"].append((float(rest[0]), int(rest[1])))
        elif key == "dump":
            board, _, *body = map(int, rest)
            result["dump"] = (board, dict(zip(body[0::2], body[1::2], strict=True)))
        elif key == "pin":  # pin P pulses N first W last W period MIN MAX
            result["pins"][int(rest[0])] = {
                "pulses": int(rest[2]), "first": float(rest[4]), "last": float(rest[6]),
                "period": (float(rest[8]), float(rest[9]))}
        elif key == "pulse":
            result["pulses"].append((int(rest[0]), float(rest[1]), float(rest[2])))
        elif key == "eeprom":
            result["eeprom"].append((float(rest[0]), int(rest[1]), int(rest[2])))
        else:
            result[key] = float(rest[0]) if key in ("ready", "cut") else int(rest[0])
    return result


RHAND = load_profile("rhand")
RHAND_PINS = {s.pin: BoardServo(s.id, s.calibration, s.reversed, s.rest)
              for s in RHAND.servos}
JITTER = 8.0  # us: another interrupt (the serial port's, the clock's) may delay an edge;
# the original firmware's worst is 6.1 us on the library, one physical degree is ~10 us


def pulses_of(pose: dict[int, int]) -> dict[int, int]:
    """Pin -> the pulse width (us) the original firmware gives servo ID -> value."""
    return {pin: s.pulse(pose[s.id]) for pin, s in RHAND_PINS.items()}


def assert_pins(pins, expected: dict[int, int], which="last", periods=True):
    """Each servo pin's (first or last) pulse is the expected width and no other pin
    pulses. A frame is 20 ms: the first servo's pulse starts every 20 ms, the others
    follow the pulses before them, so theirs move by as much as those pulses change
    (``periods=False``: the pulses stopped for a while, RELAX)."""
    assert set(pins) == set(expected)
    for pin, width in expected.items():
        assert abs(pins[pin][which] - width) <= JITTER, (pin, pins[pin], width)
        if periods and pins[pin]["pulses"] > 1:
            shortest, longest = pins[pin]["period"]
            slack = 0.01 if pin == min(expected) else 2.5  # ms
            assert 20 - slack <= shortest and longest <= 20 + slack, (pin, pins[pin])


HAND = sorted(n for n, e in LIBRARY.items() if e.path.name not in WHOLE_ROBOT)


def test_the_firmware_answers_like_the_virtual_board(simboard, build):
    """The same stream into the image and into the Python board: the same replies."""
    rhand = load_profile("rhand")
    compiled, _ = compile_program(load(str(LIBRARY["wiggle"].path)), "wiggle", rhand)
    stream = compiled.stream()
    result = simulate(simboard, build / "servo_rhand.elf", to_timed(stream))
    board = VirtualBoard(BoardCore.from_profile(rhand, rhand.boards[0]), 9600)
    board.advance(0.0)
    for t, b in zip(stream.times.tolist(), stream.data, strict=True):
        board.write(bytes([b]), t)
    board.write(bytes([Signal.DUMP]), stream.times[-1] + 0.05)
    python = board.read(1e9)
    firmware = bytes(b for _, b in result["out"])
    assert firmware == python


def test_a_burst_at_wire_speed_loses_no_byte(simboard, build):
    """Bytes back to back for 3 s (2,880 at 9600 baud) never overflow the 64-byte buffer."""
    data = [255] + [b for k in range(1439) for b in (k % 6, k % 181)]
    timed = "".join(f"0.000000 {b}\n" for b in data)  # all due at once: the wire paces them
    result = simulate(simboard, build / "servo_rhand.elf", timed)
    assert result["read"] == result["sent"] == len(data) + 1
    expected = {sid: v for sid, v in zip(data[1::2], data[2::2], strict=True)}
    assert result["dump"] == (181, expected)


def test_the_head_of_the_whole_robot_nods(simboard, build):
    inmoov = load_profile("inmoov")
    compiled, _ = compile_program(load(str(LIBRARY["nod"].path)), "nod", inmoov)
    result = simulate(simboard, build / "servo_inmoov_left.elf",
                      to_timed(compiled.stream(183)), baud=115200)
    left = [s for s in inmoov.servos if s.board == 183]
    assert result["dump"] == (183, {s.id: compiled.final[inmoov.index(s.name)] for s in left})
    assert result["read"] == result["sent"]


# -- the Megas of the InMoov ---------------------------------------------------------
INMOOV = load_profile("inmoov")
MEGA_JITTER = 10.0  # us: two timers' interrupts and the serial port's may meet


def mega_servos(board: int) -> dict[int, BoardServo]:
    """Pin -> the servo on it, of the InMoov's Mega ``board``."""
    return {s.pin: BoardServo(s.id, s.calibration, s.reversed, s.rest)
            for s in INMOOV.servos if s.board == board}


def every_servo(board: int, step: int = 0) -> str:
    """A gesture that moves every servo of Mega ``board`` to a value of its own."""
    moves = ", ".join(f"{s.name} {(37 * k + 20 + step) % 170 + 5}"
                      for k, s in enumerate(s for s in INMOOV.servos if s.board == board))
    return f"g: {moves} over 1s\n"


def assert_mega_pins(pins, board: int, pose: dict[int, int], which="last"):
    """Every servo pin of the Mega pulses the width its value maps to, within
    MEGA_JITTER, a pulse every 20 ms; no other pin pulses."""
    servos = mega_servos(board)
    assert set(pins) == set(servos)
    for pin, servo in servos.items():
        width = servo.pulse(pose[servo.id])
        assert abs(pins[pin][which] - width) <= MEGA_JITTER, (pin, pins[pin], width)
        if pins[pin]["pulses"] > 1:
            shortest, longest = pins[pin]["period"]
            assert shortest >= 19.8 and longest <= 20.2, (pin, pins[pin])


@pytest.mark.parametrize("board", [181, 183])
def test_a_mega_pulses_every_servo_of_its_board_at_its_width(simboard, build, board):
    """Both Megas of the InMoov (10 and 18 servos: two and three of its timers), every
    servo moved at once at 115200 baud: each pin ends at its width, the widths the
    virtual board gives, a pulse every 20 ms, and the first servo of each timer exactly
    every 20 ms."""
    compiled, _ = compile_program(load("m.gest", every_servo(board)), "g", INMOOV)
    name = "servo_inmoov_left" if board == 183 else "servo_inmoov_right"
    result = simulate(simboard, build / f"{name}.elf", to_timed(compiled.stream(board)),
                      "--pulses", baud=115200)
    ours = {s.id: compiled.final[INMOOV.index(s.name)] for s in INMOOV.servos
            if s.board == board}
    assert result["dump"] == (board, ours) and result["read"] == result["sent"]
    assert_mega_pins(result["pins"], board, ours)
    servos = [s for s in INMOOV.servos if s.board == board]
    for first in servos[::8]:  # the first channel of each timer (8 each) starts its frame
        starts = [t for pin, t, _ in result["pulses"] if pin == first.pin]
        gaps = [b - a for a, b in itertools.pairwise(starts)]
        assert all(abs(g - 0.020) < 1e-5 for g in gaps), first.name
    # every pulse on the way is within the jitter of a width some value maps to
    widths = {pin: sorted(s.pulse(v) for v in range(181))
              for pin, s in mega_servos(board).items()}
    worst = max(min(abs(w - x) for x in widths[pin]) for pin, _, w in result["pulses"])
    assert worst <= MEGA_JITTER


def test_a_mega_keeps_its_pose_across_a_reset(simboard, build, tmp_path):
    elf, eeprom = build / "servo_inmoov_left.elf", tmp_path / "eeprom.bin"
    compiled, _ = compile_program(load("m.gest", every_servo(183, 7)), "g", INMOOV)
    first = simulate(simboard, elf, to_timed(compiled.stream(183)), "--eeprom", eeprom,
                     "--run-on", 1.2, baud=115200)
    rest = {s.id: s.rest for s in INMOOV.servos if s.board == 183}
    assert_mega_pins(first["pins"], 183, rest, "first")  # a new board: its rest, at once
    assert len(eeprom.read_bytes()) == 4096  # the Mega's EEPROM
    pose = {s.id: compiled.final[INMOOV.index(s.name)] for s in INMOOV.servos
            if s.board == 183}
    again = simulate(simboard, elf, "", "--eeprom", eeprom, baud=115200)
    assert again["dump"] == (183, pose)
    assert_mega_pins(again["pins"], 183, pose, "first")  # from its first pulse
    relax = simulate(simboard, elf, timed_bytes([255, 248, 255]), "--pulses", baud=115200)
    assert not [t for _, t, _ in relax["pulses"] if t > 0.1]  # RELAX: every pin quiet


def timed_bytes(data, start=0.0, gap=0.01) -> str:
    return "".join(f"{start + k * gap:.6f} {b}\n" for k, b in enumerate(data))


REST = {s.id: s.rest for s in RHAND.servos}
RHAND_IDS = [s.id for s in RHAND.servos]


def test_the_image_reads_bytes_as_the_original_firmware_does(simboard, build):
    """The conformance vectors on the built image: what it answers, the pose its DUMP
    reports, and what each servo pin then carries (nothing, once relaxed)."""
    def one(case):
        return case, simulate(simboard, build / "servo_rhand.elf", timed_bytes(case["in"]),
                              "--pulses")

    checked = []
    with ThreadPoolExecutor(max_workers=2) as pool:
        for case, result in pool.map(one, VECTORS["cases"]):
            checked.append(case["name"])
            pose = dict(REST)
            pose.update({sid: value for sid, value, _ in case["writes"]})
            assert result["dump"] == (181, pose), case["name"]
            replies = [b for _, b in result["out"] if b != Signal.WAIT]
            assert replies[:len(case["out"])] == case["out"], case["name"]
            assert replies[len(case["out"]):] == [252, 181, 6, *[b for sid in sorted(pose)
                                                               for b in (sid, pose[sid])], 251]
            last = max(t for _, t, _ in result["pulses"])
            if case.get("relaxed"):  # no pulse once RELAX was read (its index, 10 ms apart)
                relaxed_at = case["in"].index(Signal.RELAX) * 0.01 + 0.002
                assert last < relaxed_at + 0.003, case["name"]
            else:
                assert_pins(result["pins"], pulses_of(pose), periods=Signal.RELAX not in
                            case["in"])
                # still pulsing: in the last frame before the DUMP's reply ended
                assert last > len(case["in"]) * 0.01 + 0.05 - 0.02, case["name"]
    assert len(checked) == len(VECTORS["cases"]) > 0  # every vector


def test_relaxed_servos_get_no_pulse_until_the_next_command(simboard, build):
    data = [255, 2, 90, 255, 248, 255]  # gestplay relax: CANCEL RELAX CANCEL
    timed = timed_bytes(data) + timed_bytes([253, 3, 60], start=0.5)  # DUMP, then a command
    result = simulate(simboard, build / "servo_rhand.elf", timed, "--pulses")
    starts = sorted(t for _, t, _ in result["pulses"])
    quiet = [t for t in starts if 0.07 < t < 0.52]
    assert quiet == []  # limp from RELAX (0.04 s) until the command at 0.52 s
    replies = [b for _, b in result["out"] if b != Signal.WAIT]
    assert replies[:3] == [252, 181, 6]  # DUMP answered while relaxed
    pose = {**REST, 2: 90, 3: 60}
    assert result["dump"] == (181, pose)
    after = {pin for pin, t, _ in result["pulses"] if t > 0.53}
    assert after == set(RHAND_PINS)  # every servo driven again, from the pose it holds
    assert_pins(result["pins"], pulses_of(pose), periods=False)


def test_the_pose_survives_a_power_cut_and_a_new_board_starts_at_rest(simboard, build,
                                                                       tmp_path):
    """The first power-up (an EEPROM never written) pulses the rest pose from the first
    pulse; a pose that held a second is stored, and the next power-up pulses it from
    the first pulse and reports it; a pose cut off before it settled is not."""
    elf, eeprom = build / "servo_rhand.elf", tmp_path / "eeprom.bin"
    rockon, _ = compile_program(load(str(LIBRARY["rockon"].path)), "rockon", RHAND)
    first = simulate(simboard, elf, to_timed(rockon.stream()), "--eeprom", eeprom,
                     "--run-on", 1.2)
    assert_pins(first["pins"], pulses_of(REST), "first")  # a new board: rest, no 1500 us
    final = dict(zip(RHAND_IDS, rockon.final, strict=True))
    assert len(first["eeprom"]) == 10  # one record: seq, six values, CRC (2 + 6 + 2 bytes)
    settled = rockon.stream().times[-1] + POSE_SETTLE  # a second after the last command
    assert all(settled < t < settled + 0.05 for t, _, _ in first["eeprom"])
    again = simulate(simboard, elf, "", "--eeprom", eeprom)
    assert again["dump"] == (181, final)
    assert_pins(again["pins"], pulses_of(final), "first")
    peace, _ = compile_program(load(str(LIBRARY["peace"].path)), "peace", RHAND, {
        s.name: final[s.id] for s in RHAND.servos})
    simulate(simboard, elf, to_timed(peace.stream()), "--eeprom", eeprom)  # cut at once
    after = simulate(simboard, elf, "", "--eeprom", eeprom)
    assert after["dump"] == (181, final)  # peace never settled: rockon it is
    assert after["eeprom"] == []  # and a power-up writes nothing


def test_a_record_torn_by_a_power_cut_is_not_read_back_by_the_image(simboard, build,
                                                                    tmp_path):
    elf, eeprom = build / "servo_rhand.elf", tmp_path / "eeprom.bin"
    ok, _ = compile_program(load(str(LIBRARY["ok"].path)), "ok", RHAND)
    simulate(simboard, elf, to_timed(ok.stream()), "--eeprom", eeprom, "--run-on", 1.2)
    fist, _ = compile_program(load(str(LIBRARY["fist"].path)), "fist", RHAND, {
        s.name: v for s, v in zip(RHAND.servos, ok.final, strict=True)})
    for written in (1, 5, 9):  # the power fails after this many bytes of the new record
        torn = tmp_path / f"torn{written}.bin"
        torn.write_bytes(eeprom.read_bytes())
        cut = simulate(simboard, elf, to_timed(fist.stream()), "--eeprom", torn,
                       "--run-on", 1.2, "--cut", written)
        assert "cut" in cut and len(cut["eeprom"]) == written
        after = simulate(simboard, elf, "", "--eeprom", torn)
        ok_pose = dict(zip(RHAND_IDS, ok.final, strict=True))
        assert after["dump"] == (181, ok_pose), written
        assert_pins(after["pins"], pulses_of(ok_pose), "first")


@pytest.fixture
def firmware_pty(simboard, build, tmp_path):
    """The rig's image served on a pty; ``tmp_path / "wire.log"``: each byte it took."""
    proc = subprocess.Popen([str(simboard), str(build / "servo_rhand.elf"), "--pty",
                             "--log", str(tmp_path / "wire.log")],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    path = proc.stdout.readline().strip()
    assert path.startswith("/dev/"), proc.stderr.read()
    yield path
    proc.kill()
    proc.wait()


def test_gestplay_plays_to_the_firmware_image_on_a_pty(firmware_pty):
    done = subprocess.run([sys.executable, "-m", "inmoov_dsl.cli.gestplay", "peace",
                           "--port", firmware_pty], capture_output=True, text=True,
                          timeout=60)
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("played peace: 0.70 s, ")
    assert "warning" not in done.stderr  # it booted, sent WAIT and answered DUMP


def test_the_firmware_image_ends_in_the_pose_played(firmware_pty):
    rhand = load_profile("rhand")
    port = serial.Serial(firmware_pty, 9600, timeout=0)
    try:
        assert wait_ready(port)  # the board reset when the port opened, and booted
        assert ask_dump(port, 181) == dict.fromkeys(range(6), 0)
        compiled, _ = compile_program(load(str(LIBRARY["rockon"].path)), "rockon", rhand)
        play(compiled, [Link(181, port, firmware_pty)])
        time.sleep(0.05)
        assert ask_dump(port, 181) == dict(zip(range(6), compiled.final, strict=True))
    finally:
        port.close()


def test_the_image_resets_only_when_dtr_rises_and_keeps_its_pose(firmware_pty, tmp_path):
    """What tells a reset is the pose: a reset board holds the pose it stored, not one
    that had no second to settle. (simavr's UART takes 11 bits a byte, so the image
    runs a little behind a stream sent at the wire's pace: its answers take longer.
    The unsettled move is not asked back before the port closes: on a busy machine the
    answer may come a second late, and the move would have settled meanwhile.)"""
    from terminal import listen_as_a_plain_program

    done = subprocess.run([sys.executable, "-m", "inmoov_dsl.cli.gestplay", "peace",
                           "--port", firmware_pty], capture_output=True, text=True,
                          timeout=60)
    assert done.returncode == 0, done.stderr
    peace = {0: 0, 1: 180, 2: 0, 3: 0, 4: 180, 5: 180}
    port, _ = listen_as_a_plain_program(firmware_pty, hold=0)
    # gestplay left DTR up: no reset, and peace (not settled yet) is what the board holds
    assert ask_dump(port, 181, timeout=3) == peace
    time.sleep(POSE_SETTLE + 0.5)  # held for a second: stored in EEPROM
    port.write(bytes([Signal.CANCEL, 0, 90]))  # the wrist moves; no time to settle...
    port.close()  # ...as DTR drops
    time.sleep(0.1)
    port, _ = listen_as_a_plain_program(firmware_pty, hold=0)
    assert wait_ready(port)  # DTR rose: it reset, and booted into the pose it stored
    wire = [int(line.split()[1]) for line in
            (tmp_path / "wire.log").read_text().splitlines()]
    move = [Signal.CANCEL, 0, 90]
    assert any(wire[k:k + 3] == move for k in range(len(wire)))  # it reached the board
    assert ask_dump(port, 181, timeout=3) == peace
    # the same move, given its second: stored, and the pose a reset boots into
    port.write(bytes([Signal.CANCEL, 0, 90]))
    assert ask_dump(port, 181, timeout=3) == {**peace, 0: 90}
    time.sleep(POSE_SETTLE + 0.5)
    port.close()
    time.sleep(0.1)
    port, _ = listen_as_a_plain_program(firmware_pty, hold=0)
    assert wait_ready(port)
    assert ask_dump(port, 181, timeout=3) == {**peace, 0: 90}
    port.close()


@pytest.mark.parametrize("name", ["fist", "peace", "wave", "count"])
def test_a_maestro_and_a_pca9685_end_in_the_widths_the_image_puts_on_the_pins(
        simboard, build, name):
    """The same gesture on the rig's image in simavr and on rhand-maestro and
    rhand-pca9685 (test_controllers checks every gesture against the firmware's widths;
    this, those widths against the pins): the Maestro within 2 us of each pin's last
    pulse, the PCA9685 within that and half its tick."""
    from test_controllers import MAESTRO, PCA, final_widths

    from inmoov_dsl.boards import controller

    compiled, _ = compile_program(load(str(LIBRARY[name].path)), name, RHAND)
    result = simulate(simboard, build / "servo_rhand.elf", to_timed(compiled.stream()))
    pins = {s.id: result["pins"][s.pin]["last"] for s in RHAND.servos
            if s.pin in result["pins"]}
    assert len(pins) == len(RHAND.servos)
    half_tick = controller(PCA, PCA.boards[0]).tick * 1e6 / 2
    for profile, bound in ((MAESTRO, 2.0), (PCA, 2.0 + half_tick)):
        got = final_widths(profile, name)
        worst = max(abs(got[i] - pins[i]) for i in pins)
        assert worst <= bound, (profile.name, got, pins)
