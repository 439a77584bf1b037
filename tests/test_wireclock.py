"""Timing set by the wire's clock, proven on the firmware image in simavr: the library
sent as one continuous run (CANCEL between commands, as gestplay sends it) against the
same streams sent bare; the board's input at 9600, 57600 and 115200 baud; a Ctrl-C in
the middle of demo, on gestsim's pty and on the image's. Every time asserted is the
board's own (simavr's cycles), which a busy machine does not stretch: the image runs
late there, but what it receives, and when in its own time, is what the wire brings."""

import dataclasses
import signal
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest
from boardmodel import read_stream
from conftest import WHOLE_ROBOT
from hardest import hardest
from stopping import Harness, after_signal, stop_mid_gesture, stop_on_board_time
from test_firmware import (  # noqa: F401
    JITTER,
    LIBRARY,
    REST,
    RHAND_PINS,
    assert_pins,
    boards,
    build,
    pulses_of,
    simboard,
    simulate,
)
from toolchain import need

from inmoov_dsl.boards.rig import commands
from inmoov_dsl.boards.rig.core import BoardCore
from inmoov_dsl.cli import gestc
from inmoov_dsl.compiling.compiled import to_timed
from inmoov_dsl.compiling.compiler import compile_program
from inmoov_dsl.language.load import load
from inmoov_dsl.profiles.profile import load_profile
from inmoov_dsl.protocol import SERVO_FRAME, Signal, pairs
from inmoov_dsl.wire.pace import padded, places

RHAND = load_profile("rhand")
HAND = sorted(n for n, e in LIBRARY.items() if e.path.name not in WHOLE_ROBOT)
SAME_PULSE = 10.0  # us


def at_baud(profile, baud):
    """``profile`` with every board's link at ``baud``."""
    return dataclasses.replace(profile, boards=tuple(dataclasses.replace(b, baud=baud)
                                                     for b in profile.boards))


def run_of(stream) -> str:
    """``stream`` as gestplay sends it: one continuous run, a byte every byte-time."""
    tau = stream.byte_time
    return "".join(f"{k * tau:.6f} {b}\n"
                   for k, b in enumerate(padded(stream.times, stream.data, tau)))


