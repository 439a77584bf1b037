"""Gestures stored in the board (issue 26): the stored form against the compiled
streams, the approach, the virtual board playing them, the command lines, the C++
player against the Python one, and, in simavr, every right-hand library gesture stored
in one image and started by the signal, a button and power-up, pulse for pulse against
the same gesture streamed live.

Tests that need a toolchain skip without it, except under CI=true."""

import bisect
import re
import subprocess
import sys
from collections import defaultdict
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest
from boardmodel import read_stream
from hardest import hardest
from toolchain import need

from inmoov_dsl import load_profile, to_timed
from inmoov_dsl.boards.pulses import pulse_us
from inmoov_dsl.boards.rig.core import BoardCore, BoardServo
from inmoov_dsl.cli import gestc
from inmoov_dsl.compiling.compiler import compile_program
from inmoov_dsl.errors import GestError
from inmoov_dsl.firmware.store import (
    FIRMWARE_FLASH,
    FLASH_MAX,
    Request,
    limits,
    stored_gesture,
    stored_set,
)
from inmoov_dsl.language.library import scan_library
from inmoov_dsl.language.load import load
from inmoov_dsl.protocol import CATALOG, PLAY, Signal
from inmoov_dsl.wire.sim import VirtualBoard
from inmoov_dsl.wire.stored import (
    NONE,
    UNIT,
    arrival_us,
    catalog_reply,
    find_catalog,
    read_blob,
    read_set,
    unpack,
)
from inmoov_dsl.wire.stored_play import Playback, approach

ROOT = Path(__file__).resolve().parent.parent
FIRMWARE = ROOT / "firmware"
RHAND = load_profile("rhand")
BOARD = RHAND.boards[0]
LIBRARY = scan_library([ROOT / "gestures"])


def _compile_rhand():
    out = {}
    for name, entry in sorted(LIBRARY.items()):
        try:
            compiled, _ = compile_program(load(str(entry.path)), name, RHAND)
        except GestError:  # a gesture of the whole robot, or one that speaks
            continue
        out[name] = compiled
    return out


COMPILED = _compile_rhand()  #: every right-hand library gesture, compiled from rest
GESTURES = {name: stored_gesture(c, RHAND, BOARD) for name, c in COMPILED.items()}
NAMES = list(GESTURES)
FLASH = stored_set(list(GESTURES.values()), Request(tuple(NAMES), buttons=((8, "wave"),)),
                   RHAND, BOARD)


def test_every_right_hand_gesture_is_stored_pair_for_pair_at_its_time():
    """The stored form gives back every pair of the compiled stream, in the servo frame
    it arrives in and at the time of its slot (the board rounds it to whole
    microseconds; on the wire a pair arrives at the last point of the byte grid at or
    before its slot, less than a byte-time earlier), and the whole library fits beside
    the firmware."""
    assert len(NAMES) >= 29 and "wave" in NAMES and "demo" in NAMES  # 29 on 2026-11-25
    for name, compiled in COMPILED.items():
        stream = compiled.stream()
        live = read_stream(stream.times.tolist(), stream.data, stream.baud)  # (t, id, v)
        stored = sorted((arrival_us(f, j, 6, FLASH.pair_us) / 1e6, j, v)
                        for f, j, v in unpack(GESTURES[name].data, GESTURES[name].start))
        assert [(sid, v) for _, sid, v in live] == [(j, v) for _, j, v in stored], name
        tau = stream.byte_time
        assert all(-3e-6 < b - a < tau for (a, _, _), (b, _, _) in zip(live, stored,
                                                                        strict=True)), name
        assert GESTURES[name].frames * 0.02 == pytest.approx(compiled.duration, abs=0.02)
    blob = FLASH.to_bytes()
    assert read_set(blob) == FLASH
    wire = sum(len(c.stream().data) for c in COMPILED.values())
    assert wire >= 12_331 and len(blob) < wire * 0.6  # the compact form: under 60%
    assert len(blob) + FIRMWARE_FLASH < FLASH_MAX


