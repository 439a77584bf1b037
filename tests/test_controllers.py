"""The kinds of board (boards/): the virtual Maestro against Pololu's documented command
bytes, the PCA9685 register model against its datasheet, and the right hand's library
on ``rhand-maestro`` and ``rhand-pca9685`` against the pulses our firmware gives."""

from pathlib import Path

import numpy as np
import pytest
from conftest import WHOLE_ROBOT

from inmoov_dsl import load_profile
from inmoov_dsl.boards import controller
from inmoov_dsl.boards.maestro import commands as mc
from inmoov_dsl.boards.maestro.device import MaestroCore
from inmoov_dsl.boards.pca9685 import chip as regs
from inmoov_dsl.boards.pca9685 import transactions as tx
from inmoov_dsl.boards.pca9685.bus import I2CPort, open_bus
from inmoov_dsl.boards.rig.core import BoardServo
from inmoov_dsl.cli.hand import reach
from inmoov_dsl.compiling.compiler import compile_program
from inmoov_dsl.errors import GestError
from inmoov_dsl.language.library import scan_library
from inmoov_dsl.language.load import load
from inmoov_dsl.wire.player import Link, play
from inmoov_dsl.wire.ports import open_port
from inmoov_dsl.wire.ready import ask_dump
from inmoov_dsl.wire.sim import VirtualBoard

ROOT = Path(__file__).resolve().parent.parent
LIBRARY = scan_library([ROOT / "gestures"])
HAND = sorted(n for n, e in LIBRARY.items() if e.path.name not in WHOLE_ROBOT)
RHAND = load_profile("rhand")
MAESTRO = load_profile("rhand-maestro")
PCA = load_profile("rhand-pca9685")


def maestro(model="mini12", device=12) -> MaestroCore:
    c = controller(MAESTRO, MAESTRO.boards[0])
    return MaestroCore(181, c.servos, c.widths, model, device)


def feed(core, data: bytes) -> bytes:
    out = bytearray()
    for byte in data:
        out += core.feed(byte)[1]
    return bytes(out)


# -- the Maestro, by Pololu's documentation ----------------------------------------------
def test_the_documented_set_target_is_1500_us_on_channel_2():
    assert mc.set_target(2, 6000) == bytes([0x84, 0x02, 0x70, 0x2E])
    core = maestro()
    feed(core, bytes([0x84, 0x02, 0x70, 0x2E]))
    assert core.targets[2] == 6000 and core.errors == 0
    assert feed(core, bytes([0x90, 0x02])) == bytes([0x70, 0x17])  # 6000, little-endian


def test_the_pololu_protocol_answers_its_own_device_number_only():
    core = maestro(device=12)
    feed(core, bytes([0xAA, 0x0C, 0x04, 0x02, 0x70, 0x2E]))  # device 12: Set Target
    assert core.targets[2] == 6000
    feed(core, bytes([0xAA, 0x0D, 0x04, 0x02, 0x40, 0x1F]))  # device 13: not this one
    assert core.targets[2] == 6000 and core.errors == 0
    assert mc.command(mc.SET_TARGET, [2, 0x70, 0x2E], 12) == bytes(
        [0xAA, 0x0C, 0x04, 0x02, 0x70, 0x2E])


def test_set_multiple_targets_on_a_mini_and_a_protocol_error_on_a_micro():
    data = mc.set_targets(3, [6000, 8000])
    assert data == bytes([0x9F, 0x02, 0x03, 0x70, 0x2E, 0x40, 0x3E])
    mini = maestro("mini12")
    feed(mini, data)
    assert mini.targets[3:5] == [6000, 8000] and mini.errors == 0
    micro = maestro("micro6")
    feed(micro, mc.set_target(2, 6000))
    feed(micro, data)
    assert micro.errors & mc.PROTOCOL_ERROR
    assert micro.targets[2] == 0  # an error sends every channel home: pulses off


