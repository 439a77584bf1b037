"""gestsim --web: the page is served from this computer, the hand is drawn in a real
browser (Debian's chromium, headless, software WebGL) and moves when a gesture is
played to the board; without viser, a clear error.

The browser tests skip without chromium or viser, except under CI=true, where a
missing toolchain fails them (as tests/toolchain.py does for the firmware)."""

from __future__ import annotations

import base64
import contextlib
import io
import json
import os
import re
import selectors
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
import urllib.request
from pathlib import Path

import numpy as np
import pytest
from toolchain import require

from inmoov_dsl.cli import gestsim

POSIX = pytest.mark.skipif(not hasattr(os, "openpty"), reason="gestsim needs a pty")
CHROMIUM = ("chromium", "chromium-browser", "google-chrome")
#: what really gives headless chromium WebGL here (SwiftShader through ANGLE; chromium
#: 156 answers --use-gl=swiftshader alone with "WebGL unavailable")
BROWSER_FLAGS = ("--headless", "--no-sandbox", "--use-angle=swiftshader",
                 "--enable-unsafe-swiftshader", "--no-first-run",
                 "--disable-background-networking", "--disable-component-update",
                 "--disable-sync", "--window-size=800,600",
                 # offline: any name but this computer's fails to resolve
                 "--host-resolver-rules=MAP * ~NOTFOUND, EXCLUDE 127.0.0.1")


def need_viser() -> None:
    try:
        import viser  # noqa: F401
        import yourdfpy  # noqa: F401
    except ImportError:
        require("viser and yourdfpy", False, "pip install 'inmoov-dsl[web]'")


def chromium() -> str:
    found = next((path for name in CHROMIUM if (path := shutil.which(name))), None)
    require("chromium", found is not None, "apt-get install chromium")
    return found


class Lines:
    """A process's output pipe, read line by line with a deadline (no buffered reads
    that a select() would not see)."""

    def __init__(self, pipe):
        self.fd, self.buffer, self.seen = pipe.fileno(), b"", []

    def until(self, pattern: str, timeout: float) -> str:
        """Read lines until one matches ``pattern``: its first group (a failure with
        what was read if none does in ``timeout`` seconds or the pipe ends)."""
        deadline = time.monotonic() + timeout
        with selectors.DefaultSelector() as sel:
            sel.register(self.fd, selectors.EVENT_READ)
            while True:
                *lines, self.buffer = self.buffer.split(b"\n")
                for line in lines:
                    self.seen.append(line.decode(errors="replace"))
                    if match := re.search(pattern, self.seen[-1]):
                        return match.group(1)
                left = deadline - time.monotonic()
                chunk = os.read(self.fd, 65536) if left > 0 and sel.select(left) else b""
                if not chunk:
                    pytest.fail(f"no {pattern!r} in {timeout} s; read: {self.seen!r}")
                self.buffer += chunk