def test_a_set_that_does_not_fit_is_an_error_naming_sizes_before_anything_is_built(
        tmp_path, capsys):
    moves = "\n".join(f"    fingers {(k * 37) % 180}, wrist {(k * 53) % 180}"
                      for k in range(1500))
    (tmp_path / "long.gest").write_text(f"long:\n{moves}\n")
    out = tmp_path / "book"
    code = gestc.main(["firmware", "rhand", "-o", str(out), "--store", "all",
                       "--store", str(tmp_path / "long.gest")])
    err = capsys.readouterr().err
    assert code == 1 and not out.exists()  # nothing written, nothing built
    assert "gestures take" in err and "bytes of flash" in err and "30,720" in err
    assert "hint: leave out long (" in err


def test_the_approach_keeps_each_servos_speed_and_acceleration():
    """From every corner to the gesture's start: a frame's change is within the servo's
    max_velocity, a change of speed within its max_acceleration (give or take the
    rounding of each speed to whole degrees), and it ends exactly at the start."""
    limit = limits(RHAND, BOARD)
    servos = [RHAND.servos[RHAND.index(n)] for n in BOARD.servos]
    for start, goal in [([180] * 6, [0] * 6), ([0] * 6, [180] * 6),
                        ([0, 180, 90, 3, 177, 45], [90, 0, 180, 4, 0, 46])]:
        frames = [start, *approach(start, goal, limit)]
        assert frames[-1] == goal
        for j, servo in enumerate(servos):
            steps = [b[j] - a[j] for a, b in zip(frames, frames[1:], strict=False)]
            assert max(map(abs, steps)) <= servo.max_velocity * 0.02, (j, steps)
            accels = [abs(b - a) for a, b in zip([0, *steps], [*steps, 0], strict=True)]
            assert max(accels) <= servo.max_acceleration * 0.0004 + 2, (j, steps)
    assert limit[1] == (7 * UNIT, 200)  # the thumb: 393 deg/s, 7850 deg/s^2


def virtual(flash=FLASH, pose=None):
    board = VirtualBoard(BoardCore.from_profile(RHAND, BOARD), 9600, flash=flash,
                         stored=pose)
    board.advance(0.0)
    return board


def test_the_virtual_board_plays_a_stored_gesture_as_the_stream_would():
    """PLAY N on the virtual board: from rest, the writes are the live stream's at its
    slots' times (on the wire, up to a byte-time earlier: the byte grid); from another
    pose, the approach first, then the same writes."""
    for name in ("wave", "count", "demo"):
        number, compiled = NAMES.index(name), COMPILED[name]
        stream = compiled.stream()
        live = read_stream(stream.times.tolist(), stream.data, stream.baud)
        board = virtual()
        board.write(bytes([Signal.CANCEL, PLAY, number]), 1.0)
        t0 = 1.0 + 3 / 960  # PLAY's number has arrived
        board.advance(t0 + compiled.duration + 1)
        got = [(t - t0, w.id, w.value) for t, w in board.log]
        assert [(sid, v) for _, sid, v in got] == [(sid, v) for _, sid, v in live], name
        assert all(-1e-5 < a[0] - b[0] < stream.byte_time
                   for a, b in zip(got, live, strict=True)), name
    far = virtual(pose=[180] * 6)
    far.write(bytes([Signal.CANCEL, PLAY, NAMES.index("wave")]), 1.0)
    far.advance(9)
    ahead = [f[1] for f in approach([180] * 6, [0] * 6, FLASH.limits)]  # the thumb's
    moved = [v for k, v in enumerate(ahead) if v != ([180] + ahead)[k]]
    assert [w.value for _, w in far.log if w.id == 1][:len(moved)] == moved
    assert moved[-1] == 0 and len(ahead) == 28
    assert far.positions() == dict(zip(range(6), COMPILED["wave"].final, strict=True))


def test_any_host_byte_stops_stored_playback_and_dump_answers_that_pose():
    board = virtual()
    board.write(bytes([Signal.CANCEL, PLAY, NAMES.index("wave")]), 0.0)
    board.read(1.2)
    held = board.positions()
    assert held != dict.fromkeys(range(6), 0)  # the wrist is on its way
    board.write(bytes([Signal.DUMP]), 1.2)
    reply = board.read(1.3)
    assert reply[:3] == bytes([Signal.START, 181, 6])
    assert dict(zip(reply[3:15:2], reply[4:15:2], strict=True)) == board.positions()
    board.advance(5)
    assert board.positions() == {sid: v for sid, v in zip(reply[3:15:2], reply[4:15:2],
                                                           strict=True)}  # it stopped