def test_errors_are_read_once_and_a_command_cut_short_is_one():
    core = maestro()
    feed(core, bytes([0x84, 0x02, 0x70]) + mc.set_target(1, 6000))  # cut short
    assert feed(core, bytes([mc.GET_ERRORS])) == bytes([mc.PROTOCOL_ERROR, 0])
    assert feed(core, bytes([mc.GET_ERRORS])) == bytes([0, 0])  # reading cleared it
    feed(core, bytes([0x02]))  # a data byte where a command is due
    assert core.errors == mc.PROTOCOL_ERROR
    assert "serial protocol error" in mc.describe(core.errors)


def test_targets_are_kept_within_the_channel_limits_and_0_is_off():
    core = maestro()
    feed(core, mc.set_target(0, 100 * 4) + mc.set_target(1, 3000 * 4) + mc.set_target(2, 0))
    assert core.targets[:3] == [500 * 4, 2500 * 4, 0]


# -- the PCA9685, by its datasheet -------------------------------------------------------
def test_prescale_is_refused_while_the_chip_is_awake():
    assert regs.prescale(50) == 121
    chip = regs.Chip()
    chip.write(regs.MODE1, bytes([regs.AI]))  # awake
    chip.write(regs.PRESCALE, bytes([121]))
    assert chip.registers[regs.PRESCALE] == 30 and chip.refused
    chip.write(regs.MODE1, bytes([regs.SLEEP | regs.AI]))
    chip.write(regs.PRESCALE, bytes([121]))
    assert chip.registers[regs.PRESCALE] == 121


def test_a_channel_s_pulse_is_its_off_count_and_full_off_wins():
    chip = regs.Chip()
    chip.write(regs.MODE1, bytes([regs.SLEEP | regs.AI]))
    chip.write(regs.PRESCALE, bytes([121]))
    chip.write(regs.MODE1, bytes([regs.AI]))
    chip.write(regs.led(3), bytes([0, 0, 307 & 0xFF, 307 >> 8]))
    assert chip.pulse(3) == pytest.approx(307 * 122 / 25e6)  # 1.4986 ms
    chip.write(regs.led(3) + 3, bytes([0x10 | 307 >> 8]))
    assert chip.pulse(3) == 0.0
    chip.write(regs.MODE1, bytes([0]))  # no auto-increment: every byte to one register
    chip.write(regs.led(4), bytes([1, 2, 3]))
    assert list(chip.registers[regs.led(4):regs.led(4) + 2]) == [3, 0]


def test_the_port_makes_each_transaction_a_block_write_of_at_most_32_bytes():
    calls = []

    class Bus:
        def write_i2c_block_data(self, address, register, data):
            calls.append((address, register, len(data)))

        def close(self):
            pass

    port = I2CPort(Bus(), 0x41, "i2c:1@0x41")
    data = tx.write(regs.led(0), bytes(16 * 4))
    port.write(data[:10])  # half a transaction waits for the rest
    assert calls == []
    port.write(data[10:])
    assert calls == [(0x41, regs.led(0), 32), (0x41, regs.led(8), 32)]


class ChipBus:
    """A bus with one PCA9685 model at ``address``, called as ``smbus2.SMBus`` is."""

    def __init__(self, chip, address=0x40):
        self.chip, self.address = chip, address

    def _check(self, address):
        if address != self.address:
            raise OSError(121, "Remote I/O error")  # nobody acknowledges the address

    def write_i2c_block_data(self, address, register, data):
        self._check(address)
        self.chip.write(register, bytes(data))

    def read_i2c_block_data(self, address, register, length):
        self._check(address)
        return list(self.chip.read(register, length))

    def close(self):
        pass


def test_a_bus_that_does_not_answer_is_a_clear_error():
    port = I2CPort(ChipBus(regs.Chip(), address=0x40), 0x41, "i2c:1@0x41")
    with pytest.raises(OSError, match="the PCA9685 at 0x41 did not answer"):
        port.write(tx.read(regs.MODE1, 1))
    for spec, message in [("COM3", "a PCA9685 is on an I2C bus"),
                          ("i2c:1@0x99", "0x99 is not a PCA9685.s address, which is 0x40..0x77 "
                           "except 0x70")]:
        with pytest.raises(GestError, match=message):
            open_bus(spec)


