"""The ``mrlcomm`` kind: MyRobotLab's MrlComm messages laid out as its schema says, the
virtual MrlComm board, MyRobotLab's handshake, and the right hand's library played on
``rhand-mrlcomm`` ending in the firmware's widths with no message lost."""

from pathlib import Path

import numpy as np
import pytest
from conftest import WHOLE_ROBOT

from inmoov_dsl import clock, load_profile
from inmoov_dsl.boards import controller
from inmoov_dsl.boards.mrlcomm import MOVES_PER_FRAME
from inmoov_dsl.boards.mrlcomm import messages as m
from inmoov_dsl.boards.rig.core import BoardServo
from inmoov_dsl.cli.hand import reach
from inmoov_dsl.compiling.compiler import compile_program
from inmoov_dsl.errors import GestError
from inmoov_dsl.language.library import scan_library
from inmoov_dsl.language.load import load
from inmoov_dsl.wire.link import connect, parse_ports
from inmoov_dsl.wire.player import BoardTrouble, play, relax_all
from inmoov_dsl.wire.ready import ask_dump
from inmoov_dsl.wire.urlhandler import protocol_sim

ROOT = Path(__file__).resolve().parent.parent
LIBRARY = scan_library([ROOT / "gestures"])
HAND = sorted(n for n, e in LIBRARY.items() if e.path.name not in WHOLE_ROBOT)
MRL = load_profile("rhand-mrlcomm")
RHAND = load_profile("rhand")
KIND = controller(MRL, MRL.boards[0])


def test_messages_are_laid_out_as_the_schema_says():
    # > servoAttach/deviceId/pin/b16 initPos/b16 initVelocity/str name: id 35
    assert m.message(m.SERVO_ATTACH, 1, 3, 1500, -1, b"index") == bytes(
        [170, 13, 35, 1, 3, 0x05, 0xDC, 0xFF, 0xFF, 5, *b"index"])
    # > servoMoveToMicroseconds/deviceId/b16 target: id 41
    assert m.message(m.SERVO_MOVE_TO_MICROSECONDS, 2, 2400) == bytes([170, 4, 41, 2, 9, 96])
    assert m.message(m.GET_BOARD_INFO) == bytes([170, 1, 2])
    assert m.message(m.ENABLE_ACK, 0) == bytes([170, 2, 8, 0])
    # < publishBoardInfo/version/boardType/b16 microsPerLoop/b16 sram/activePins/[] ...
    info = m.message(m.BOARD_INFO, 68, 1, 100, 5000, 0, bytes([1, 2]))
    assert list(m.Reader().feed(b"MRLComm Reset.   " + info)) == [
        (m.BOARD_INFO, (68, 1, 100, 5000, 0, bytes([1, 2])))]
    assert m.fault(info[:-1]) == "byte 1: an MrlComm message cut short"


