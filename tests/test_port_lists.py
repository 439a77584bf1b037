"""``--port`` as every command reads it (``wire/link.py``, one reading): lists of
``BOARD=PORT``, each item checked and a mistake named; the I2C bus of a PCA9685; a
virtual board of another kind than the board it is given for (issue 41)."""

import pytest

from inmoov_dsl.boards.pca9685 import bus
from inmoov_dsl.cli import gestplay
from inmoov_dsl.errors import GestError
from inmoov_dsl.profiles.profile import load_profile
from inmoov_dsl.protocol import DEFAULT_BAUD
from inmoov_dsl.wire import link

BOARDS = "(boards: 181 or 'right', 183 or 'left')"


def run(capsys, *argv):
    code = gestplay.main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


@pytest.mark.parametrize(("ports", "message"), [
    (["right=sim://,left="], "--port left=: no port for board 'left'\n"
     "  hint: give one after the '=': left=PORT, a device ('gestplay ports' lists them), "
     "a pyserial URL or sim://"),
    (["right=sim://,lft=sim://"], f"--port lft=sim://: profile 'inmoov' has no board 'lft' "
     f"{BOARDS}\n  hint: did you mean 'left'?"),
    (["right=sim://,,left=sim://"], "--port right=sim://,,left=sim://: an empty item "
     "between two commas\n  hint: --port right=sim://,left=sim://"),
    ([",right=sim://"], "--port ,right=sim://: an empty item before the first comma\n"
     "  hint: --port right=sim://"),
    (["sim://,"], "--port sim://,: an empty item after the last comma\n"
     "  hint: --port sim://"),
    (["right=sim://,right=sim://"], "--port right=sim://: board 'right' is given twice\n"
     "  hint: first as right=sim://; give each board one port"),
    (["right=sim://", "181=loop://"], "--port 181=loop://: board 181 is given twice\n"
     "  hint: first as right=sim://; give each board one port"),
    (["=COM3"], f"--port =COM3: no board before the '='\n  hint: BOARD=PORT, BOARD one of: "
     f"{BOARDS[9:-1]}"),
    (["182=COM3"], f"--port 182=COM3: profile 'inmoov' has no board 182 {BOARDS}"),
])
@pytest.mark.parametrize("tool", ["peace", "dump", "relax"])
def test_each_item_of_a_port_list_is_checked_and_named(capsys, tool, ports, message):
    argv = [tool, "--profile", "inmoov"] + [a for p in ports for a in ("--port", p)]
    code, out, err = run(capsys, *argv)
    assert (code, out, err) == (1, "", f"gestplay: error: {message}\n")


@pytest.mark.parametrize("tool", ["peace", "dump", "relax"])
def test_a_board_given_two_ports_is_an_error(capsys, tool):
    assert run(capsys, tool, "--port", "COM3", "--port", "COM4") == (
        1, "", "gestplay: error: --port COM4: board 181 is given twice\n"
        "  hint: first as COM3; give each board one port\n")


def test_a_name_near_a_board_s_name_is_suggested_in_any_profile(capsys):
    assert run(capsys, "dump", "--port", "right=sim://") == (
        1, "", "gestplay: error: --port right=sim://: profile 'rhand' has no board 'right' "
        "(boards: 181 or 'right hand')\n  hint: did you mean 'right hand'?\n")


def test_a_list_is_items_and_a_port_with_a_comma_is_one():
    inmoov = load_profile("inmoov")
    assert link.board_ports(["right=COM4, left=COM3"], inmoov) == {181: "COM4", 183: "COM3"}
    assert link.board_ports(["COM4,left=COM3"], inmoov, [181]) == {181: "COM4", 183: "COM3"}
    assert link.board_ports(["right hand=COM4"], load_profile("rhand")) == {181: "COM4"}
    assert link.board_ports(["sim://a,b"], load_profile("rhand")) == {181: "sim://a,b"}
    assert link.board_ports(["sim://?boot=0&fresh"], inmoov) == \
        dict.fromkeys((181, 183), "sim://?boot=0&fresh")
    assert link.named_boards(["left=COM3", "sim://"], inmoov) == {183}
    with pytest.raises(GestError, match="has no board 'lft'"):
        link.named_boards(["lft=COM3"], inmoov)