# -- the right hand on each controller: the firmware's pulses ----------------------------
def final_widths(profile, name: str) -> dict[int, float]:
    """Servo ID -> the width (us) the board of ``profile`` sends once ``name`` has played
    on its virtual device, from the rest pose (set up, and holding it, as a connected
    board is)."""
    compiled, _ = compile_program(load(str(LIBRARY[name].path)), name, profile)
    c = controller(profile, profile.boards[0])
    core = c.core()
    rest = c.set_values({s.id: s.rest for s in c.servos})
    for byte in c.setup() + rest + compiled.streams[0].data:
        core.feed(byte)
    if profile is MAESTRO:
        return {s.id: core.targets[s.pin] / 4 for s in c.servos}
    return {s.id: core.chip.pulse(s.pin) * 1e6 for s in c.servos}


@pytest.mark.parametrize("name", HAND)
def test_every_hand_gesture_ends_in_the_firmware_s_pulses(name):
    """The rig's final values, as the firmware's Servo library turns them into widths
    (what test_firmware proves the image puts on the pins), are the widths the Maestro
    ends at within a quarter-microsecond and the PCA9685 within half a tick."""
    compiled, _ = compile_program(load(str(LIBRARY[name].path)), name, RHAND)
    firmware = {s.id: BoardServo(s.id, s.calibration, s.reversed).pulse(v)
                for s, v in zip(RHAND.servos, compiled.final, strict=True)}
    tick = controller(PCA, PCA.boards[0]).tick * 1e6
    for profile, bound in ((MAESTRO, 0.125), (PCA, tick / 2)):
        got = final_widths(profile, name)
        assert all(abs(got[i] - firmware[i]) <= bound + 1e-9 for i in firmware), \
            (profile.name, got, firmware)


@pytest.mark.parametrize("profile", [MAESTRO, PCA], ids=lambda p: p.name)
def test_an_update_every_frame_while_a_servo_moves_and_no_step_above_its_limit(profile):
    name = "wave"
    compiled, _ = compile_program(load(str(LIBRARY[name].path)), name, profile)
    c = controller(profile, profile.boards[0])
    stream = compiled.streams[0]
    frames = {}
    for first, stop in c.commands(stream.data):
        for sid, unit in c.moves(stream.data[first:stop]):
            frames.setdefault(sid, []).append((round(stream.times[stop - 1] / 0.02), unit))
    per_us = 4 if profile is MAESTRO else 1 / (c.tick * 1e6)
    assert frames
    moving = [s for s in c.servos if len(frames.get(s.id, ())) > 1]  # (one: held)
    assert moving
    for s in moving:
        f, units = zip(*frames[s.id], strict=True)
        assert len(set(f)) == len(f)  # one update per frame at most
        # a servo moves in unbroken runs: a frame without an update is one it held
        steps = np.abs(np.diff(units)) / per_us  # us per update
        us_per_value = np.abs(np.diff(c.widths[[x.id for x in c.servos].index(s.id)]
                                      .table)).max()
        assert steps.max() <= s.max_velocity * 0.02 * us_per_value + 1 + 5 / per_us


@pytest.mark.parametrize("profile", [MAESTRO, PCA], ids=lambda p: p.name)
def test_sim_plays_and_reads_back_the_pose_from_a_non_rest_start(profile):
    """On the virtual device behind sim://: the pose read back is the one left, and a
    gesture from it starts next to it (no jump)."""
    from inmoov_dsl.wire.link import connect, parse_ports

    links = connect(parse_ports(["sim://?fresh"], profile), profile)
    try:
        c = links[0].controller
        # as gestplay connects: ready, errors said, pose asked, set up
        assert reach(links[0], profile, False, "") == {s.id: s.rest for s in c.servos}
        first, _ = compile_program(load(str(LIBRARY["fist"].path)), "fist", profile)
        play(first, links)
        held = ask_dump(links[0].port, 181, controller=c)
        assert held == {s.id: 180 if s.name != "wrist" else 0 for s in c.servos}
        start = {s.name: held[s.id] for s in c.servos}
        then, _ = compile_program(load(str(LIBRARY["open"].path)), "open", profile,
                                  start=start)
        first_moves = dict(reversed(c.moves(then.streams[0].data)))  # each one's first
        us = 0.25 if profile is MAESTRO else c.tick * 1e6  # per unit
        assert first_moves
        for s in c.servos:
            if s.id in first_moves:
                now = c.set_values({s.id: held[s.id]})
                # within a degree of the servo's angle (10.3 us) of the pose read back
                assert abs(first_moves[s.id] - dict(c.moves(now))[s.id]) * us <= 10.4
    finally:
        for link in links:
            link.port.close()


