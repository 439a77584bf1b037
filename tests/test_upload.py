"""gestc upload: a board's firmware built from its profile and flashed by the real
avrdude through a simulated Arduino bootloader on a pseudo-terminal; its options and
its messages."""

import os
import shlex
import subprocess
import sys
from pathlib import Path

import pytest
from stk500 import Bootloader
from stk500v2 import MegaBootloader
from toolchain import need

from inmoov_dsl import load_profile
from inmoov_dsl.cli import gestc
from inmoov_dsl.errors import GestError
from inmoov_dsl.firmware.upload import MEGA, OLD_NANO, build, explain, read_hex

POSIX = pytest.mark.skipif(not hasattr(os, "openpty"), reason="pseudo-terminals are POSIX")
LINUX = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="Linux port names")
TINY_HEX = ":020000000C945E\n:00000001FF\n"  # two bytes at 0 (a jmp's first word)


@pytest.fixture
def port(tmp_path):
    """A port that is there (never opened: the test fails before avrdude would)."""
    device = tmp_path / "ttyUSB0"
    device.touch()
    return str(device)


def gestc_run(*argv, timeout=300, cwd=None, **env):
    return subprocess.run([sys.executable, "-m", "inmoov_dsl.cli.gestc", *argv],
                          capture_output=True, text=True, timeout=timeout, cwd=cwd,
                          env={**os.environ, **env})


