import subprocess
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).parent))

from lsp_client import client  # noqa: E402, F401 (pytest-lsp's client on gestc lsp, as VS Code starts it)

from inmoov_dsl import load_profile  # noqa: E402
from inmoov_dsl.profiles.profile import parse_profile  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent


def library_profile(path: Path) -> str:
    """The profile a library file's gestures play on: its robot line's, else rhand."""
    from inmoov_dsl.compiling.robot import DEFAULT
    from inmoov_dsl.language.parse import parse

    line = parse(path.read_text(encoding="utf-8"), str(path)).robot
    return line.name if line is not None else DEFAULT


#: the library's files of whole-robot gestures (their robot line names another profile)
WHOLE_ROBOT = tuple(p.name for p in sorted((ROOT / "gestures").glob("*.gest"))
                    if library_profile(p) != "rhand")


def early(profile, baud: int) -> float:
    """Degrees the fastest servo's plan moves in a byte-time: a pair arrives up to a
    byte-time before its slot (on the link's byte grid), with the value of its slot."""
    from inmoov_dsl import protocol

    return max(s.max_velocity for s in profile.servos) * protocol.byte_time(baud) + 1e-9


class VirtualClock:
    """A clock that moves only when slept on: logic runs on it the same on a loaded
    machine as on an idle one."""

    def __init__(self, t: float = 100.0):
        self.t = t

    def now(self) -> float:
        return self.t

    def sleep(self, seconds: float) -> None:
        self.t += max(seconds, 1e-6)


@pytest.fixture
def virtual_clock(monkeypatch):
    """Every tool's clock (``inmoov_dsl.clock``: the player, the drive loop, sim://) on a
    VirtualClock for this test."""
    from inmoov_dsl import clock

    virtual = VirtualClock()
    monkeypatch.setattr(clock, "now", virtual.now)
    monkeypatch.setattr(clock, "sleep", virtual.sleep)
    return virtual


@pytest.fixture(autouse=True)
def _fresh_virtual_boards(tmp_path_factory, monkeypatch):
    """Each test finds new virtual boards on the desk (sim:// keeps a board's state for
    the life of the process, and its pose in the user's state directory, as a real board
    keeps it between programs): each test has a state directory of its own, which the
    programs it starts inherit."""
    from inmoov_dsl.resources import STATE_ENV
    from inmoov_dsl.wire.urlhandler.protocol_sim import power_off

    monkeypatch.setenv(STATE_ENV, str(tmp_path_factory.mktemp("state")))
    power_off()


@pytest.fixture(scope="session")
def rhand():
    return load_profile("rhand")


def servo_toml(name, sid, v=400.0, a=8000.0, j=160000.0, lo=0, hi=180):
    return (f"[servo.{name}]\nid = {sid}\nrange = [{lo}, {hi}]\nrest = {lo}\n"
            f"max_velocity = {v}\nmax_acceleration = {a}\nmax_jerk = {j}\n")


def board_toml(bid, names, baud=9600):
    quoted = ", ".join(f'"{n}"' for n in names)
    return f"[[board]]\nid = {bid}\nbaud = {baud}\nservos = [{quoted}]\n"


def make_profile(boards, baud=9600, name="test", limits=None):
    """A profile from {board id: [servo names]}; servo IDs are numbered in order."""
    text = f'name = "{name}"\n'
    sid = 0
    servos = ""
    for bid, names in boards.items():
        text += board_toml(bid, names, baud)
        for n in names:
            servos += servo_toml(n, sid, **(limits or {}))
            sid += 1
    return parse_profile(text + servos, f"{name}.toml")


@pytest.fixture(scope="session")
def two_boards():
    """A left and a right hand on two boards (the compiler's one-stream-per-board case)."""
    return make_profile({181: ["r_thumb", "r_index", "r_middle"],
                         183: ["l_thumb", "l_index", "l_middle"]}, name="two")


@pytest.fixture
def gestsim(tmp_path):
    """gestsim serving the right hand on a pty, logging every byte it receives:
    (process, the pty's path, the log)."""
    log = tmp_path / "received.log"
    proc = subprocess.Popen([sys.executable, "-m", "inmoov_dsl.cli.gestsim", "--quiet",
                             "--boot", "0.2", "--log", str(log)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    path = proc.stdout.readline().strip()
    assert path.startswith("/dev/"), proc.stderr.read()
    yield proc, path, log
    proc.kill()
    proc.wait()
