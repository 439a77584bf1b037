"""A port name that is wrong here gets the same message and the same hint from every
command that names a port: gestplay's, gestc record, gestc upload (whose avrdude
opens the port), the ROS node (tests/test_ros.py)."""

import sys

import pytest

from inmoov_dsl.cli import gestc, gestplay
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