@POSIX
def test_the_flash_the_bootloader_receives_is_the_hex_built(tmp_path):
    need("make", "avr-gcc", "avrdude", "/usr/share/arduino/hardware/arduino/avr/cores")
    bootloader = Bootloader()
    try:
        done = gestc_run("upload", "servo_rhand", "--port", bootloader.path)
    finally:
        bootloader.close()
    assert done.returncode == 0, done.stderr
    assert "gestc: flashing servo_rhand (3," in done.stderr
    assert "Writing | ####" in done.stderr  # avrdude's progress, as it came
    assert done.stderr.rstrip().endswith(f"gestc: uploaded servo_rhand to {bootloader.path}")
    # the same sketch built here: every byte of its .hex is in the flash, the rest erased
    hex_file = build(load_profile("rhand"), ["servo_rhand"], tmp_path)["servo_rhand"]
    image = read_hex(hex_file)
    assert 3000 < len(image) < 3872
    flash = bytes(bootloader.flash)
    assert all(flash[address] == byte for address, byte in image.items())
    assert flash[max(image) + 1:].count(0xFF) == len(flash) - max(image) - 1
    assert bootloader.commands.count(0x64) == -(-len(image) // 128)  # one write a page


@POSIX
def test_a_mega_is_flashed_through_its_stk500v2_bootloader(tmp_path):
    """servo_inmoov_left, built for the ATmega2560, reaches the flash of a Mega's
    bootloader (STK500v2, avrdude's wiring programmer) byte for byte."""
    need("make", "avr-gcc", "avrdude", "/usr/share/arduino/hardware/arduino/avr/cores")
    with MegaBootloader() as mega:
        done = gestc_run("upload", "servo_inmoov_left", "--port", mega.path)
        assert done.returncode == 0, done.stderr
        assert done.stderr.rstrip().endswith(f"gestc: uploaded servo_inmoov_left to "
                                             f"{mega.path}")
        hex_file = build(load_profile("inmoov"), ["servo_inmoov_left"],
                         tmp_path)["servo_inmoov_left"]
        image = read_hex(hex_file)
        flash = bytes(mega.flash)
        assert all(flash[address] == byte for address, byte in image.items())
        assert flash[max(image) + 1:].count(0xFF) == len(flash) - max(image) - 1
        assert mega.bad == 0 and mega.messages[0] == 0x01  # signed on, no bad checksum
        assert {length for _, length in mega.pages} == {256}  # the Mega's flash pages
        assert mega.messages.count(0x13) == -(-(max(image) + 1) // 256)
        assert mega.left  # it leaves the bootloader: the sketch starts
        # a Mega's board refuses the old Nano's bootloader
        refused = gestc_run("upload", "servo_inmoov_left", "--port", mega.path,
                            "--old-bootloader")
    assert refused.returncode == 1
    assert "error: --old-bootloader is an old Nano's, and board 183 (left) is a Mega" in \
        refused.stderr


def test_a_mega_that_does_not_answer_says_what_to_try(capsys, port):
    said = ("avrdude error: timeout\navrdude error: timeout communicating with programmer\n"
            "avrdude error: unable to open programmer wiring on port /dev/ttyACM0\n")
    d = explain(said, "/dev/ttyACM0", MEGA)
    assert d.message == "no bootloader answered on /dev/ttyACM0 at 115200 baud"
    assert d.hint.startswith("is it the board's port ('gestplay ports')? is it a Mega 2560 "
                             "with its bootloader?")
    assert gestc.main(["upload", "--profile", "inmoov", "--port", f"left={port},right={port}",
                       "--dry-run"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[1] == "make -C firmware servo_inmoov_right servo_inmoov_left"
    assert lines[2] == (f"avrdude -p atmega2560 -c wiring -P {port} -b 115200 -D -U "
                        "flash:w:firmware/build/servo_inmoov_right.hex:i")


@POSIX
def test_an_old_nano_answers_only_at_57600_baud(tmp_path, capsys):
    """--old-bootloader talks at the old Nano bootloader's speed; at the Uno's 115200 it
    hears nothing and says what to try. (--hex: no compiler needed.)"""
    need("avrdude")
    hex_file = tmp_path / "blink.hex"
    image = bytes(range(256)) * 3
    hex_file.write_text(_hex(_records(image)) + ":00000001FF\n")
    with Bootloader(baud=57600) as nano:
        assert gestc.main(["upload", "servo_rhand", "--port", nano.path, "--hex",
                           str(hex_file), "--old-bootloader"]) == 0
        assert bytes(nano.flash[:768]) == image and nano.flash[768:].count(0xFF) == 32000
        assert gestc.main(["upload", "servo_rhand", "--port", nano.path, "--hex",
                           str(hex_file), "--avrdude-option=-xattempts=1"]) == 1
    assert capsys.readouterr().err.endswith("an old Nano needs 57600 baud "
                                            "(--old-bootloader); a board without the "
                                            "Arduino bootloader needs an ISP programmer\n")


@POSIX
def test_a_port_where_no_bootloader_answers(tmp_path, capsys):
    need("avrdude")
    hex_file = tmp_path / "tiny.hex"
    hex_file.write_text(TINY_HEX)
    master, slave = os.openpty()  # a port nothing answers on
    try:
        path = os.ttyname(slave)
        code = gestc.main(["upload", "servo_rhand", "--port", path, "--hex", str(hex_file),
                           "--avrdude-option=-xattempts=1"])
    finally:
        os.close(master)
        os.close(slave)
    assert code == 1
    err = capsys.readouterr().err
    assert err.endswith(f"gestc: error: no bootloader answered on {path} at 115200 baud\n"
                        "  hint: is it the board's port ('gestplay ports')? an old Nano "
                        "needs 57600 baud (--old-bootloader); a board without the Arduino "
                        "bootloader needs an ISP programmer\n")


def test_no_answer_says_what_to_try(capsys):
    said = ("avrdude warning: attempt 1 of 1: not in sync: resp=0x00\n"
            "avrdude error: unable to open programmer arduino on port /dev/ttyUSB0\n")
    d = explain(said, "/dev/ttyUSB0")
    assert d.message == "no bootloader answered on /dev/ttyUSB0 at 115200 baud"
    assert d.hint == ("is it the board's port ('gestplay ports')? an old Nano needs 57600 "
                      "baud (--old-bootloader); a board without the Arduino bootloader "
                      "needs an ISP programmer")
    assert "115200 baud (no --old-bootloader)" in explain(said, "COM3", OLD_NANO).hint


def test_avrdudes_other_failures_are_ours():
    d = explain("avrdude OS error: cannot open port /dev/ttyUSB7: No such file or directory\n",
                "/dev/ttyUSB7")
    assert d.message.startswith("port /dev/ttyUSB7 not found; ports on this machine: ")
    assert d.hint == "'gestplay ports' lists them (and marks the likely Arduinos)"
    d = explain("avrdude OS error: cannot open port /dev/ttyUSB0: Permission denied\n",
                "/dev/ttyUSB0")
    assert d.message == "permission denied on port /dev/ttyUSB0"
    assert d.hint.startswith("add yourself to the dialout group: sudo usermod -a -G dialout")
    d = explain("avrdude error: verification error, first mismatch at byte 0x0040\n", "COM3")
    assert d.message == "the flash read back from the board on COM3 is not what was written"
    d = explain("avrdude: something new\navrdude error: it broke\n", "COM3")
    assert d.message == "avrdude failed on COM3: avrdude error: it broke"


def test_avrdude_missing_says_how_to_get_it(tmp_path, capsys, monkeypatch, port):
    hex_file = tmp_path / "tiny.hex"
    hex_file.write_text(TINY_HEX)
    monkeypatch.setenv("PATH", str(tmp_path))  # no avrdude here
    assert gestc.main(["upload", "servo_rhand", "--port", port, "--hex", str(hex_file)]) == 1
    err = capsys.readouterr().err
    assert "gestc: error: avrdude not found\n  hint: on Debian or Ubuntu: sudo apt-get install " \
           "avrdude; on macOS: brew install avrdude; on Windows: the Arduino IDE has one" in err


def test_no_compiler_says_what_to_install(capsys, monkeypatch, tmp_path, port):
    monkeypatch.setenv("PATH", str(tmp_path))
    assert gestc.main(["upload", "servo_rhand", "--port", port]) == 1
    err = capsys.readouterr().err
    assert err.startswith("gestc: error: cannot build the firmware: make not found\n"
                          "  hint: on Debian or Ubuntu: sudo apt-get install make gcc-avr "
                          "avr-libc arduino-core-avr; elsewhere build the sketch in the "
                          "Arduino IDE (docs/firmware.md) and give its .hex with --hex")


def test_the_commands_for_an_uno_an_old_nano_and_a_whole_profile(capsys, port):
    assert gestc.main(["upload", "servo_rhand", "--port", port, "--dry-run"]) == 0
    sketchbook, make, flash = capsys.readouterr().out.splitlines()
    assert sketchbook == "gestc firmware rhand -o firmware"
    assert make == "make -C firmware servo_rhand"
    assert flash == (f"avrdude -p atmega328p -c arduino -P {port} -b 115200 -D -U "
                     "flash:w:firmware/build/servo_rhand.hex:i")
    assert gestc.main(["upload", "servo_rhand", "--port", port, "--old-bootloader",
                       "--dry-run"]) == 0
    assert " -b 57600 " in capsys.readouterr().out
    assert gestc.main(["upload", "--profile", "rhand", "--port", f"servo_rhand={port}",
                       "--port", f"182={port}", "--baud", "57600", "--dry-run"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0] == "gestc firmware rhand -o firmware --baud 57600"
    assert out[1] == "make -C firmware servo_rhand glove_rhand"
    assert f" -P {port} " in out[2] and out[2].endswith("servo_rhand.hex:i")
    assert f" -P {port} " in out[3] and out[3].endswith("glove_rhand.hex:i")


@POSIX
def test_a_dry_run_prints_commands_that_run_as_they_are(tmp_path, port):
    """Every line printed runs as it is, in order, and the avrdude line names the .hex
    that the lines before it built, in a sketchbook that stays."""
    need("make", "avr-gcc", "/usr/share/arduino/hardware/arduino/avr/cores")
    done = gestc_run("upload", "servo_rhand", "--port", port, "--dry-run",
                     "--build-dir", "my sketches", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    *build_lines, flash = done.stdout.splitlines()
    for line in build_lines:
        ran = subprocess.run(line, shell=True, cwd=tmp_path, capture_output=True, text=True)
        assert ran.returncode == 0, (line, ran.stderr)
    hex_file = shlex.split(flash)[-1].removeprefix("flash:w:").removesuffix(":i")
    assert hex_file == "my sketches/build/servo_rhand.hex"
    assert 3000 < len(read_hex(tmp_path / hex_file)) < 3872


@POSIX
def test_build_dir_keeps_the_sketchbook_it_built(tmp_path, port, monkeypatch):
    """Without --dry-run, --build-dir is where it builds, and it stays: the .hex that
    was flashed (here by a stand-in avrdude) is there after."""
    need("make", "avr-gcc", "/usr/share/arduino/hardware/arduino/avr/cores")
    fake = tmp_path / "avrdude"
    fake.write_text("#!/bin/sh\necho \"$@\" > \"$(dirname \"$0\")/flashed\"\n")
    fake.chmod(0o755)
    done = gestc_run("upload", "servo_rhand", "--port", port, "--build-dir",
                     str(tmp_path / "kept"), "--avrdude", str(fake))
    assert done.returncode == 0, done.stderr
    hex_file = tmp_path / "kept" / "build" / "servo_rhand.hex"
    assert f"flash:w:{hex_file}:i" in (tmp_path / "flashed").read_text()
    assert 3000 < len(read_hex(hex_file)) < 3872


@LINUX
def test_a_windows_port_name_is_found_out_before_building(capsys):
    """COM3 on Linux: the message and hint every command gives, at once (nothing built,
    avrdude not run); a dry run says the same as a warning and prints its commands."""
    assert gestc.main(["upload", "servo_rhand", "--port", "COM3"]) == 1
    out, err = capsys.readouterr()
    assert out == "" and err.startswith("gestc: error: port COM3 not found; ports on this "
                                        "machine: ")
    assert err.endswith("\n  hint: COM ports are Windows names; here an Arduino is "
                        "/dev/ttyACM0 (Uno, Leonardo) or /dev/ttyUSB0 (Nano, clones)\n")
    assert gestc.main(["upload", "servo_rhand", "--port", "COM3", "--dry-run"]) == 0
    out, err = capsys.readouterr()
    assert err.startswith("gestc: warning: port COM3 not found") and "COM ports are " in err
    assert " -P COM3 " in out.splitlines()[-1]


def test_a_url_is_no_port_to_flash(capsys):
    assert gestc.main(["upload", "servo_rhand", "--port", "sim://"]) == 1
    assert capsys.readouterr().err == (
        "gestc: error: port sim://: avrdude opens a serial device, not a URL\n"
        "  hint: give the board's device ('gestplay ports' lists them); the virtual board "
        "(sim://, gestsim) needs no firmware\n")


@pytest.mark.parametrize(("argv", "message"), [
    (["servo_rhnd", "--port", "COM3"],
     "gestc: error: no board called 'servo_rhnd'\n  hint: did you mean 'servo_rhand'?\n"),
    (["--port", "COM3"], "gestc: error: which board?\n  hint: name one (gestc upload "
     "servo_rhand --port COM3), or give --profile for all of a profile's\n"),
    (["--profile", "rhand", "--port", "COM3"],  # the words of every --port (link.py)
     "gestc: error: profile 'rhand' has 2 boards: give a port for each\n"
     "  hint: --port servo_rhand=PORT --port glove_rhand=PORT\n"),
    (["--profile", "rhand", "--port", "183=COM3"],
     "gestc: error: --port 183=COM3: profile 'rhand' has no board 183 (boards: "
     "servo_rhand, glove_rhand)\n"),
    (["--profile", "rhand", "--port", "181=COM3"],
     "gestc: error: no port for glove_rhand\n  hint: add --port glove_rhand=PORT\n"),
    (["servo_lhand", "--profile", "rhand", "--port", "COM3"],
     "gestc: error: profile 'rhand' has no board 'servo_lhand'\n"
     "  hint: its boards: servo_rhand, glove_rhand\n"),
    (["--profile", "rhand", "--port", "181=COM3", "--port", "182=COM4", "--hex", "x.hex"],
     "gestc: error: --hex is one board's firmware\n"
     "  hint: name the board: gestc upload BOARD --hex FILE\n"),
])
def test_what_to_upload_where_is_checked_first(argv, message, capsys):
    assert gestc.main(["upload", *argv]) == 1
    assert capsys.readouterr().err == message


def test_a_file_that_is_not_intel_hex_is_refused(tmp_path, capsys, port):
    bad = tmp_path / "sketch.hex"
    bad.write_text(":020000000C94FF\n")  # a checksum that does not add up
    assert gestc.main(["upload", "servo_rhand", "--port", port, "--hex", str(bad)]) == 1
    assert capsys.readouterr().err == (f"gestc: error: {bad}:1: not an Intel HEX record\n"
                                       "  hint: give the .hex that the build wrote\n")
    good = tmp_path / "good.hex"
    good.write_text(TINY_HEX)
    assert read_hex(good) == {0: 0x0C, 1: 0x94}
    with pytest.raises(GestError):
        read_hex(Path(tmp_path / "missing.hex"))


def _records(image: bytes) -> list[bytes]:
    """``image`` from address 0 as Intel HEX data records of 16 bytes, without their
    checksums."""
    return [bytes([16, a >> 8, a & 0xFF, 0]) + image[a:a + 16] for a in range(0, len(image), 16)]


def _hex(records: list[bytes]) -> str:
    """Intel HEX data records, each with its checksum."""
    return "".join(f":{r.hex()}{-sum(r) & 0xFF:02x}\n" for r in records)


def avrdudes_on(path: str) -> list[int]:
    """The avrdude processes that have ``path`` on their command line (Linux's /proc)."""
    found = []
    for entry in Path("/proc").iterdir():
        try:
            words = (entry / "cmdline").read_bytes().split(b"\0")
        except OSError:
            continue
        if words and words[0].endswith(b"avrdude") and path.encode() in words:
            found.append(int(entry.name))
    return found


@LINUX
def test_a_board_unplugged_during_the_upload_ends_it_with_no_avrdude_left(tmp_path):
    """The cable goes after three pages: avrdude waits forever on a port whose other end
    is gone. gestc upload stops it after STALL s of silence and says what happened."""
    need("avrdude")
    import time

    from inmoov_dsl.firmware.upload import STALL

    hex_file = tmp_path / "big.hex"
    hex_file.write_text(_hex(_records(bytes(range(16)) * 512)) + ":00000001FF\n")
    with Bootloader(unplugged_after=3) as board:
        began = time.monotonic()
        done = gestc_run("upload", "servo_rhand", "--port", board.path, "--hex",
                         str(hex_file), timeout=STALL + 100)
        took = time.monotonic() - began
        left = avrdudes_on(board.path)
    assert done.returncode == 1 and len(board.pages) == 3
    assert STALL <= took < STALL + 60  # then stopped (a busy machine: the starts)
    assert left == []
    assert done.stderr.endswith(
        f"gestc: error: the board on {board.path} stopped answering: avrdude heard nothing "
        f"for {STALL:.0f} s, and was stopped\n  hint: was the cable pulled or the board "
        "reset? plug it in and upload again: the bootloader is still there\n")


def _bad_hex(rng, how: int) -> str:
    """A small image's Intel HEX, mutated: a record of another kind or too short, an
    address at the end of the space, a checksum or a character wrong, lines lost."""
    records = _records(bytes(range(16)) * 32)
    k = rng.randrange(len(records))
    if how == 0:  # an extended address record with too little data
        records.insert(k, bytes([rng.randrange(2), 0, 0, rng.choice([2, 4])]) +
                       bytes(rng.randrange(2)))
    elif how == 1:  # the last bytes of the address space, and beyond
        records[k] = bytes([16, 0xFF, 0xF8, 0]) + bytes(16)
    elif how == 2:  # a record kind no loader knows
        records[k] = bytes([1, 0, 0, rng.randrange(6, 256), 0])
    text = _hex(records) + ":00000001FF\n"
    if how == 3:  # a checksum wrong
        at = text.index("\n", rng.randrange(len(text) - 20)) - 1
        text = text[:at] + ("0" if text[at] != "0" else "1") + text[at + 1:]
    elif how == 4:  # a character that is no hex digit
        at = rng.randrange(len(text))
        text = text[:at] + rng.choice("gZ :\x00é") + text[at + 1:]
    elif how == 5:  # lines lost, the end too
        text = "".join(rng.sample(text.splitlines(True), rng.randrange(len(records))))
    return text


@LINUX
def test_seeded_bad_hex_files_and_boards_that_go_end_with_a_word_and_no_avrdude(
        tmp_path, capsys, monkeypatch):
    """gestc upload's path with bad input: hex files mutated (seeded), to a board that
    answers, stays silent or loses its cable mid-write. Each ends with exit 0 or a
    ``gestc: error:`` line, in bounded time, with no traceback and no avrdude left."""
    need("avrdude")
    import random
    import time

    from inmoov_dsl.firmware import upload

    monkeypatch.setattr(upload, "STALL", 1.5)
    rng = random.Random(35)
    for k in range(14):  # each mutation twice
        hex_file = tmp_path / f"m{k}.hex"
        hex_file.write_text(_bad_hex(rng, k % 7), encoding="utf-8")
        board = rng.choice([{}, {}, {"silent": True}, {"unplugged_after": 1}])
        with Bootloader(**board) as loader:
            began = time.monotonic()
            code = gestc.main(["upload", "servo_rhand", "--port", loader.path, "--hex",
                               str(hex_file), "--avrdude-option=-xattempts=1"])
            took = time.monotonic() - began
            left = avrdudes_on(loader.path)
        err = capsys.readouterr().err
        assert code in (0, 1) and left == [] and took < 60, (k, board, err[-500:])
        assert "Traceback" not in err
        assert code == 0 or "gestc: error: " in err, (k, err[-500:])