def test_the_virtual_board_reads_as_mrlcomm_does():
    """As MrlComm built for the Mega answered in simavr (docs/controllers.md)."""
    core = KIND.twin()

    def said(data: bytes) -> list:
        return list(m.Reader().feed(b"".join(core.feed(b)[1] for b in data)))

    assert said(b"\x01" + m.message(m.GET_BOARD_INFO)) == [  # a stray byte, then a question
        (m.ERROR, (b"error serial",)), (m.BOARD_INFO, (68, 1, 60, 6400, 0, b"")),
        (m.ACK, (m.GET_BOARD_INFO,))]  # acks are on as it starts
    assert said(bytes([170, 2, 200, 0])) == [(m.ERROR, (b"unknown method 200",)),
                                             (m.ACK, (200,))]
    assert said(bytes([170, 2, 5, 1])) == [(m.ACK, (5,))]  # setDebug: read, not modelled
    assert said(bytes([170, 0])) == [(m.ACK, (5,))]  # an empty message: the last again
    assert said(m.message(m.SERVO_ATTACH, 1, 3, 1500, -1, b"i")
                + m.message(m.SERVO_ATTACH_PIN, 1, 3)
                + m.message(m.SERVO_MOVE_TO_MICROSECONDS, 1, 1600)) == [
        (m.ACK, (m.SERVO_ATTACH,)), (m.ACK, (m.SERVO_ATTACH_PIN,)),
        (m.SERVO_EVENT, (1, m.STARTED, 1500, 1600)), (m.ACK, (m.SERVO_MOVE_TO_MICROSECONDS,)),
        (m.SERVO_EVENT, (1, m.STOPPED, 1600, 1600))]
    assert core.devices[1].us == 1600 and core.devices[1].pulsing
    assert said(m.message(m.GET_BOARD_INFO))[0] == (m.BOARD_INFO,
                                                     (68, 1, 60, 6346, 0, b"\x01"))
    assert said(m.message(m.ENABLE_ACK, 0) + m.message(m.SOFT_RESET)) == []  # acks stay off
    assert core.devices == {}
    # a device that does not exist: the error, then the real one ran its method on a null
    # pointer and crashed; the twin stops answering until it is reset
    assert said(m.message(m.SERVO_STOP, 2)) == [(m.ERROR, (b"device does not exist",))]
    assert said(m.message(m.GET_BOARD_INFO)) == [] and core.crashed
    core.restore(None)
    assert said(m.message(m.GET_BOARD_INFO))[0][0] == m.BOARD_INFO


def test_the_pose_is_asked_only_of_the_servos_the_board_has():
    """A board just reset has no servo: its board info says so, and none is asked (a
    servoStop to it would crash MrlComm); one attached is asked where it is, whatever
    else comes (its board info each second, a late event of the last move, twice)."""
    reader = KIND.pose_reader()
    assert KIND.ask_pose() == m.message(m.GET_BOARD_INFO)
    info = m.message(m.BOARD_INFO, 68, 1, 60, 6400, 0, b"")
    assert reader.feed(info) == {s.id: s.rest for s in MRL.servos} and reader.ask() == b""
    reader = KIND.pose_reader()
    assert reader.feed(m.message(m.BOARD_INFO, 68, 1, 60, 6346, 0, b"\x02")) is None
    assert reader.ask() == m.message(m.SERVO_STOP, 2) and reader.ask() == b""
    index = MRL.servos[1]
    stopped = m.message(m.SERVO_EVENT, 2, m.STOPPED, 1000, 1000)
    pose = reader.feed(m.message(m.SERVO_EVENT, 5, m.STOPPED, 900, 900) + info + stopped
                       + stopped)
    assert pose == {**{s.id: s.rest for s in MRL.servos},
                    index.id: KIND.widths[1].value(1000)}


def test_connect_as_myrobotlab_does_and_refuse_another_version():
    protocol_sim.power_off()
    links = connect(parse_ports(["sim://?fresh"], MRL), MRL)
    try:
        pose = reach(links[0], MRL, False, "")  # begin, board info, acks off, attach
        assert pose == {s.id: s.rest for s in MRL.servos}  # a board just reset: the rests
        assert ask_dump(links[0].port, 181, controller=KIND) == pose  # now it can say
    finally:
        links[0].port.close()
    protocol_sim.power_off()
    links = connect(parse_ports(["sim://?fresh"], MRL), MRL)
    links[0].port.board.core.version = 67  # an older MrlComm on the board
    try:
        with pytest.raises(GestError, match="runs MrlComm version 67; this speaks "
                                            "version 68, as MyRobotLab 1.1"):
            reach(links[0], MRL, False, "")
    finally:
        links[0].port.close()