def test_a_board_s_kind_is_checked_in_the_profile(tmp_path):
    from inmoov_dsl.profiles.profile import parse_profile

    text = (ROOT / "gestures/profiles/rhand-maestro.toml").read_text()
    wrong = text.replace('kind = "maestro"', 'kind = "maestr"')
    with pytest.raises(GestError) as exc:
        parse_profile(wrong, "p.toml")
    assert "'kind' must be one of rig, maestro, pca9685" in str(exc.value)
    assert "did you mean 'maestro'" in str(exc.value.first.hint)
    assert len(exc.value.diagnostics) == 1  # not its servos' pins 0 and 1, as a rig's
    micro = text.replace('model = "mini12"', 'model = "micro6"').replace("pin = 5", "pin = 6")
    with pytest.raises(GestError, match=r"has channels 0\.\.5"):
        parse_profile(micro, "p.toml")
    twice = text.replace("pin = 5", "pin = 4")
    with pytest.raises(GestError, match="channel 4 of board 181 is servo 'ring'"):
        parse_profile(twice, "p.toml")


def test_a_kind_is_one_folder_and_the_profile_reader_names_none():
    """Each kind's part of a profile is declared in its folder (``table.py``), listed
    once in ``boards.TABLES``; the profile reader names no kind."""
    from inmoov_dsl.boards import TABLES

    folders = {p.parent.name for p in (ROOT / "inmoov_dsl" / "boards").glob("*/table.py")}
    assert folders == set(TABLES) == {"rig", "maestro", "pca9685", "mrlcomm"}
    for module in (ROOT / "inmoov_dsl" / "profiles").glob("*.py"):
        code = module.read_text()
        assert not [k for k in TABLES if f'"{k}"' in code], module.name


def test_virtual_board_logs_every_servo_a_command_sets():
    c = controller(MAESTRO, MAESTRO.boards[0])
    board = VirtualBoard(c.core(), 115200, chatty=False)
    board.write(c.set_values({1: 90, 2: 90, 3: 90}), 0.0)
    board.advance(1.0)
    assert sorted(w.id for _, w in board.log) == [1, 2, 3]
    assert board.read(1.0) == b""  # a Maestro says nothing it is not asked
    link = Link(181, None, "", c)
    assert link.controller.kind == "maestro"


@pytest.mark.parametrize("profile", [MAESTRO, PCA], ids=lambda p: p.name)
def test_a_compiled_file_carries_the_board_s_kind_and_its_rules(profile):
    import json

    from inmoov_dsl.compiling.compiled import to_json
    from inmoov_dsl.compiling.compiled_reader import from_json
    from inmoov_dsl.compiling.playable import check_profile

    compiled, _ = compile_program(load(str(LIBRARY["wave"].path)), "wave", profile)
    again = from_json(to_json(compiled), "wave.gestc")
    assert again.streams[0].kind == profile.boards[0].kind
    assert again.streams[0].data == compiled.streams[0].data
    check_profile(again, profile)
    with pytest.raises(GestError, match=r"as a \w+, and profile 'rhand' has a rig there"):
        check_profile(again, RHAND)
    doc = json.loads(to_json(compiled))
    doc["streams"][0]["bytes"] = doc["streams"][0]["bytes"][:-1]  # a command cut short
    doc["streams"][0]["times"] = doc["streams"][0]["times"][:-1]
    with pytest.raises(GestError, match="cut short"):
        from_json(json.dumps(doc), "cut.gestc")
    doc["streams"][0]["kind"] = "servo2040"
    with pytest.raises(GestError, match="'kind' must be one of rig, maestro, pca9685"):
        from_json(json.dumps(doc), "kind.gestc")


