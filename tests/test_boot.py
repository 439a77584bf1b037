"""A board that opening its port resets is never trapped by us: the player listens
without a word until it speaks or its bootloader has had its time (the Mega's STK500v2
keeps to its command loop after any byte in its first 0.83 s, until it has heard
nothing for seconds: facts.md), and ``gestplay ports`` asks the same way. On the
virtual boards, whose Mega bootloader traps as the real one does (the real ones in
simavr: test_bootloaders.py)."""

from __future__ import annotations

import pytest
from serial.tools import list_ports, list_ports_common

from inmoov_dsl import load_profile
from inmoov_dsl.boards import controller
from inmoov_dsl.boards.arduino import BOOTLOADERS
from inmoov_dsl.cli import gestplay
from inmoov_dsl.wire.ports import open_port, reset_on_open
from inmoov_dsl.wire.ready import PROBE, ask_dump, wait_ready
from inmoov_dsl.wire.urlhandler import protocol_sim

MEGA = "sim://rhand-mrlcomm?boot=0.84"  #: MrlComm on a Mega: its begin 0.84 s after a reset
MEGA_OURS = "sim://inmoov?board=181&boot=0.84"  #: our firmware on the InMoov's right Mega


class Spy:
    """A port that notes when each write happened."""

    def __init__(self, port, now):
        self.port, self.now, self.writes = port, now, []
        self.reset_on_open = port.reset_on_open

    def write(self, data: bytes) -> int:
        self.writes.append(self.now())
        return self.port.write(data)

    def read(self, size: int = 1) -> bytes:
        return self.port.read(size)


def mega(url: str):
    profile = load_profile(url.split("//")[1].split("?")[0])
    board = next(b for b in profile.boards if f"board={b.id}" in url or len(profile.boards) == 1)
    return controller(profile, board)


@pytest.mark.parametrize("url", [MEGA, MEGA_OURS])
def test_after_a_reset_nothing_is_sent_until_the_board_speaks(virtual_clock, url):
    kind = mega(url)
    assert kind.bootloader() == BOOTLOADERS["mega"]
    port = open_port(url, kind.board.baud)
    assert reset_on_open(port)
    spy, opened = Spy(port, virtual_clock.now), virtual_clock.now()
    assert wait_ready(spy, controller=kind)
    board = port.board
    assert board.swallowed == 0 and board.ready_at == pytest.approx(opened + 0.84)
    assert all(t >= board.ready_at for t in spy.writes)
    assert virtual_clock.now() - opened < 0.84 + 2 * PROBE  # not the whole window
    assert ask_dump(port, kind.board.id, controller=kind) is not None
    port.close()


def test_a_board_opened_again_without_a_reset_is_asked_at_once(virtual_clock):
    kind = mega(MEGA)
    first = open_port(MEGA, kind.board.baud)
    assert wait_ready(first, controller=kind)
    first.close()  # this open cleared HUPCL: DTR stays up
    port = open_port(MEGA, kind.board.baud)
    assert not reset_on_open(port)
    spy, opened = Spy(port, virtual_clock.now), virtual_clock.now()
    assert wait_ready(spy, controller=kind)
    assert spy.writes[0] == opened and virtual_clock.now() - opened < 0.1
    port.close()


def probing_at_once(port, now, sleep, seconds: float = 2.0) -> bool:
    """What gestplay did before: a question every PROBE s from the open on."""
    kind = mega(MEGA)
    heard, end = b"", now() + seconds
    while now() < end:
        port.write(kind.probe())
        sleep(PROBE)
        heard += port.read(4096)
        if kind.ready(heard):
            return True
    return False


def test_the_virtual_mega_is_trapped_by_a_byte_in_its_window_as_the_real_one(virtual_clock):
    kind = mega(MEGA)
    port = open_port(MEGA, kind.board.baud)
    assert not probing_at_once(port, virtual_clock.now, virtual_clock.sleep)
    last = virtual_clock.now()
    assert port.board.ready_at == pytest.approx(last - PROBE + BOOTLOADERS["mega"].trap,
                                                abs=0.01)
    port.close()


def test_a_mega_trapped_by_another_program_is_left_alone_until_it_starts(virtual_clock):
    kind = mega(MEGA)
    port = open_port(MEGA, kind.board.baud)
    probing_at_once(port, virtual_clock.now, virtual_clock.sleep)  # trapped
    port.close()  # DTR stays up: the next open does not reset the board
    port = open_port(MEGA, kind.board.baud)
    opened = virtual_clock.now()
    assert wait_ready(port, controller=kind)  # its questions trap it at first
    assert virtual_clock.now() - opened < 3.0 + BOOTLOADERS["mega"].trap + 1.0
    assert ask_dump(port, kind.board.id, controller=kind) is not None
    port.close()


@pytest.mark.parametrize("argv", [
    ["wave", "--profile", "rhand-mrlcomm", "--port", MEGA],
    ["wave", "--profile", "inmoov", "--port", "right=" + MEGA_OURS],
])
def test_a_play_from_a_fresh_reset_of_a_mega_connects_and_plays(virtual_clock, capsys, argv):
    protocol_sim.power_off()
    assert gestplay.main(argv) == 0, capsys.readouterr().err
    assert "no board answered" not in capsys.readouterr().err
    protocol_sim.power_off()


@pytest.mark.parametrize(("url", "said"), [
    (MEGA, "MyRobotLab's MrlComm, version 68"),
    ("sim://rhand?boot=0.5", "board 181, 6 servos"),
])
def test_ports_asks_a_named_port_and_names_the_board(virtual_clock, capsys, url, said):
    protocol_sim.power_off()
    assert gestplay.main(["ports", "--port", url]) == 0
    out = capsys.readouterr().out
    assert out.startswith(f"{url}\tnamed\tanswers: {said}"), out
    protocol_sim.power_off()


def test_ports_listens_to_a_mega_it_resets_before_asking(virtual_clock, capsys, monkeypatch):
    info = list_ports_common.ListPortInfo(MEGA, skip_link_detection=True)
    info.description, info.vid, info.pid = "Arduino Mega 2560", 0x2341, 0x0042
    monkeypatch.setattr(list_ports, "comports", lambda: [info])
    protocol_sim.power_off()
    assert gestplay.main(["ports"]) == 0
    assert capsys.readouterr().out.rstrip().endswith("answers: MyRobotLab's MrlComm, "
                                                     "version 68: profile kind mrlcomm")
    board = protocol_sim._Desk.boards[MEGA]
    assert board.swallowed == 0
    protocol_sim.power_off()
