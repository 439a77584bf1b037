"""Board replies that are not a board's answer (issue 42's seeded fuzzer of replies):
an I2C address the port pattern takes, a port that echoes what it is sent, a DUMP
reply from no board's ID; and what each kind of board says in its own words when it
answers late or is stopped."""

from __future__ import annotations

import random
from pathlib import Path

import pytest

from inmoov_dsl import load_profile
from inmoov_dsl.boards import controller
from inmoov_dsl.boards.pca9685 import bus
from inmoov_dsl.cli import gestplay, hand
from inmoov_dsl.cli.common import Exit
from inmoov_dsl.decode import Replies, parse_dump
from inmoov_dsl.errors import GestError
from inmoov_dsl.profiles.profile import parse_profile
from inmoov_dsl.protocol import CANCEL_PENDING, FIRST_BOARD_ID, Signal, reply
from inmoov_dsl.wire.player import Link
from inmoov_dsl.wire.ports import open_port

SEED = 42
PROFILES = Path(__file__).resolve().parent.parent / "gestures" / "profiles"


def run(capsys, *argv):
    code = gestplay.main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def pololu(tmp_path):
    """rhand-maestro on the Pololu protocol (device 12): its questions start 0xAA 12."""
    text = (PROFILES / "rhand-maestro.toml").read_text()
    path = tmp_path / "pololu.toml"
    path.write_text(text.replace('model = "mini12"', 'model = "mini12"\ndevice = 12')
                    .replace('name = "rhand-maestro"', 'name = "pololu"'))
    return str(path)


# -- 1. an I2C address with a leading zero --------------------------------------------
@pytest.mark.parametrize("command", [["wave"], ["play", "wave"], ["dump"]])
@pytest.mark.parametrize(("address", "hint"), [
    ("010", "write it in hex with 0x, as i2cdetect shows addresses; a PCA9685's address "
     "is 0x40..0x77 except 0x70"),
    ("099", "write it in hex with 0x, as i2cdetect shows addresses: i2c:1@0x63 for "
     "decimal 99"),
    ("064", "write it in hex with 0x, as i2cdetect shows addresses: i2c:1@0x64 or "
     "i2c:1@0x40 for decimal 64"),
])
def test_an_i2c_address_with_a_leading_zero_is_an_error_with_its_readings(
        capsys, command, address, hint):
    port = f"i2c:1@{address}"
    assert run(capsys, *command, "--profile", "rhand-pca9685", "--port", port) == (
        1, "", f"gestplay: error: cannot open port {port}: the address {address} has a "
        f"leading zero, which some tools read as octal, others as decimal\n  hint: {hint}\n")


def test_a_decimal_i2c_address_is_decimal_and_says_so_when_out_of_range(capsys,
                                                                        monkeypatch):
    monkeypatch.setattr(bus, "buses", lambda: [])
    code, _, err = run(capsys, "dump", "--profile", "rhand-pca9685", "--port", "i2c:1@40")
    assert code == 1 and err.startswith(
        "gestplay: error: cannot open port i2c:1@40: 40 (decimal: 0x28) is not a PCA9685's "
        "address, which is 0x40..0x77 except 0x70\n")
    code, _, err = run(capsys, "dump", "--profile", "rhand-pca9685", "--port", "i2c:1@65")
    assert code == 1 and "there is no I2C bus 1" in err  # 65 = 0x41: the address is good


def test_every_address_the_port_pattern_takes_is_a_number_or_a_message(monkeypatch):
    monkeypatch.setattr(bus.os.path, "exists", lambda path: False)  # no bus: stop there
    rng = random.Random(SEED)
    texts = [f(a) for a in range(0x100) for f in (str, hex, "0{}".format, "0x0{:x}".format)]
    texts += ["".join(rng.choice("0123456789") for _ in range(rng.randint(1, 6)))
              for _ in range(200)]
    for text in texts:
        with pytest.raises(GestError) as caught:
            bus.open_bus(f"i2c:1@{text}")
        said = caught.value.first.message
        good = not text.startswith("0") or text == "0" or text.startswith("0x")
        if good and bus.usable(int(text, 0)):
            assert "there is no I2C bus 1" in said, text
        else:
            assert "address" in said, text


# -- 2. a port that echoes what it is sent ----------------------------------------------
@pytest.mark.parametrize("profile", ["rhand", "rhand-maestro", "pololu", "rhand-mrlcomm"])
def test_a_loopback_is_no_board_for_any_kind(capsys, virtual_clock, tmp_path, profile):
    name = pololu(tmp_path) if profile == "pololu" else profile
    code, out, err = run(capsys, "dump", "--profile", name, "--port", "loop://")
    assert (code, out) == (1, "")
    said = {"rhand": "DUMP reply", "rhand-mrlcomm": "board info (getBoardInfo)"}.get(
        profile, "answer to Get Position")  # each kind's own word
    assert err.startswith(f"gestplay: error: no {said} from loop://\n")
    code, out, err = run(capsys, "wave", "--profile", name, "--port", "loop://")
    assert (code, out) == (1, "")
    assert err.startswith("gestplay: error: no board answered on loop:// (board 181")
    assert "warning" not in err


@pytest.mark.parametrize("profile", ["rhand", "rhand-maestro", "pololu", "rhand-mrlcomm"])
def test_no_kind_takes_its_own_questions_for_an_answer(tmp_path, profile):
    p = load_profile(pololu(tmp_path) if profile == "pololu" else profile)
    c = controller(p, p.boards[0])
    assert not c.ready(c.probe() * 3)
    reader = c.pose_reader()
    assert reader.feed(c.ask_pose()) is None
    assert reader.feed(c.ask_pose()) is None  # asked again, echoed again