def test_ports_says_who_answers_a_board_of_ours_a_maestro_and_its_errors(capsys,
                                                                          monkeypatch):
    from serial.tools import list_ports, list_ports_common

    from inmoov_dsl.cli import gestplay
    from inmoov_dsl.wire.urlhandler import protocol_sim

    def port(device, description, vid, pid):
        info = list_ports_common.ListPortInfo(device, skip_link_detection=True)
        info.description, info.vid, info.pid = description, vid, pid
        return info

    protocol_sim.power_off()
    monkeypatch.setattr(list_ports, "comports", lambda: [
        port("sim://rhand?fresh&boot=0", "Arduino Uno", 0x2341, 0x0043),
        port("sim://rhand-maestro?fresh", "Pololu Mini Maestro 12", 0x1FFB, 0x008A),
        port("sim://rhand-maestro?fresh&board=181", "Pololu Mini Maestro 12", 0x1FFB,
             0x008A),
        port("/dev/ttyS0", "n/a", None, None)])
    # the second Maestro was sent a command cut short: it reports a protocol error
    cut = open_port("sim://rhand-maestro?fresh&board=181", 115200)
    cut.write(bytes([0x84, 0x01]) + mc.set_target(1, 6000))
    cut.close()
    assert gestplay.main(["ports"]) == 0
    out = dict(line.split("\t", 1) for line in capsys.readouterr().out.splitlines())
    assert out["sim://rhand?fresh&boot=0"].endswith(
        "answers: board 181, 6 servos (our firmware or the original)")
    assert out["sim://rhand-maestro?fresh"].endswith(
        "answers: a Pololu Maestro's Command Port: no errors")
    assert out["sim://rhand-maestro?fresh&board=181"].endswith(
        "answers: a Pololu Maestro's Command Port: errors: serial protocol error (cleared "
        "now)")
    assert out["/dev/ttyS0"] == "n/a\t-"  # an unknown device is not sent a byte
    protocol_sim.power_off()


@pytest.mark.parametrize("stops", [[0.7], [0.7, 0.703], [0.7, 0.75, 0.9]])
@pytest.mark.parametrize("profile", [MAESTRO, PCA], ids=lambda p: p.name)
def test_the_drive_loop_says_the_pose_a_maestro_or_a_pca9685_holds(profile, stops):
    """The repl's, the service's and the ROS node's one drive loop on another kind: take
    overs and stops at any moment, and the board holds the pose the loop reports; no
    servo jumps."""
    import itertools

    from test_repl import ClockedPort, Timeline

    from inmoov_dsl.live.drive import Drive, library_program
    from inmoov_dsl.live.orders import Control, Order

    timeline = Timeline([(0.0, Order("fingers 180, wrist 180 over 2s", "a")),
                         (0.6, Order("index 0 over 2s", "b")),
                         *[(t, Control("stop", f"s{k}")) for k, t in enumerate(stops)]])
    c = controller(profile, profile.boards[0])
    board = VirtualBoard(c.core(), 115200, chatty=False)
    board.write(c.setup() + c.set_values({s.id: s.rest for s in c.servos}), 0.0)
    loop = Drive([Link(181, ClockedPort(board, timeline), "timeline", c)], profile, {},
                 library_program(), lambda note: None, now=timeline.now,
                 sleep=timeline.sleep)
    loop.run(timeline.next_line)
    board.advance(timeline.t + 1)
    assert board.positions() == {s.id: v for s, v in zip(profile.servos, loop.mirror.held(),
                                                         strict=True)}
    index = [w.angle for _, w in board.log if w.id == 2]  # the widths, us
    assert len(index) > 20
    assert max(abs(b - a) for a, b in itertools.pairwise(index)) <= 60  # a frame's motion