def test_the_hardest_gestures_sent_as_one_run_end_and_pulse_as_sent_bare(simboard, build,  # noqa: F811
                                                                        tmp_path):
    """The hand gestures of the library that ask the most of the board (hardest.py), and
    peace, from a new EEPROM, then 1.1 s still. Sent bare
    at its planned times at 9600 baud: the board ends in the gesture's final pose and
    reads every byte, and every pulse on every pin, from the first, is the width the
    original firmware gives a value the board was sent (the Python board decodes which).
    Sent as one run (gestplay's way): the same DUMP, every byte read, every pulse within
    10 us of the bare run's (start and width), the EEPROM written alike (one record when
    a gesture ends; demo's parts hold a second each: six)."""
    elf = build / "servo_rhand.elf"
    ids = [s.id for s in RHAND.servos]
    pin_of = {s.id: s.pin for s in RHAND.servos}

    def one(name):
        compiled, _ = compile_program(load(str(LIBRARY[name].path)), name, RHAND)
        stream = compiled.stream()
        out = []
        for kind, timed in (("bare", to_timed(stream)), ("run", run_of(stream))):
            out.append(simulate(simboard, elf, timed, "--pulses", "--run-on", "1.1",
                                "--eeprom", tmp_path / f"{name}-{kind}.eep"))
        return name, compiled, *out

    records = {}
    names = hardest({n: compile_program(load(str(LIBRARY[n].path)), n, RHAND)[0].stream()
                     for n in HAND}, ("demo", "peace"))
    with ThreadPoolExecutor(max_workers=2) as pool:
        for name, compiled, bare, run in pool.map(one, names):
            stream = compiled.stream()
            final = dict(zip(ids, compiled.final, strict=True))
            assert bare["dump"] == (181, final), name
            assert bare["read"] == bare["sent"] == len(stream.data) + 1, name
            assert_pins(bare["pins"], pulses_of(final))  # what each servo is told
            # and the first pulse was the rest pose: no pin pulsed before it had a value
            assert_pins(bare["pins"], pulses_of(dict.fromkeys(ids, 0)), "first")
            core = BoardCore.from_profile(RHAND, RHAND.boards[0])
            widths = {pin: {width} for pin, width in pulses_of(REST).items()}
            for byte in stream.data:
                write, _ = core.feed(byte)
                if write:
                    widths[pin_of[write.id]].add(RHAND_PINS[pin_of[write.id]].pulse(write.value))
            for pin, _, us in bare["pulses"]:
                assert min(abs(us - w) for w in widths[pin]) <= JITTER, (name, pin, us)
            # the same gesture as one run
            ran = padded(stream.times, stream.data, stream.byte_time)
            assert run["read"] == run["sent"] == len(ran) + 1, name  # the DUMP too
            assert run["dump"] == bare["dump"], name
            assert len(run["pulses"]) == len(bare["pulses"]), name
            a, b = np.array(run["pulses"]), np.array(bare["pulses"])
            assert np.array_equal(a[:, 0], b[:, 0]), name  # the same pins, in turn
            assert np.max(np.abs(a[:, 1] - b[:, 1])) * 1e6 <= SAME_PULSE, name
            assert np.max(np.abs(a[:, 2] - b[:, 2])) <= SAME_PULSE, name
            assert [e[1:] for e in run["eeprom"]] == [e[1:] for e in bare["eeprom"]], name
            assert all(abs(x[0] - y[0]) < 0.002 for x, y in zip(run["eeprom"], bare["eeprom"],
                                                                strict=True)), name
            records[name] = len(run["eeprom"])
    assert list(records) == names and len(HAND) >= 29
    size = records["peace"]  # the bytes of one record
    assert size > 0 and {n: r // size for n, r in records.items() if r != size} == \
        {"demo": 6}


@pytest.fixture(scope="module")
def image_at(build, tmp_path_factory):  # noqa: F811
    """servo_rhand built for a link at ``baud`` (9600: the suite's own build)."""
    made = {9600: build / "servo_rhand.elf"}

    def at(baud):
        if baud not in made:
            need("make", "avr-gcc", "avr-g++")
            book = tmp_path_factory.mktemp(f"rhand-{baud}")
            assert gestc.main(["firmware", "rhand", "--baud", str(baud), "-o", str(book)]) == 0
            done = subprocess.run(["make", "-C", str(book), "-j2", "servo_rhand"],
                                  capture_output=True, text=True, timeout=600)
            assert done.returncode == 0, done.stdout + done.stderr
            made[baud] = book / "build" / "servo_rhand.elf"
        return made[baud]
    return at


@pytest.mark.parametrize("baud", [9600, 57600, 115200])
def test_a_continuous_run_never_overflows_the_boards_input(simboard, image_at, baud):  # noqa: F811
    """wave as one run at the link's full rate: the image reads every byte (its 64-byte
    buffer never overflows), answers the filler with WAIT, and ends where wave does."""
    profile = at_baud(RHAND, baud)
    compiled, _ = compile_program(load(str(LIBRARY["wave"].path)), "wave", profile)
    stream = compiled.stream()
    ran = padded(stream.times, stream.data, stream.byte_time)
    result = simulate(simboard, image_at(baud), run_of(stream), baud=baud)
    assert result["read"] == result["sent"] == len(ran) + 1
    assert result["dump"] == (181, dict(zip(range(6), compiled.final, strict=True)))
    waits = sum(1 for _, b in result["out"] if b == Signal.WAIT)
    assert waits > len(ran) // 4  # the board kept up: nothing left to read, again and again


# -- Ctrl-C in the middle of demo ------------------------------------------------------------
DEMO = compile_program(load(str(LIBRARY["demo"].path)), "demo", RHAND)[0].stream()


@pytest.fixture
def gestsim_pty(tmp_path):
    """gestsim on a pty, logging when each byte starts on its wire: (its path, the log)."""
    log = tmp_path / "received.log"
    proc = subprocess.Popen([sys.executable, "-m", "inmoov_dsl.cli.gestsim", "--quiet",
                             "--boot", "0.2", "--log", str(log)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    path = proc.stdout.readline().strip()
    assert path.startswith("/dev/"), proc.stderr.read()
    yield path, log
    proc.kill()
    proc.wait()


@pytest.fixture
def image_pty(simboard, build, tmp_path):  # noqa: F811
    """The firmware image in simavr on a pty, taking orders (``--control``) and logging
    when each byte starts on the board's wire, in its own time: (the harness, the log)."""
    log = tmp_path / "received.log"
    proc = subprocess.Popen([str(simboard), str(build / "servo_rhand.elf"), "--pty", "--log",
                             str(log), "--control"], stdin=subprocess.PIPE,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    harness = Harness(proc)
    assert harness.path.startswith("/dev/"), proc.stderr.read()
    yield harness, log
    proc.kill()
    proc.wait()


def run_lateness(times, data, stream) -> float:
    """s the link ran behind the run's own schedule when its last pair reached the board,
    in the board's time: each pair of the run (after the player's DUMP request) against
    its place on the run's byte grid (``pace.places``: the player's clock), the earliest
    taken as on time. What a busy machine adds on the way (a pty that hands the bytes
    over late, a simulator that takes them late), none of the player's horizon."""
    where = places(stream.times, stream.data, stream.byte_time)
    ids = [where[first] for first, stop in commands(stream.data) if stop - first == 2]
    late, k = [], len(data) - data[::-1].index(Signal.DUMP)
    while k < len(data):
        if data[k] != Signal.CANCEL:  # a pair: its ID, then its value
            late.append(times[k] - ids[len(late)] * stream.byte_time)
            k += 1
        k += 1
    return late[-1] - min(late)


def test_ctrl_c_in_demo_reaches_gestsim_as_a_cancel(gestsim_pty):
    """The player's status and words; the board's last byte is the CANCEL, mid-gesture.
    (How much of the run still reaches it: on the image, which can tell, below.)"""
    path, log = gestsim_pty
    ended, signalled, times, data = stop_mid_gesture(log, ["demo", "--port", path],
                                                     signal.SIGINT, 2.0)
    assert ended.returncode == 130, ended.stderr
    assert "gestplay: interrupted: CANCEL sent, the hand holds its pose" in ended.stderr
    after_signal(times, data, signalled)
    assert 0 < len(read_stream(times, data, 9600)) < len(pairs(DEMO.data))  # mid-gesture


def test_ctrl_c_in_demo_reaches_the_board_as_a_cancel_behind_the_horizon(image_pty):
    """The player drops what the port holds and sends CANCEL; what the pty's other end
    had already taken (as a USB adapter's chip would) still goes first: at most the
    horizon. In the board's own time: the harness signals the player 2 s into demo by
    its clock, and what reaches the board after that, before the CANCEL, is no more than
    a servo frame of the run (the horizon, 15 ms, and the player's noticing the signal)
    beyond how late the link itself ran (measured at the board). How soon in the
    computer's time is benchmarks/stop.py's figure."""
    harness, log = image_pty
    ended, signalled, times, data = stop_on_board_time(
        harness, log, ["demo", "--port", harness.path], signal.SIGINT, 2.0)
    assert ended.returncode == 130, ended.stderr
    assert "gestplay: interrupted: CANCEL sent, the hand holds its pose" in ended.stderr
    after = [b for t, b in zip(times, data, strict=True) if t >= signalled]
    assert after[-1:] == [Signal.CANCEL], after[-8:]  # the last byte the board got
    assert 0 < len(read_stream(times, data, 9600)) < len(pairs(DEMO.data))  # mid-gesture
    late = run_lateness(times, data, DEMO)
    bound = (SERVO_FRAME + late) / DEMO.byte_time + 2  # a command goes whole, rounded up
    assert len(after) - 1 <= bound, (len(after) - 1, round(late * 1000, 1), bound)