@pytest.mark.parametrize("name", HAND)
def test_every_hand_gesture_ends_in_the_firmware_s_widths_with_no_message_lost(name):
    compiled, _ = compile_program(load(str(LIBRARY[name].path)), name, MRL)
    core = KIND.core()
    moves = 0
    for first, stop in KIND.commands(compiled.streams[0].data):
        for byte in compiled.streams[0].data[first:stop]:
            core.feed(byte)
        moves += 1
    assert moves == len(KIND.moves(compiled.streams[0].data))  # each one a whole move
    final = dict(zip(MRL.names, compiled.final, strict=True))
    for s, d in zip(KIND.servos, KIND.devices, strict=True):
        firmware = BoardServo(s.id, s.calibration, s.reversed).pulse(final[s.name])
        assert abs(core.devices[d].us - firmware) <= 0.5, (name, s.name)


def test_twelve_servos_get_six_moves_a_frame_and_all_end_where_planned():
    """A Mega's dozen servos moving at once: at most MOVES_PER_FRAME moves a frame (what
    MrlComm kept up with), the furthest behind first, and every servo still ends at its
    planned width."""
    from inmoov_dsl.compiling.compiler import compile_source
    from inmoov_dsl.profiles.profile import parse_profile

    servos = "".join(f"[servo.s{k}]\nid = {k}\npin = {k + 2}\nmax_velocity = 400\n"
                     f"max_acceleration = 8000\nmax_jerk = 160000\n" for k in range(12))
    text = ('name = "mega"\n[[board]]\nid = 181\nkind = "mrlcomm"\nservos = ['
            + ", ".join(f'"s{k}"' for k in range(12)) + "]\n" + servos)
    mega = parse_profile(text, "mega.toml")
    compiled = compile_source("g: all 180 over 1s\n", "g", mega)
    kind = controller(mega, mega.boards[0])
    stream, core = compiled.streams[0], kind.core()
    frames: dict[int, int] = {}
    for _, stop in kind.commands(stream.data):
        f = round(stream.times[stop - 1] / 0.02)
        frames[f] = frames.get(f, 0) + 1
    assert max(frames.values()) == MOVES_PER_FRAME
    for byte in stream.data:
        core.feed(byte)
    assert all(abs(core.devices[d].us - 2400) <= 0.5 for d in kind.devices)


def test_relax_detaches_every_pin_and_a_play_on_sim_ends_where_planned():
    protocol_sim.power_off()
    links = connect(parse_ports(["sim://?fresh"], MRL), MRL)
    try:
        reach(links[0], MRL, False, "")
        compiled, _ = compile_program(load(str(LIBRARY["peace"].path)), "peace", MRL)
        play(compiled, links)
        held = ask_dump(links[0].port, 181, controller=KIND)
        assert held == dict(zip((s.id for s in MRL.servos), compiled.final, strict=True))
        relax_all(links)
        board = links[0].port.board
        board.advance(board.sending_until() + 0.01)
        assert board.core.relaxed
    finally:
        links[0].port.close()
    protocol_sim.power_off()


def test_a_profile_s_mrlcomm_servo_needs_a_pin_of_the_mega():
    from inmoov_dsl.profiles.profile import parse_profile

    text = (ROOT / "gestures/profiles/rhand-mrlcomm.toml").read_text()
    with pytest.raises(GestError, match=r"pin 70 cannot drive a servo: an Arduino Mega "
                       r"has pins 2\.\.69"):
        parse_profile(text.replace("pin = 7", "pin = 70"), "p.toml")
    assert np.isfinite(KIND.tau)


def test_ports_names_a_board_running_mrlcomm(virtual_clock, capsys, monkeypatch):
    from serial.tools import list_ports, list_ports_common

    from inmoov_dsl.cli import gestplay

    info = list_ports_common.ListPortInfo("sim://rhand-mrlcomm?fresh",
                                          skip_link_detection=True)
    info.description, info.vid, info.pid = "Arduino Mega 2560", 0x2341, 0x0042
    monkeypatch.setattr(list_ports, "comports", lambda: [info])
    protocol_sim.power_off()
    assert gestplay.main(["ports"]) == 0
    out = capsys.readouterr().out
    assert out.rstrip().endswith("answers: MyRobotLab's MrlComm, version 68: profile kind "
                                 "mrlcomm")
    protocol_sim.power_off()