def test_a_maestro_s_answers_are_still_read():
    p = load_profile("rhand-maestro")
    c = controller(p, p.boards[0])
    assert c.ready(b"\x00\x00") and c.ready(b"\x10\x00") and c.ready(b"\xff\x01")
    assert not c.ready(b"\x00\x02") and not c.ready(b"\xa1")
    us = (0, 544, 2400, 1500, 0, 0)
    pose = c.pose_reader().feed(b"".join((u * 4).to_bytes(2, "little") for u in us))
    assert pose == {s.id: c.widths[j].value(u) if u else s.rest
                    for j, (s, u) in enumerate(zip(c.servos, us, strict=True))}


# -- 3. a board that answered its pose but not as ready: each kind's words --------------
@pytest.mark.parametrize(("profile", "words"), [
    ("rhand", "sent no WAIT, but answered DUMP"),
    ("rhand-maestro", "did not answer Get Errors, but answered Get Position"),
    ("rhand-mrlcomm", "was not ready in time, but then told its pose"),
])
def test_a_board_that_answers_late_is_told_in_its_kind_s_words(capsys, virtual_clock,
                                                                monkeypatch, profile, words):
    monkeypatch.setattr(hand, "wait_ready", lambda *args, **kwargs: False)  # not in time
    p = load_profile(profile)
    board = p.boards[0]
    kind = controller(p, board)
    port = open_port(f"sim://{profile}?fresh&boot=0", board.baud)
    link = Link(board.id, port, "late", None if kind.ours else kind)
    try:
        assert hand.reach(link, p, False, hand.REST_POSE) is not None
    finally:
        port.close()
    assert capsys.readouterr().err == f"gestplay: warning: board 181 on late {words}\n"


# -- 4. a DUMP reply from no board's ID ---------------------------------------------------
def test_a_reply_from_an_id_below_181_is_no_answer():
    six = [(i, 90) for i in range(6)]
    for board in (0, 100, FIRST_BOARD_ID - 1):
        assert Replies().feed(reply(board, six)) is None
        assert parse_dump(bytes([Signal.WAIT]) + reply(board, six)) is None
    assert Replies().feed(reply(FIRST_BOARD_ID, six)) == (181, dict(six))
    # one from no board, then one from a board: the board's
    assert parse_dump(reply(180, six) + reply(183, six[:2])) == (183, dict(six[:2]))


def test_random_replies_name_only_board_ids():
    rng = random.Random(SEED)
    for _ in range(2000):
        data = bytes(rng.choice([Signal.START, Signal.END, 0, 1, 90, 180, 181, 200, 254,
                                 rng.randrange(256)]) for _ in range(rng.randint(0, 24)))
        found = Replies().feed(data)
        assert found is None or found[0] >= FIRST_BOARD_ID, data


class Board180:
    """A serial device that answers WAIT to CANCEL and DUMP as board 180."""

    def __init__(self):
        self.out = bytearray()

    def write(self, data):
        if CANCEL_PENDING in data:
            self.out.append(Signal.WAIT)
        if Signal.DUMP in data:
            self.out += reply(180, [(i, 90) for i in range(6)])
        return len(data)

    def read(self, size=1):
        data, self.out = bytes(self.out[:size]), self.out[size:]
        return data

    def close(self):
        pass


def test_ports_does_not_take_board_180_for_a_board(capsys, monkeypatch, virtual_clock):
    from serial.tools import list_ports, list_ports_common

    from inmoov_dsl.wire import identify

    info = list_ports_common.ListPortInfo("/dev/ttyACM7", skip_link_detection=True)
    info.description, info.vid, info.pid = "Arduino Uno", 0x2341, 0x0043
    monkeypatch.setattr(list_ports, "comports", lambda: [info])
    monkeypatch.setattr(identify, "open_port", lambda device, baud: Board180())
    assert gestplay.main(["ports"]) == 0
    out = capsys.readouterr().out
    assert "board 180" not in out
    assert "a board that sends WAIT at 9600 baud but did not answer DUMP" in out


# -- 5. Ctrl-C: what each kind was sent -------------------------------------------------
def mixed(tmp_path):
    """inmoov with its left Mega on MrlComm (board 183), its right one ours (181)."""
    text = (PROFILES / "inmoov.toml").read_text()
    left = text.index('name = "left"')
    path = tmp_path / "mixed.toml"
    path.write_text(text[:left] + text[left:].replace('arduino = "mega"', 'kind = "mrlcomm"',
                                                      1).replace('name = "inmoov"', ""))
    return parse_profile(path.read_text(), str(path))


@pytest.mark.parametrize(("profile", "ports", "said"), [
    ("rhand", ["sim://?fresh&boot=0"], "CANCEL sent, the hand holds its pose"),
    ("rhand-maestro", ["sim://?fresh"], "nothing more sent, each servo holds its last "
     "target"),
    ("rhand-mrlcomm", ["sim://?fresh"], "nothing more sent, each servo holds its last "
     "target"),
    ("rhand-pca9685", ["sim://?fresh"], "nothing more sent, each servo holds its last "
     "target"),
    ("mixed", ["right=sim://?fresh", "left=sim://?fresh"], "CANCEL sent to board 181, "
     "nothing more sent to board 183; each servo holds its last position"),
])
def test_ctrl_c_says_what_each_kind_was_sent(capsys, virtual_clock, tmp_path, profile,
                                             ports, said):
    p = mixed(tmp_path) if profile == "mixed" else load_profile(profile)
    with pytest.raises(Exit) as left, hand.opened("gestplay", p, ports):
        capsys.readouterr()
        raise KeyboardInterrupt
    assert left.value.status == 130
    assert capsys.readouterr().err == f"\ngestplay: interrupted: {said}\n"