def test_power_up_a_button_and_idling_start_stored_gestures_on_the_virtual_board():
    wave = NAMES.index("wave")
    flash = read_set(stored_set(list(GESTURES.values()), Request(
        tuple(NAMES), boot="peace", idle="ok", idle_after=5, buttons=((8, "wave"),)),
        RHAND, BOARD).to_bytes())
    board = virtual(flash)
    board.advance(2)
    assert board.positions() == dict(zip(range(6), COMPILED["peace"].final, strict=True))
    assert board.read(2).count(Signal.WAIT) == 2  # at power-up, and when peace ended
    board.press(8, 2.0)
    board.advance(2.0 + 0.02 + 1.0)
    assert board.playing is not None and board.playing.number == wave
    board.advance(30)
    assert board.positions() == dict(zip(range(6), COMPILED["ok"].final, strict=True))
    quiet = virtual(flash)
    quiet.write(bytes([Signal.CANCEL]), 0.1)  # a host opened the port: no boot gesture
    quiet.advance(3)
    assert quiet.log == []


def test_the_catalog_names_every_gesture_and_what_starts_it():
    board = virtual()
    board.write(bytes([Signal.CANCEL, PLAY, CATALOG]), 0.0)
    out = board.read(2.0)
    catalog = find_catalog(out, 181)
    assert catalog.names == tuple(NAMES)
    assert catalog.durations[NAMES.index("wave")] == pytest.approx(3.1)
    assert catalog.triggers(NAMES.index("wave")) == ["button D8"]
    assert out.index(catalog_reply(181, FLASH.to_bytes())) > out.index(Signal.WAIT)


def test_play_is_a_foreign_pair_for_the_original_firmware_and_a_board_without_gestures():
    """The original reads CANCEL PLAY N as a pair for a servo it does not have: nothing
    moves and it stays in step; so does our board without stored gestures."""
    data = bytes([Signal.CANCEL, PLAY, 3, 2, 90, Signal.CANCEL, PLAY, CATALOG, 1, 45])
    assert [(sid, v) for _, sid, v in read_stream(range(len(data)), data, 9600,
                                                    owned=range(6))] == [(2, 90), (1, 45)]
    board = virtual(flash=None)
    board.write(data, 0.0)
    out = board.read(1.0)
    assert [(w.id, w.value) for _, w in board.log] == [(2, 90), (1, 45)]
    assert find_catalog(out, 181) is None and set(out) == {Signal.WAIT}


def test_gestplay_lists_and_plays_what_a_virtual_board_stores(tmp_path):
    book = tmp_path / "book"
    assert gestc.main(["firmware", "rhand", "-o", str(book), "--store", "wave,peace",
                       "--button", "D8=peace", "--on-boot", "wave"]) == 0
    assert read_set(read_blob(book / "servo_rhand")).number("peace") == 1
    port = f"sim://?flash={book / 'servo_rhand'}&fresh"
    run = [sys.executable, "-m", "inmoov_dsl.cli.gestplay"]
    listed = subprocess.run([*run, "stored", "--port", port], capture_output=True,
                            text=True, timeout=60)
    assert listed.returncode == 0, listed.stderr
    lines = listed.stdout.splitlines()
    assert lines[0].endswith(": 2 stored gestures")
    assert lines[2].split() == ["0", "wave", "3.10", "s", "the", "host;", "power-up"]
    assert lines[3].split() == ["1", "peace", "0.70", "s", "the", "host;", "button", "D8"]
    played = subprocess.run([*run, "peace", "--stored", "--port", port],
                            capture_output=True, text=True, timeout=60)
    assert played.returncode == 0, played.stderr
    assert played.stdout.startswith("played peace (stored gesture 1 of board 181): 0.7")
    assert "pinky      180" in played.stdout
    missing = subprocess.run([*run, "wve", "--stored", "--port", port],
                             capture_output=True, text=True, timeout=60)
    assert missing.returncode == 1
    assert "stores no gesture 'wve'" in missing.stderr and "did you mean 'wave'" in \
        missing.stderr