def test_a_port_where_nothing_answers_is_one_clear_error(virtual_clock, capsys, monkeypatch):
    from inmoov_dsl.cli import gestplay
    from inmoov_dsl.wire import link

    class Silent:
        def write(self, data):
            return len(data)

        def read(self, size=1):
            return b""

        def close(self):
            pass

    monkeypatch.setattr(link, "open_port", lambda name, baud, timeout=0: Silent())
    assert gestplay.main(["wave", "--profile", "rhand-mrlcomm", "--port", "COM4"]) == 1
    err = capsys.readouterr().err
    assert "error: no board answered on COM4 (board 181, mrlcomm at 115200 baud)" in err
    assert "Traceback" not in err


def test_a_board_that_starts_again_mid_gesture_stops_the_play_with_a_clear_message(
        virtual_clock):
    """MrlComm reset mid-gesture (its power, its USB) has lost its servos: its begin
    message ends the play at once, saying so, and nothing more goes to a device that no
    longer exists (the real firmware would run it on a null pointer)."""
    protocol_sim.power_off()
    links = connect(parse_ports(["sim://?fresh"], MRL), MRL)
    board = links[0].port.board
    try:
        reach(links[0], MRL, False, "")
        compiled, _ = compile_program(load(str(LIBRARY["wave"].path)), "wave", MRL)

        reset_at = []

        def progress(t):
            if t > 0.5 and not board.resets:
                reset_at.append(clock.now())
                board.reset(clock.now(), 0.0)  # a brown-out: no DTR, no host

        with pytest.raises(BoardTrouble) as info:
            play(compiled, links, progress=progress)
        assert info.value.diagnostic.message.startswith(
            "board 181 started again mid-gesture (MrlComm's begin message: its power or its "
            "USB reset it); its servos are detached and limp (on sim://")
        assert clock.now() - reset_at[0] < 0.05  # at once: its banner and begin message
        assert not board.core.crashed  # no move reached a device it no longer has
    finally:
        links[0].port.close()


def test_the_service_takes_a_board_that_started_again_as_gone_and_back():
    """The service's port of an MrlComm board that sent its begin message is down (its
    servos are gone): it is connected anew, as a board that was unplugged and came back."""
    from inmoov_dsl.service.links import Resilient
    from inmoov_dsl.wire.player import Link

    class Port:
        def __init__(self, data):
            self.data, self.closed = data, False

        def read(self, size=1):
            data, self.data = self.data, b""
            return data

        def close(self):
            self.closed = True

    lost = []
    events = m.message(m.SERVO_EVENT, 1, m.STARTED, 1000, 1100)
    port = Resilient(Link(181, Port(events), "COM3", KIND), lost.append)
    assert port.read(4096) == events and not port.down
    port.back(Port(KIND.hello()))
    assert port.read(4096) == b"" and port.down and lost == [181]


def test_ports_names_a_mega_of_ours_at_115200_and_never_sends_it_mrlcomm_s_question(
        monkeypatch, virtual_clock):
    """A Mega with our firmware runs at 115200: gestplay ports asks it there, as ours,
    before it asks for MrlComm (whose getBoardInfo, 170 1 2, a board of ours would read as
    part of a servo command)."""
    from inmoov_dsl.wire import identify
    from inmoov_dsl.wire.link import open_board
    from inmoov_dsl.wire.ports import PortInfo

    inmoov = load_profile("inmoov")
    protocol_sim.power_off()
    mega = open_board("sim://inmoov?board=181&fresh", inmoov, inmoov.boards[0])
    heard = []

    class Garbled:  # the port at a speed the board does not run at: noise, no answer
        def write(self, data):
            heard.append((9600, bytes(data)))
            return len(data)

        def read(self, size=1):
            return b""

        def close(self):
            pass

    class Kept:  # the Mega's port, opened again and again (each close is not the end)
        def write(self, data):
            heard.append((115200, bytes(data)))
            return mega.write(data)

        def read(self, size=1):
            return mega.read(size)

        def close(self):
            pass

    monkeypatch.setattr(identify, "open_port",
                        lambda device, baud, timeout=0: Kept() if baud == 115200 else Garbled())
    said = identify.answer(PortInfo("/dev/ttyACM0", "Arduino Mega 2560", 0x2341, 0x0042))
    assert said == "board 181, 10 servos at 115200 baud (our firmware or the original)"
    assert not any(m.message(m.GET_BOARD_INFO) in data for _, data in heard)
    board = mega.board
    assert board.positions() == {s.id: s.rest for s in inmoov.servos if s.board == 181}
    mega.close()
    protocol_sim.power_off()