def test_an_i2c_bus_that_fails_mid_gesture_is_one_clear_line(capsys, monkeypatch):
    """A PCA9685 that stops answering (a loose wire): one error naming the bus, the
    address and the cause; no traceback."""
    from inmoov_dsl.boards.pca9685 import bus
    from inmoov_dsl.cli import gestplay

    class Loose(ChipBus):
        writes = 0

        def write_i2c_block_data(self, address, register, data):
            Loose.writes += 1
            if Loose.writes > 40:
                raise OSError(121, "Remote I/O error")
            super().write_i2c_block_data(address, register, data)

    monkeypatch.setattr(bus, "open_bus", lambda spec: I2CPort(Loose(regs.Chip()), 0x40,
                                                              spec))
    assert gestplay.main(["wave", "--profile", "rhand-pca9685", "--port", "i2c:1"]) == 1
    err = capsys.readouterr().err
    assert "error: lost the link (board 181 on i2c:1): i2c:1: the PCA9685 at 0x40 did " \
           "not answer (Remote I/O error)" in err
    assert "Traceback" not in err


def test_a_servo_may_give_its_widths_in_microseconds():
    from inmoov_dsl.profiles.profile import parse_profile

    text = (ROOT / "gestures/profiles/rhand-maestro.toml").read_text()
    text = text.replace("[servo.index]", "[servo.index]\npulse = [1000, 2000]", 1)
    profile = parse_profile(text, "p.toml")
    c = controller(profile, profile.boards[0])
    index = [s.name for s in c.servos].index("index")
    # reversed: 0 is 2000 us, 180 is 1000 us; halfway 1500 us, in quarter-us
    assert c.quarters(index, [0, 90, 180, 45.5]).tolist() == [8000, 6000, 4000, 6989]
    with pytest.raises(GestError, match=r"'pulse' must be \[width at 0, width at 180\]"):
        parse_profile(text.replace("pulse = [1000, 2000]", "pulse = [1000, 9000]"), "p.toml")


@pytest.mark.parametrize("name", ["wave", "count", "beckon"])
def test_a_finer_controller_follows_the_plan_at_least_as_closely_as_the_rig(name):
    """Measured from each stream's own commands (``measure``): every servo-frame that
    needs a fresh width gets one, and the board holds the plan as closely as the rig's
    whole degrees allow, or closer."""
    from inmoov_dsl.compiling.metrics import measure

    compiled, plan = compile_program(load(str(LIBRARY[name].path)), name, RHAND)
    rig = measure(plan, compiled.streams)[0]
    for profile in (MAESTRO, PCA):
        compiled, plan = compile_program(load(str(LIBRARY[name].path)), name, profile)
        report = measure(plan, compiled.streams)[0]
        assert report.coverage == 1.0, (profile.name, report)
        assert report.worst_lag <= rig.worst_lag + 1e-9, (profile.name, report, rig)
        assert report.max_error <= 1.5  # a PCA9685's tick is about a degree


@pytest.mark.parametrize("seed", range(3))
def test_rubbish_never_breaks_a_virtual_device_or_a_reader(seed):
    """Seeded random bytes into the virtual Maestro and the PCA9685 (their cores) and
    into the readers of their answers: no exception, no target outside a channel's
    limits, and the Maestro flags what it cannot read."""
    rng = np.random.default_rng(seed)
    data = bytes(rng.integers(0, 256, 20_000, dtype=np.uint8).tolist())
    core = maestro()
    for byte in data:
        core.feed(byte)
    assert all(q == 0 or core.low <= q <= core.high for q in core.targets)
    assert core.errors & mc.PROTOCOL_ERROR
    pca = controller(PCA, PCA.boards[0]).core()
    for byte in data:
        pca.feed(byte)
    for profile in (MAESTRO, PCA):
        c = controller(profile, profile.boards[0])
        pose = c.pose_reader().feed(data[:64])
        assert pose is not None and all(0 <= v <= 180 for v in pose.values())
        assert mc.fault(data) is not None and tx.fault(data) is not None


def test_a_compiled_gesture_that_leaves_a_controller_still_reads_back():
    """Found by the fuzzer: another kind's stream with no bytes (nothing moves)."""
    from inmoov_dsl.compiling.compiled import to_json
    from inmoov_dsl.compiling.compiled_reader import from_json
    from inmoov_dsl.compiling.compiler import compile_source

    compiled = compile_source("g: hold 0.5s\n", "g", MAESTRO)
    assert compiled.streams[0].idle
    assert from_json(to_json(compiled), "g.gestc").streams[0].data == b""