# -- the C++ player on this computer, and the image in simavr ---------------------------
@pytest.fixture(scope="session")
def image(tmp_path_factory):
    """A sketchbook whose servo_rhand stores every right-hand library gesture (the first
    at power-up and on a button on D8), built with the harness and the host driver."""
    need("make", "g++", "cc", "avr-gcc", "avr-g++", "/usr/share/arduino/hardware/arduino/avr/cores",
         "/usr/include/simavr/sim_avr.h")
    book = tmp_path_factory.mktemp("stored-book")
    assert gestc.main(["firmware", "rhand", "-o", str(book), "--store", "all", "--on-boot",
                       NAMES[0], "--button", f"D8={NAMES[0]}"]) == 0
    done = subprocess.run(["make", "-C", str(book), "-j2", "servo_rhand", "harness", "host"],
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stdout + done.stderr
    assert read_set(read_blob(book / "servo_rhand")) == read_set(FLASH.to_bytes()) or \
        read_set(read_blob(book / "servo_rhand")).gestures == FLASH.gestures
    return book, done.stdout


def drive(book, *lines):
    """The C++ player on this computer (core_driver stored), on the image's blob."""
    script = ["board 181", *(f"servo {s.id} {s.pin} {s.calibration[0]} {s.calibration[1]} "
                             f"{int(s.reversed)} {s.rest}" for s in RHAND.servos),
              "blob " + read_blob(book / "servo_rhand").hex(), *lines]
    done = subprocess.run([str(book / "build" / "host" / "core_driver"), "stored"],
                          input="\n".join(script) + "\n", capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 0, done.stdout + done.stderr
    return done.stdout.splitlines()


def test_the_firmware_player_plays_like_the_python_one(image):
    """From a far pose, the C++ player's approach writes the Python one's values, frame
    by frame, and its stream the same pairs at the same times (within the driver's 4 us
    steps); PLAY is read where an ID is expected only; the catalog is the same bytes."""
    book, _ = image
    far = [180, 170, 160, 150, 140, 130]
    for name in ("wave", "count", "demo", "softgrip"):
        number = NAMES.index(name)
        out = drive(book, "begin " + " ".join(map(str, far)), f"host 0 255 {PLAY} {number}",
                    "run 40000000")
        out = out[out.index("reply"):]  # what begin wrote is the pose it starts in
        writes = [tuple(map(int, x.split()[1:])) for x in out if x.startswith("write")]
        end = next(int(line.split()[1]) for line in out if line.startswith("end"))
        t0 = end - GESTURES[name].frames * 20_000
        python = Playback(FLASH, number, far, 0.0)
        steps = []
        while python.t0 is None:
            steps += python.run()[0]
        assert [(j, v) for t, j, v in writes if t <= t0] == steps, name
        stream = [(t - t0, j, v) for t, j, v in writes if t > t0]
        pairs = unpack(GESTURES[name].data, GESTURES[name].start)
        assert [(j, v) for _, j, v in stream] == [(j, v) for _, j, v in sorted(
            pairs, key=lambda p: arrival_us(p[0], p[1], 6, FLASH.pair_us))], name
        assert all(0 <= t - arrival_us(f, j, 6, FLASH.pair_us) < 4 for (t, _, _), (f, j, _)
                   in zip(stream, sorted(pairs, key=lambda p: arrival_us(
                       p[0], p[1], 6, FLASH.pair_us)), strict=True)), name
    catalog = drive(book, "begin 0 0 0 0 0 0", f"host 0 255 {PLAY} {CATALOG}")[-1]
    assert list(map(int, catalog.split()[1:])) == list(catalog_reply(
        181, read_blob(book / "servo_rhand")))
    # 255 PLAY 255 PLAY 5: the second PLAY counts; PLAY as a value is 180, nothing plays
    out = drive(book, "begin 0 0 0 0 0 0", f"host 0 255 {PLAY} 255 {PLAY} 5", "run 25000000",
                "begin 0 0 0 0 0 0", f"host 0 255 2 {PLAY} 3", "run 3000000")
    assert out[6] == "reply" and any(line.startswith("end ") for line in out)
    assert out[-2:] == ["write 0 2 180", "reply"]


def run_image(book, timed="", *options, sketch="servo_rhand"):
    """The image in simavr: its replies, the DUMP at the end, every pulse (pin, s,
    width), the watched player's states (s, state), the EEPROM it kept."""
    eeprom = options[options.index("--eeprom") + 1] if "--eeprom" in options else None
    done = subprocess.run([str(book / "build" / "harness" / "simboard"),
                           str(book / "build" / f"{sketch}.elf"), "--pulses", "--watch",
                           "inmoov_playing", *map(str, options)], input=timed,
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    result = {"out": [], "pulses": defaultdict(list), "watch": []}
    for line in done.stdout.splitlines():
        key, *rest = line.split()
        if key == "out":
            result["out"].append((float(rest[0]), int(rest[1])))
        elif key == "dump":
            body = list(map(int, rest[2:]))
            result["dump"] = dict(zip(body[0::2], body[1::2], strict=True))
        elif key == "pulse":
            result["pulses"][int(rest[0])].append((float(rest[1]), float(rest[2])))
        elif key == "watch":
            result["watch"].append((float(rest[0]), int(rest[1])))
    if eeprom is not None:
        result["eeprom"] = newest_pose(Path(eeprom).read_bytes())
    return result


def crc16(crc, byte):
    crc ^= byte << 8
    for _ in range(8):
        crc = ((crc << 1) ^ 0x1021 if crc & 0x8000 else crc << 1) & 0xFFFF
    return crc


def newest_pose(eeprom, board=181, ids=range(6)):
    """The pose the EEPROM keeps (pose_store.h's ring of records), or None."""
    key = crc16(crc16(0xFFFF, board), len(ids))
    for sid in ids:
        key = crc16(key, sid)
    size, best = len(ids) + 4, None
    for at in range(0, len(eeprom) - size + 1, size):
        record = eeprom[at:at + size]
        crc = key
        for b in record[:-2]:
            crc = crc16(crc, b)
        if crc != int.from_bytes(record[-2:], "little") or max(record[2:-2]) > 180:
            continue
        seq = int.from_bytes(record[:2], "little")
        if best is None or ((seq - best[0]) & 0xFFFF) < 0x8000:
            best = (seq, dict(zip(ids, record[2:-2], strict=True)))
    return None if best is None else best[1]


FRAME, WIDTH = 0.020, 10.0  #: the issue's bounds: one servo frame, 10 us a pulse
WIRE = 0.0005  #: s: the live pairs' extra delay on simavr's wire (11 bits a byte)


def follows(pulses, t0, live, until):
    """The worst (width difference, time difference) between every pulse of ``pulses``
    from ``t0`` to ``t0 + until`` and the nearest-width pulse of ``live`` (from 0) on
    the same pin within a servo frame (and the wire's delay) of it."""
    worst = 0.0
    for pin, got in pulses.items():
        times = [t for t, _ in live[pin]]
        for t, width in got:
            if not t0 <= t <= t0 + until:
                continue
            lo = bisect.bisect_left(times, t - t0 - FRAME - WIRE)
            hi = bisect.bisect_right(times, t - t0 + FRAME + WIRE)
            worst = max(worst, min(abs(w - width) for _, w in live[pin][lo:hi]))
    return worst


def starts(watch):
    """When the player began to play a stream (state 2)."""
    return [t for t, state in watch if state == 2]


#: gestures proven with every trigger (power-up, the signal, a button); the others by the
#: signal alone: how a gesture starts is the same code whatever the gesture
EVERY_TRIGGER = ("demo", "wave", NAMES[0])
HARDEST = hardest({name: c.stream() for name, c in COMPILED.items()}, EVERY_TRIGGER)


def proof(book, name):
    """One gesture: streamed live from rest, and stored (at power-up, by the signal, by a
    button on D8; or by the signal alone) in one run: the worst pulse differences, the
    DUMPs, the EEPROM poses."""
    number, compiled = NAMES.index(name), COMPILED[name]
    every = name in EVERY_TRIGGER
    d, tmp = compiled.duration, book / f"eeprom-{name}"
    for old in book.glob(f"eeprom-{name}-*"):
        old.unlink()  # a new chip each time
    live = run_image(book, to_timed(compiled.stream()), "--eeprom", f"{tmp}-live",
                     "--run-on", 1.2)
    back = len(list(approach(compiled.final, compiled.start, FLASH.limits))) * FRAME
    t1 = 0.25 + d + 0.2 if every else 0.3  # after the boot gesture, if any: the signal
    t2 = t1 + back + d + 0.3  # after that one: the button
    boot = number if every else NONE  # the catalog's boot byte: this gesture, or none
    button = ("--button", 8, "--press", 8, t2, 0.1) if every else ()
    stored = run_image(book, "".join(f"{t1:.6f} {b}\n" for b in (255, PLAY, number)),
                       "--flash", "INMOOV_STORED", 4, boot, "--flash", "INMOOV_STORED", 10,
                       number, *button, "--wait",
                       (t2 - t1 if every else 0) + back + d + 1.3,
                       "--eeprom", f"{tmp}-stored")
    begun = starts(stored["watch"])
    worst = [follows(stored["pulses"], t, live["pulses"], d + 0.1) for t in begun]
    return name, begun, worst, live, stored


def test_the_hardest_library_gestures_stored_in_one_image_play_as_they_stream(image):
    """Every right-hand library gesture stored in one image; for the ones that ask the
    most of the board (hardest.py: every gesture's stored pairs are checked in Python
    above), started by the signal (and for some, at power-up and by a button pressed in
    the simulation as well): every
    pulse on every servo pin is within 10 us of one of the same gesture streamed live to
    the same image, within a servo frame in time (and the live bytes' delay on the
    simulated wire), after the approach to its start; the final DUMP and the pose kept
    in EEPROM are the same."""
    book, _ = image
    checked = []
    with ThreadPoolExecutor(max_workers=2) as pool:
        for name, begun, worst, live, stored in pool.map(lambda n: proof(book, n), HARDEST):
            checked.append(name)
            every = name in EVERY_TRIGGER
            final = dict(zip(range(6), COMPILED[name].final, strict=True))
            assert live["dump"] == stored["dump"] == final, name
            assert live["eeprom"] == stored["eeprom"] == final, name
            if GESTURES[name].frames:
                assert len(begun) == (3 if every else 1), (name, begun)
                assert abs(begun[0] - 0.25) < 0.002 or not every, (name, begun)
            assert all(w <= WIDTH for w in worst), (name, worst)
            ends = [t for t, b in stored["out"] if b == Signal.WAIT]
            # at power-up, and when each gesture played ended
            assert len(ends) >= (4 if every else 2), name
    assert checked == HARDEST and len(NAMES) >= 29
    assert all(GESTURES[name].frames for name in EVERY_TRIGGER)


def test_a_mega_plays_a_stored_gesture_as_it_streams(tmp_path):
    """The InMoov's left Mega (18 servos, two timers, 115200 baud) stores 'nod' with a
    button on A0 (its pin 54): started by the signal and by the button, every pulse on
    every one of its servo pins is within 10 us of the nod streamed live to the same
    image, within a servo frame; the final DUMP is the same."""
    need("make", "cc", "avr-gcc", "avr-g++", "/usr/share/arduino/hardware/arduino/avr/cores",
         "/usr/include/simavr/sim_avr.h")
    book = tmp_path / "book"
    assert gestc.main(["firmware", "inmoov", "-o", str(book), "--store", "nod", "--board",
                       "servo_inmoov_left", "--button", "A0=nod"]) == 0
    assert "  button A0\n" in (book / "servo_inmoov_left" / "stored.h").read_text()
    done = subprocess.run(["make", "-C", str(book), "-j2", "servo_inmoov_left", "harness"],
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stdout + done.stderr
    inmoov = load_profile("inmoov")
    compiled, _ = compile_program(load(str(LIBRARY["nod"].path)), "nod", inmoov)
    d, sketch = compiled.duration, "servo_inmoov_left"
    live = run_image(book, to_timed(compiled.stream(183)), "--baud", 115200, "--run-on", 0.5,
                     sketch=sketch)
    t1, t2 = 0.2, 0.2 + d + 0.5
    stored = run_image(book, "".join(f"{t1:.6f} {b}\n" for b in (255, PLAY, 0)), "--baud",
                       115200, "--button", 54, "--press", 54, t2, 0.1, "--wait",
                       t2 - t1 + d + 0.5, sketch=sketch)
    begun = starts(stored["watch"])
    assert len(begun) == 2 and abs(begun[0] - t1) < 0.01, begun
    assert all(follows(stored["pulses"], t, live["pulses"], d + 0.1) <= WIDTH for t in begun)
    servos = {s.pin for s in inmoov.servos if s.board == 183}
    assert set(stored["pulses"]) == set(live["pulses"]) == servos
    final = {s.id: compiled.final[inmoov.index(s.name)] for s in inmoov.servos
             if s.board == 183}
    assert live["dump"] == stored["dump"] == final


def test_the_approach_from_a_far_pose_keeps_the_speed_limit_at_the_pins(image, tmp_path):
    """The board powers up in a fist (kept in EEPROM) and plays wave from rest: between
    consecutive pulses no servo moves faster than its max_velocity allows."""
    book, _ = image
    eeprom = tmp_path / "eeprom"
    run_image(book, to_timed(COMPILED["fist"].stream()), "--eeprom", eeprom, "--run-on", 1.2)
    wave = NAMES.index("wave")
    result = run_image(book, "", "--flash", "INMOOV_STORED", 4, wave, "--eeprom", eeprom,
                       "--wait", 5)
    begun = starts(result["watch"])
    assert len(begun) == 1 and begun[0] > 0.25 + 0.3  # an approach first
    servos = {s.pin: s for s in RHAND.servos}
    for pin, pulses in result["pulses"].items():
        s = servos[pin]
        servo = BoardServo(s.id, s.calibration, s.reversed, s.rest)
        top = int(s.max_velocity * FRAME)  # whole degrees a frame
        most = max(abs(servo.pulse(v + top) - servo.pulse(v)) for v in range(181 - top))
        during = [w for t, w in pulses if t < begun[0] + 0.03]
        changes = [abs(b - a) for a, b in zip(during, during[1:], strict=False)]
        assert max(changes) <= most + 8, (pin, max(changes), most)  # 8 us: an edge's delay
        if abs(during[0] - during[-1]) > 100:  # a finger the fist had curled
            assert max(changes) > most / 2  # it moved at speed
    assert result["dump"] == dict(zip(range(6), COMPILED["wave"].final, strict=True))


def test_dump_during_stored_playback_answers_the_pose_of_that_moment(image):
    """A DUMP sent while the board plays: its answer is the pose of that moment, and the
    hand holds it (every pin's last pulses are that pose's)."""
    book, _ = image
    wave = NAMES.index("wave")
    result = run_image(book, f"0.0 255\n0.0 {PLAY}\n0.0 {wave}\n1.2 253\n", "--wait", 1)
    replies = [b for _, b in result["out"] if b != Signal.WAIT]
    mid = dict(zip(replies[3:15:2], replies[4:15:2], strict=True))
    assert replies[:3] == [252, 181, 6] and mid[0] != 0  # the wrist was on its way
    assert result["dump"] == mid  # the final DUMP: it stopped there
    for s in RHAND.servos:
        last = result["pulses"][s.pin][-1][1]
        expected = pulse_us(BoardServo(s.id, s.calibration, s.reversed).angle(mid[s.id]))
        assert abs(last - expected) <= 8, (s.name, last, expected)


def test_the_image_lists_what_it_stores_as_the_virtual_board_does(image):
    """PLAY CATALOG: the image answers the bytes the virtual board answers; the firmware
    with its player takes no more flash than the size check counts on."""
    book, built = image
    result = run_image(book, f"0.0 255\n0.0 {PLAY}\n0.0 {CATALOG}\n", "--wait", 1)
    board = virtual(read_set(read_blob(book / "servo_rhand")))
    board.write(bytes([255, PLAY, CATALOG]), 0.0)
    python = board.read(2.0)
    firmware = bytes(b for _, b in result["out"])
    assert firmware[:len(python)] == python
    assert find_catalog(firmware, 181).names == tuple(NAMES)
    flash = int(re.search(r"servo_rhand: flash (\d+)", built)[1])
    assert flash - len(read_blob(book / "servo_rhand")) <= FIRMWARE_FLASH < flash


@pytest.mark.parametrize(("profile", "board", "written"), [
    ("rhand", [], "D99"), ("rhand", [], "d99"),
    ("inmoov", ["--board", "servo_inmoov_left"], "A85")])
def test_a_button_on_no_such_pin_is_named_as_the_user_wrote_it(profile, board, written,
                                                             tmp_path, capsys):
    gesture = "fist" if profile == "rhand" else "look_around"
    assert gestc.main(["firmware", profile, *board, "-o", str(tmp_path), "--button",
                       f"{written}={gesture}"]) == 1
    err = capsys.readouterr().err
    assert err.startswith(f"gestc: error: --button {written}={gesture}: there is no such "
                          "pin\n  hint: free pins on board 18")