def test_the_whole_robot_plays_with_ours_on_one_mega_and_mrlcomm_on_the_other(
        virtual_clock, tmp_path):
    """The InMoov's right Mega with our firmware, its left still on MrlComm (a profile
    says which kind each board runs): hello ends where planned on both."""
    from inmoov_dsl.cli.hand import board_pose
    from inmoov_dsl.profiles.profile import parse_profile

    text = (ROOT / "gestures/profiles/inmoov.toml").read_text()
    left = text.index('name = "left"')
    path = tmp_path / "mixed.toml"
    path.write_text(text[:left] + text[left:].replace('arduino = "mega"', 'kind = "mrlcomm"',
                                                      1).replace('name = "inmoov"', ""))
    mixed = parse_profile(path.read_text(), str(path))
    assert [b.kind for b in mixed.boards] == ["rig", "mrlcomm"]
    protocol_sim.power_off()
    links = connect(parse_ports(["right=sim://?fresh", "left=sim://?fresh"], mixed), mixed)
    try:
        start = board_pose(links, mixed)
        compiled, _ = compile_program(load(str(LIBRARY["hello"].path)), "hello", mixed, start)
        assert [s.kind for s in compiled.streams] == ["rig", "mrlcomm"]
        play(compiled, links)
        for link in links:
            link.port.board.advance(clock.now())
            held = link.port.board.positions()
            for s in (s for s in mixed.servos if s.board == link.board):
                planned = compiled.final[mixed.index(s.name)]
                assert abs(held[s.id] - planned) <= 1, (s.name, held[s.id], planned)
    finally:
        for link in links:
            link.port.close()
        protocol_sim.power_off()


def test_a_board_that_goes_silent_mid_gesture_stops_the_play_with_a_clear_message(
        virtual_clock):
    """MrlComm says something every second (its board info, unasked, and the events of
    every move): a board silent for 2.5 s has stopped, and the play ends saying so."""
    protocol_sim.power_off()
    links = connect(parse_ports(["sim://?fresh"], MRL), MRL)
    board = links[0].port.board
    try:
        reach(links[0], MRL, False, "")
        idle_start = clock.now()
        clock.sleep(3.5)  # idle, it still says its board info every second
        assert sum(1 for meth, _ in m.Reader().feed(links[0].listen())
                   if meth == m.BOARD_INFO) == 3, clock.now() - idle_start
        compiled, _ = compile_program(load(str(LIBRARY["wiggle"].path)), "wiggle", MRL)
        stopped_at = []

        def progress(t):
            if t > 0.5 and not stopped_at:
                stopped_at.append(clock.now())
                board.core.crashed = True  # it hangs: it reads and says nothing more

        with pytest.raises(BoardTrouble) as info:
            play(compiled, links, progress=progress)
        message = info.value.diagnostic.message
        assert message.startswith("board 181 has sent nothing for 2.") and message.endswith(
            "s (MrlComm sends its board info every second): it has stopped (its power? a "
            f"crash?) (on {links[0].name})")
        assert 2.5 < clock.now() - stopped_at[0] < 2.7
    finally:
        links[0].port.close()
        protocol_sim.power_off()