@contextlib.contextmanager
def web_board(port: int = 0, *more: str, first: str = r"^(/dev/\S+)$", what: str = "hand"):
    """gestsim --web on ``port`` (``more``: its other options): (process, the first line
    it prints (``first``: the pty's path), the line giving the page's address)."""
    need_viser()
    proc = subprocess.Popen([sys.executable, "-m", "inmoov_dsl.cli.gestsim", "--web",
                             "--http", str(port), "--quiet", "--boot", "0.1", *more],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    try:
        path = Lines(proc.stdout).until(first, 30)
        said = Lines(proc.stderr).until(rf"(the {what} in 3-D.* at .*)", 10)
        yield proc, path, said
    finally:
        if proc.poll() is None:
            proc.kill()
        proc.communicate(timeout=10)


def test_without_viser_gestsim_web_says_how_to_get_it(monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "viser", None)
    assert gestsim.main(["--web", "--http", "0", "--quiet"]) == 1
    assert capsys.readouterr() == ("", (
        "gestsim: error: gestsim --web needs viser and yourdfpy (viser is not installed)\n"
        "  hint: pip install 'inmoov-dsl[web]'\n"))


def test_the_model_is_posed_where_viser_s_own_update_puts_it():
    """``Robot.pose`` sends only the joints that turn, each from its angle: every joint
    frame ends where viser's ``update_cfg`` (the whole model through yourdfpy) puts it,
    the fingers' mimic joints too, pose after pose of the InMoov."""
    need_viser()
    import numpy as np
    import viser

    from inmoov_dsl.profiles.profile import load_profile
    from inmoov_dsl.views.scene import Robot, start_server, stop_server

    server = start_server(viser, 0)
    try:
        profile = load_profile("inmoov")
        robot, rng = Robot(server, profile), np.random.default_rng(7)
        for _ in range(12):
            values = [float(rng.uniform(s.lo, s.hi)) if rng.random() < 0.4 else s.rest
                      for s in profile.servos]
            robot.pose(values)
            sent = [(np.array(f.wxyz), np.array(f.position)) for f in robot.handle._joint_frames]
            robot.handle.update_cfg(robot.configuration(values))
            for (wxyz, at), frame in zip(sent, robot.handle._joint_frames, strict=True):
                same = wxyz if np.dot(wxyz, frame.wxyz) >= 0 else -wxyz  # (q and -q)
                assert np.allclose(same, frame.wxyz, atol=1e-9)
                assert np.allclose(at, frame.position, atol=1e-9)
    finally:
        stop_server(server)


def test_web_with_a_glove_is_an_error(capsys):
    assert gestsim.main(["--web", "--glove", "fist"]) == 1
    assert "--web shows a board's pose" in capsys.readouterr().err


@POSIX
def test_the_page_is_served_from_here_and_sigterm_stops_it():
    with socket.socket() as taken:  # a port another program has
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        busy = taken.getsockname()[1]
        with web_board(busy) as (proc, path, said):
            url = re.fullmatch(rf"the hand in 3-D \(port {busy} is busy\) at "
                               rf"(http://127\.0\.0\.1:\d+/)", said)[1]  # the address last
            with urllib.request.urlopen(url, timeout=10) as page:
                assert page.status == 200
                html = page.read().decode()
            assert "<html" in html and "<script" in html  # viser's client, from its wheel
            assert not re.search(r"<script[^>]+src=[\"']https?:", html)  # none from a CDN
            proc.send_signal(signal.SIGTERM)
            out, err = proc.communicate(timeout=15)
    assert proc.returncode == 0 and b"Traceback" not in err


class Browser:
    """Headless chromium on one page, driven through its DevTools protocol (a
    websocket): navigate, take screenshots, list what the page asked the network for."""

    def __init__(self, exe: str, profile_dir: str):
        from websockets.sync.client import connect  # viser's dependency

        self.proc = subprocess.Popen([exe, *BROWSER_FLAGS, f"--user-data-dir={profile_dir}",
                                      "--remote-debugging-port=0", "about:blank"],
                                     stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                     start_new_session=True)  # its helpers in its group
        try:
            port = Path(profile_dir, "DevToolsActivePort")  # chromium writes it when ready
            deadline = time.monotonic() + 30
            while not (port.exists() and port.read_text().count("\n")):
                assert self.proc.poll() is None, "chromium ended at its start"
                assert time.monotonic() < deadline, "chromium did not start in 30 s"
                time.sleep(0.05)
            endpoint = f"127.0.0.1:{port.read_text().split()[0]}"
            with urllib.request.urlopen(f"http://{endpoint}/json/list", timeout=10) as r:
                page = next(t for t in json.load(r) if t["type"] == "page")
            self.ws = connect(page["webSocketDebuggerUrl"], max_size=None, open_timeout=10)
        except BaseException:
            self.close()
            raise
        self.ids, self.requests = 0, []
        self.call("Network.enable")
        self.call("Page.enable")

    def call(self, method: str, **params) -> dict:
        """One command; its result (events that come meanwhile are noted)."""
        self.ids += 1
        self.ws.send(json.dumps({"id": self.ids, "method": method, "params": params}))
        message = self.receive(lambda m: m.get("id") == self.ids)
        assert "error" not in message, message
        return message["result"]

    def navigate(self, url: str) -> None:
        """Open ``url`` and wait until it has loaded."""
        self.call("Page.navigate", url=url)
        self.receive(lambda m: m.get("method") == "Page.loadEventFired")

    def receive(self, wanted, timeout: float = 60) -> dict:  # software WebGL, busy machine
        """Read messages until ``wanted(message)``, noting the URLs the page asks for."""
        deadline = time.monotonic() + timeout
        while True:
            message = json.loads(self.ws.recv(timeout=max(0.01, deadline - time.monotonic())))
            if message.get("method") == "Network.requestWillBeSent":
                self.requests.append(message["params"]["request"]["url"])
            elif message.get("method") == "Network.webSocketCreated":
                self.requests.append(message["params"]["url"])
            if wanted(message):
                return message

    def screenshot(self):
        """The page as it is drawn now, as a Pillow image."""
        from PIL import Image

        data = self.call("Page.captureScreenshot", format="png")["data"]
        return Image.open(io.BytesIO(base64.b64decode(data))).convert("RGB")

    def close(self) -> None:
        """End chromium and every helper process it started, and wait until all are
        gone: a helper still writing into the profile folder breaks its removal."""
        if getattr(self, "ws", None) is not None:
            self.ws.close()
        with contextlib.suppress(ProcessLookupError):
            os.killpg(self.proc.pid, signal.SIGKILL)
        self.proc.communicate(timeout=10)
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline:
            if not running_in_group(self.proc.pid):
                return
            time.sleep(0.05)
        raise AssertionError("chromium's helper processes did not end in 30 s")


def running_in_group(pgid: int) -> bool:
    """Whether a process of group ``pgid`` still runs (zombies waiting for a parent that
    never reaps them do not count: they write nothing)."""
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue  # it ended while we looked
        if int(fields[2]) == pgid and fields[0] not in "ZX":
            return True
    return False


@pytest.fixture
def browser(tmp_path):
    exe = chromium()
    need_viser()
    with tempfile.TemporaryDirectory(prefix="chromium-") as profile_dir:
        b = Browser(exe, profile_dir)
        try:
            yield b
        finally:
            b.close()


#: s a page may take to draw and settle: software WebGL on a machine kept busy by other
#: programs (idle, a few seconds: docs/simulation.md)
SETTLE = 120


def settled(browser: Browser, ready, timeout: float) -> np.ndarray:
    """The first screenshot that is the same as the one before it (the page has drawn
    all it had to) and for which ``ready`` holds; a failure if none comes in time."""
    deadline, before = time.monotonic() + timeout, None
    while time.monotonic() < deadline:
        shot = np.asarray(browser.screenshot(), dtype=int)
        if before is not None and np.array_equal(shot, before) and ready(shot):
            return shot
        before = shot
        time.sleep(0.2)
    pytest.fail(f"the page did not settle in {timeout} s")


def box(*masks: np.ndarray, margin: int = 10) -> tuple[slice, slice]:
    """The rows and columns around every pixel set in ``masks``."""
    ys, xs = np.nonzero(np.logical_or.reduce(masks))
    return (slice(max(0, ys.min() - margin), ys.max() + margin + 1),
            slice(max(0, xs.min() - margin), xs.max() + margin + 1))


def ivory(shot: np.ndarray) -> np.ndarray:
    """Where the picture has the colour of the hand's printed parts, lit or shaded: a
    light, warm grey (red a little above blue), unlike the white page, the grey floor
    and forearm, or the orange of a notice."""
    r, g, b = shot[..., 0], shot[..., 1], shot[..., 2]
    return (r > 110) & (r - b >= 6) & (r - b <= 45) & (g >= b) & (g <= r)


@POSIX
def test_the_hand_is_drawn_in_a_browser_and_moves_with_the_board(browser, tmp_path):
    with web_board() as (proc, path, said):
        url = re.fullmatch(r"the hand in 3-D at (http://127\.0\.0\.1:\d+/)", said)[1]
        see_the_hand_move(browser, path, url, tmp_path)


def see_the_hand_move(browser: Browser, path: str, url: str, tmp_path: Path) -> None:
    """The page drawn, a fist played to the board, the page drawn again."""
    from PIL import Image

    browser.call("Emulation.setDeviceMetricsOverride", width=800, height=600,
                 deviceScaleFactor=1, mobile=False)
    browser.navigate(url)
    rest = settled(browser, lambda shot: ivory(shot).mean() > 0.03, SETTLE)  # the hand

    player = subprocess.run([sys.executable, "-m", "inmoov_dsl.cli.gestplay", "fist",
                             "--port", path], capture_output=True, text=True, timeout=30)
    assert player.returncode == 0, player.stderr

    def changed(shot: np.ndarray) -> np.ndarray:
        return np.abs(shot - rest).max(axis=2) > 40

    fist = settled(browser, lambda shot: changed(shot).mean() > 0.01, SETTLE)
    for name, shot in (("rest", rest), ("fist", fist)):  # to look at when it fails
        Image.fromarray(shot.astype(np.uint8)).save(tmp_path / f"{name}.png")
    moved = changed(fist)  # where the hand is, at rest or in a fist
    assert moved[box(ivory(rest), ivory(fist))].sum() >= 0.9 * moved.sum()
    assert 0 < ivory(fist).sum() < 0.7 * ivory(rest).sum()  # the fingers are curled
    # all the page asked for came from gestsim: none from a CDN
    here = url.rstrip("/").split("//")[1]
    assert browser.requests
    assert all(u.startswith(("data:", "blob:")) or u.split("//")[1].startswith(here)
               for u in browser.requests), browser.requests


@POSIX
def test_one_page_shows_every_board_of_the_robot(browser, tmp_path):
    """``gestsim --web --profile inmoov``: one page for both Megas; both elbows bent
    (the right arm on board 181, the left on 183), the page changes where each arm is,
    on both sides of the robot, and the head stays as it was."""
    from PIL import Image

    source = tmp_path / "elbows.gest"
    source.write_text("robot inmoov\n\nelbows:\n    r_bicep 90, l_bicep 90 over 1.5s\n")
    with web_board(0, "--profile", "inmoov", first=r"^(181=/dev/\S+,183=/dev/\S+)$",
                   what="robot") as (proc, ports, said):
        url = re.fullmatch(r"the robot in 3-D at (http://127\.0\.0\.1:\d+/)", said)[1]
        browser.call("Emulation.setDeviceMetricsOverride", width=800, height=600,
                     deviceScaleFactor=1, mobile=False)
        browser.navigate(url)
        rest = settled(browser, lambda shot: ivory(shot).mean() > 0.03, SETTLE)
        player = subprocess.run([sys.executable, "-m", "inmoov_dsl.cli.gestplay",
                                 str(source), "--port", ports], capture_output=True,
                                text=True, timeout=60)
        assert player.returncode == 0, player.stderr

        def changed(shot: np.ndarray) -> np.ndarray:
            return np.abs(shot - rest).max(axis=2) > 40

        bent = settled(browser, lambda shot: changed(shot).mean() > 0.005, SETTLE)
    for name, shot in (("rest", rest), ("bent", bent)):  # to look at when it fails
        Image.fromarray(shot.astype(np.uint8)).save(tmp_path / f"{name}.png")
    moved = changed(bent)
    rows, cols = box(ivory(rest))  # the robot, at rest
    middle = (cols.start + cols.stop) // 2
    assert moved[:, :middle].sum() > 200 and moved[:, middle:].sum() > 200
    top = rows.start + (rows.stop - rows.start) // 5  # the head, seen from the front
    assert not moved[:top].any()
