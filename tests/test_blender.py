"""gestplay blender: Blender Servo Animation's live mode (its Web Socket method: a binary
message of 5 bytes a position, as its add-on's ``LiveMode.send_position`` sends them) moves
the virtual board through the drive loop; a move into the body is refused; another web
site, a wrong token and an open address without one are refused. The client is the
``websockets`` library's, not ours."""

import json
import re
import signal
import subprocess
import sys
import time

import pytest

from inmoov_dsl.boards.pulses import widths
from inmoov_dsl.cli.gestc import main as gestc
from inmoov_dsl.profiles.profile import load_profile

ws_client = pytest.importorskip("websockets.sync.client", reason="the test extra")
pytest.importorskip("aiohttp", reason="the serve extra")


class Blender:
    """``gestplay blender`` on sim://, listening on a free port."""

    def __init__(self, *args: str, listen: str = "127.0.0.1:0", path: str = "/"):
        self.proc = subprocess.Popen(
            [sys.executable, "-m", "inmoov_dsl.cli.gestplay", "blender", "--listen",
             listen, "--port", "sim://", *args],
            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        first = self.proc.stderr.readline()
        found = re.search(r"ws://[\d.]+:(\d+)/", first)
        assert found, first + self.proc.stderr.read()
        self.url = f"ws://127.0.0.1:{found.group(1)}{path}"

    def send(self, positions: list[tuple[int, int]], every: float = 0.02) -> None:
        """Each (ID, position) as the add-on sends it, ``every`` s apart."""
        with ws_client.connect(self.url) as ws:
            for servo, us in positions:
                ws.send(bytes([0x3C, servo, us >> 8, us & 0xFF, 0x3E]))
                time.sleep(every)

    def stop(self) -> tuple[int, str]:
        """Ctrl-C: (exit status, what it said on stderr)."""
        self.proc.send_signal(signal.SIGINT)
        _, err = self.proc.communicate(timeout=60)
        return self.proc.returncode, err


def held(profile: str, names: list[str]) -> dict[str, int]:
    dump = subprocess.run([sys.executable, "-m", "inmoov_dsl.cli.gestplay", "dump", "--port",
                           "sim://", "--profile", profile], capture_output=True, text=True,
                          timeout=120)
    assert dump.returncode == 0, dump.stderr
    return {line.split()[0]: int(line.split()[-1]) for line in dump.stdout.splitlines()
            if line.strip() and line.split()[0] in names}


def test_an_animation_sent_live_moves_the_board_to_its_last_pose(tmp_path):
    """peace exported as BSA's JSON, its frames sent as Blender's live mode sends them:
    the virtual board ends in peace's last pose (each width the nearest whole value)."""
    out = tmp_path / "peace.json"
    assert gestc(["export", "peace", "--format", "bsa-json", "-o", str(out)]) == 0
    frames = json.loads(out.read_text())["positions"]
    blender = Blender()
    blender.send([(int(k), v) for frame in frames for k, v in frame.items()], every=0.005)
    time.sleep(1.0)  # the last move's time at the servos' limits
    status, err = blender.stop()
    assert status == 130 and "the hand holds its pose" in err, err
    rhand = load_profile("rhand")
    last: dict[int, int] = {}
    for frame in frames:
        last.update({int(k): v for k, v in frame.items()})
    want = {s.name: widths(s).value(last[s.pin]) for s in rhand.servos}
    got = held("rhand", list(want))
    assert all(abs(got[n] - want[n]) <= 1 for n in want), (got, want)


def test_a_move_into_the_body_is_refused_and_the_arm_stops_short():
    """The whole robot's right arm: the elbow bent towards the chest (test_puppet's) is
    refused, told once, and the arm stays clear."""
    pytest.importorskip("fcl", reason="python-fcl: the collision check")
    inmoov = load_profile("inmoov")
    servo = {s.name: s for s in inmoov.servos}
    rotate, bicep = servo["r_rotate"], servo["r_bicep"]
    blender = Blender("--profile", "inmoov", "--board", "right")
    sweep = [(rotate.pin, int(widths(rotate).us(125)[()]))] + \
        [(bicep.pin, int(widths(bicep).us(round(143 * k / 50))[()])) for k in range(51)]
    blender.send(sweep, every=0.04)
    time.sleep(1.0)
    status, err = blender.stop()
    assert status == 130, err
    assert err.count("error: at ") == 1 and "the right forearm comes near the chest" in err, err
    got = held("inmoov", ["r_rotate", "r_bicep"])
    assert got["r_rotate"] == 125 and 0 < got["r_bicep"] < 143, got


def test_another_site_a_wrong_token_and_an_open_address_without_one_are_refused(tmp_path):
    blender = Blender()
    with pytest.raises(Exception, match="403"):
        ws_client.connect(blender.url, origin="http://evil.example")
    assert blender.stop()[0] == 130
    opened = subprocess.run([sys.executable, "-m", "inmoov_dsl.cli.gestplay", "blender",
                             "--listen", "0.0.0.0:0", "--port", "sim://"],
                            capture_output=True, text=True, timeout=60)
    assert opened.returncode == 1 and "needs a token" in opened.stderr, opened.stderr
    (tmp_path / "token").write_text("a-secret-of-sixteen-or-more\n")
    secret = Blender("--token-file", str(tmp_path / "token"), listen="0.0.0.0:0",
                     path="/?token=a-secret-of-sixteen-or-more")
    with pytest.raises(Exception, match="401"):
        ws_client.connect(secret.url.replace("token=a-", "token=b-"))
    rhand = load_profile("rhand")
    index = rhand.servos[rhand.index("index")]
    secret.send([(index.pin, int(widths(index).us(90)[()]))])  # the add-on's path: accepted
    time.sleep(0.5)
    assert secret.stop()[0] == 130
    assert held("rhand", ["index"]) == {"index": 90}
