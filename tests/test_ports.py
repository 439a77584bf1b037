"""A port name that is wrong here gets the same message and the same hint from every
command that names a port: gestplay's, gestc record, gestc upload (whose avrdude
opens the port), the ROS node (tests/test_ros.py). Every command reads ``--port`` and
opens it through one edge (wire/link.py)."""

import sys
from pathlib import Path

import pytest

from inmoov_dsl.cli import gestc, gestplay
from inmoov_dsl.errors import GestError
from inmoov_dsl.profiles.profile import load_profile
from inmoov_dsl.wire import link
from inmoov_dsl.wire.ports import not_found

POSIX_NAMES = pytest.mark.skipif(sys.platform == "win32", reason="COM3 is a port name on "
                                  "Windows")

COMMANDS = [
    ("gestplay", ["peace", "--port", "{}"]),
    ("gestplay", ["dump", "--port", "{}"]),
    ("gestplay", ["send", "--port", "{}", "cancel"]),
    ("gestplay", ["relax", "--port", "{}"]),
    ("gestplay", ["calibrate", "--port", "{}", "--servo", "index"]),
    ("gestc", ["record", "--port", "{}", "-o", "never.gest"]),
    ("gestc", ["upload", "servo_rhand", "--port", "{}"]),
    ("gestc", ["upload", "servo_rhand", "--port", "{}", "--hex", "never.hex"]),
]


@POSIX_NAMES
@pytest.mark.parametrize("name", ["COM3", "ttyUSB0"])
@pytest.mark.parametrize(("tool", "argv"), COMMANDS)
def test_the_same_wrong_name_gets_the_same_hint_everywhere(tool, argv, name, capsys,
                                                           tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    main = {"gestplay": gestplay.main, "gestc": gestc.main}[tool]
    assert main([a.format(name) for a in argv]) == 1
    out, err = capsys.readouterr()
    expected = not_found(name)
    assert expected.hint.startswith(("COM ports are Windows names", "a port is named by its "
                                     "path: /dev/ttyUSB0"))
    assert err == f"gestc: {expected.format()}\n".replace("gestc", tool, 1)
    assert not list(tmp_path.iterdir())  # nothing was written, nothing was built


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="Linux port names")
def test_the_hint_names_the_ports_of_this_system():
    assert not_found("COM3").hint == ("COM ports are Windows names; here an Arduino is "
                                      "/dev/ttyACM0 (Uno, Leonardo) or /dev/ttyUSB0 (Nano, "
                                      "clones)")
    assert not_found("/dev/ttyUSB9").hint == ("'gestplay ports' lists them (and marks the "
                                              "likely Arduinos); sim:// is the virtual board")
    assert not_found("/dev/ttyUSB9", virtual=False).hint == (
        "'gestplay ports' lists them (and marks the likely Arduinos)")


TWO = Path(__file__).parent / "data" / "two.toml"


def test_one_reading_of_port_for_every_command():
    """``--port`` is read once (``link.board_ports``): gestplay's boards by ID, gestc
    upload's by sketch name or ID, with the same words for the same mistake."""
    two = load_profile(str(TWO))
    assert link.board_ports(["COM3"], two, [183]) == {183: "COM3"}
    assert link.board_ports(["181=COM3", "183=COM4"], two) == {181: "COM3", 183: "COM4"}
    assert link.board_ports(["sim://?boot=0"], two) == dict.fromkeys((181, 183), "sim://?boot=0")
    sketches = {181: "servo_a", 183: "servo_b"}
    assert link.board_ports(["servo_b=COM4", "181=COM3"], two, names=sketches) == \
        {183: "COM4", 181: "COM3"}
    for specs, names, message, hint in [  # the ports by ID, and by sketch name
        (["COM3"], None, "profile 'two' has 2 boards: give a port for each",
         "--port 181=PORT --port 183=PORT"),
        (["COM3"], sketches, "profile 'two' has 2 boards: give a port for each",
         "--port servo_a=PORT --port servo_b=PORT"),
        (["181=COM3"], None, "no port for board 183", "add --port 183=PORT"),
        (["181=COM3"], sketches, "no port for servo_b", "add --port servo_b=PORT"),
        (["182=COM3"], None, "--port 182=COM3: profile 'two' has no board 182 (boards: "
         "181, 183)", None),
    ]:
        with pytest.raises(GestError) as info:
            link.board_ports(specs, two, names=names)
        assert (info.value.first.message, info.value.first.hint) == (message, hint)


def test_a_bare_sim_port_is_completed_inside_the_link_edge():
    lhand = load_profile("lhand")
    assert link.parse_ports(["sim://"], lhand) == {183: "sim://lhand?board=183"}
    assert link.parse_ports(["183=COM4"], lhand) == {183: "COM4"}  # any other port as it is
    assert link.every_board("sim://?boot=0") and not link.every_board("sim://rhand")
    port = link.open_board("sim://?boot=0", lhand)  # the virtual board of the left hand
    try:
        assert port.board.core.board_id == 183
    finally:
        port.close()


def test_a_glove_is_listened_to_at_its_baud_and_never_written_to():
    rhand, lhand = load_profile("rhand"), load_profile("lhand")
    listener = link.open_listener("sim://?boot=0", rhand)
    try:
        assert (listener.glove, listener.baud) == (rhand.gloves[0], rhand.gloves[0].baud)
        assert listener.port.timeout == link.LISTEN_POLL
        assert isinstance(listener.read(), bytes)
    finally:
        listener.close()
    listener = link.open_listener("sim://?boot=0", lhand, baud=115200)  # no glove: --baud's
    listener.close()
    assert (listener.glove, listener.baud) == (None, 115200)


def test_no_command_opens_a_port_past_the_link_edge():
    """cli/ and ros/ open ports through wire/link.py: none imports the sim:// handler
    or completes a sim:// URL itself."""
    package = Path(__file__).resolve().parent.parent / "inmoov_dsl"
    files = sorted(p for folder in ("cli", "ros") for p in (package / folder).rglob("*.py"))
    assert {package / "cli" / "hand.py", package / "ros" / "core.py"} <= set(files)
    for path in files:
        text = path.read_text(encoding="utf-8")
        assert "protocol_sim" not in text and "urlhandler" not in text, path