def test_dump_takes_the_ports_as_play_does(capsys):
    code, out, err = run(capsys, "dump", "--profile", "inmoov", "--port",
                         "right=sim://?boot=0&fresh")
    assert (code, err) == (0, "")
    assert out.splitlines()[0] == "board 181 (right): 10 servos"
    assert "board 183" not in out
    code, out, err = run(capsys, "dump", "--profile", "inmoov", "--port",
                         "right=sim://?boot=0,left=sim://?boot=0")
    assert (code, err) == (0, "")
    assert [line for line in out.splitlines() if line.startswith("board")] == \
        ["board 181 (right): 10 servos", "board 183 (left): 18 servos"]


def test_a_one_board_tool_takes_its_board_s_port_from_a_list():
    """send and calibrate open one board: its item of a list, by ID or name."""
    inmoov = load_profile("inmoov")
    port = link.open_board("right=loop://,left=sim://?boot=0", inmoov, inmoov.boards[1])
    try:
        assert port.board.core.board_id == 183
    finally:
        port.close()
    with pytest.raises(GestError) as info:
        link.open_board("left=loop://", inmoov)
    assert (info.value.first.message, info.value.first.hint) == (
        "no port for board 181", "add --port 181=PORT")


def test_a_virtual_board_of_another_kind_is_refused_before_it_is_opened(capsys, monkeypatch):
    def never(*args, **kwargs):
        raise AssertionError("a port was opened")

    monkeypatch.setattr(link, "open_port", never)
    assert run(capsys, "peace", "--profile", "rhand-maestro", "--port", "sim://rhand") == (
        1, "", "gestplay: error: port sim://rhand is the virtual board of profile 'rhand' "
        "(board 181, kind rig): it cannot answer as board 181 of profile 'rhand-maestro' "
        "(kind maestro)\n  hint: a virtual board is of its own profile's kind: for profile "
        "'rhand-maestro' give --port sim:// (the virtual board of what is played) or "
        "sim://rhand-maestro\n")
    code, _, err = run(capsys, "dump", "--profile", "inmoov", "--port",
                       "left=sim://rhand-pca9685")
    assert code == 1
    assert err.endswith("for profile 'inmoov' give --port sim:// (the virtual board of "
                        "what is played) or sim://inmoov?board=183\n")


ADDRESS = ("{} is not a PCA9685's address, which is 0x40..0x77 except 0x70\n  hint: its six "
           "address pins give 0x40..0x7F; the I2C bus reserves 0x78..0x7F, and 0x70 is the "
           "All Call address every PCA9685 answers; with no pin bridged it is 0x40: --port "
           "i2c:1")
PI = ("  hint: on a Raspberry Pi, enable I2C (sudo raspi-config, Interface Options): its "
      "bus is then /dev/i2c-1, --port i2c:1")


@pytest.mark.parametrize(("port", "found", "message"), [
    ("i2c:1@0x99", [], ADDRESS.format("0x99")),
    ("i2c:1@0x70", [], ADDRESS.format("0x70")),
    ("i2c:1@0x3f", [], ADDRESS.format("0x3f")),
    ("i2c:99", [], f"there is no I2C bus 99 (/dev/i2c-99); buses on this machine: none\n{PI}"),
    ("i2c:99@0x41", ["/dev/i2c-1", "/dev/i2c-20"], "there is no I2C bus 99 (/dev/i2c-99); "
     f"buses on this machine: /dev/i2c-1, /dev/i2c-20\n{PI}"),
])
def test_an_i2c_port_names_one_range_and_the_buses_there_are(capsys, monkeypatch, port,
                                                              found, message):
    monkeypatch.setattr(bus, "buses", lambda: found)
    assert run(capsys, "peace", "--profile", "rhand-pca9685", "--port", port) == (
        1, "", f"gestplay: error: cannot open port {port}: {message}\n")


def test_the_buses_are_listed_by_number(monkeypatch):
    monkeypatch.setattr(bus.glob, "glob", lambda pattern: ["/dev/i2c-20", "/dev/i2c-1",
                                                           "/dev/i2c-x"])
    assert bus.buses() == ["/dev/i2c-1", "/dev/i2c-20"]


def test_ports_asks_at_the_protocol_s_default_baud():
    args = gestplay.parser("ports").parse_args(["ports"])
    assert args.baud == DEFAULT_BAUD
