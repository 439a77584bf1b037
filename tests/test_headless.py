"""The commands docs/simulation.md and docs/service.md give to look at the pages from a
headless machine, run exactly as the docs write them (only the address replaced) against
a fresh ``gestsim --web`` and a fresh ``gestplay serve``: what they show is what a person
would see, the hand drawn, the service's page connected with its buttons and its pose.

Skips without chromium, viser or aiohttp, except under CI=true, where a missing tool
fails (tests/toolchain.py)."""

from __future__ import annotations

import contextlib
import os
import re
import signal
import subprocess
import sys
from collections import Counter
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pytest
from test_web import POSIX, Lines, ivory, need_viser, web_board
from toolchain import require

from inmoov_dsl import load_profile

DOCS = Path(__file__).resolve().parent.parent / "docs"
#: the address each doc's commands name (the page's default port), replaced by the
#: address of the page the test starts
SIMULATION = (DOCS / "simulation.md", "http://127.0.0.1:8080/")
SERVICE = (DOCS / "service.md", "http://127.0.0.1:8180/")
#: s a command may take: 5 to 25 on two busy cores; a hang fails rather than waits
RUN = 240


def commands(doc: Path, url: str) -> list[str]:
    """The chromium command lines of ``doc``'s code blocks (indented four spaces), each
    naming ``url`` once."""
    lines = [line[4:] for line in doc.read_text(encoding="utf-8").splitlines()
             if line.startswith("    chromium ")]
    assert lines, f"{doc.name} gives no chromium command"
    for line in lines:
        assert line.count(url) == 1, f"{doc.name}: {line!r} does not name {url} once"
    return lines


def flags(line: str) -> list[str]:
    """A command's flags but the ones that say what to take and how big."""
    return [w for w in line.split()[1:-1]
            if not w.startswith(("--screenshot", "--dump-dom", "--window-size"))]


def need_chromium() -> None:
    import shutil

    require("chromium", shutil.which("chromium") is not None, "apt-get install chromium")


def run(line: str, url: str, where: Path) -> str:
    """Run a doc's command line as a shell would, in ``where``, with ``url`` for the
    doc's address and a profile of its own (not the user's): its standard output."""
    env = {**os.environ, "XDG_CONFIG_HOME": str(where / "config"),
           "XDG_CACHE_HOME": str(where / "cache")}
    proc = subprocess.Popen(["sh", "-c", line], cwd=where, env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, start_new_session=True)
    try:
        out, err = proc.communicate(timeout=RUN)
    except subprocess.TimeoutExpired:
        pytest.fail(f"{line!r} did not end in {RUN} s")
    finally:
        if proc.poll() is None:  # chromium and its helpers: their own process group
            os.killpg(proc.pid, signal.SIGKILL)
            proc.communicate(timeout=30)
    assert proc.returncode == 0, err.decode(errors="replace")[-3000:]
    return out.decode()


def picture(line: str, where: Path) -> np.ndarray:
    """The picture a ``--screenshot=FILE`` command wrote, as an array of RGB pixels."""
    from PIL import Image

    png = where / re.search(r"--screenshot=(\S+)", line)[1]
    assert png.is_file(), f"no {png.name}"
    with Image.open(png) as image:
        return np.asarray(image.convert("RGB"), dtype=int)


#: times a documented screenshot is taken before a blank one fails the test (as a user
#: on a busy machine takes it again: docs/simulation.md)
TRIES = 3


def colours(shot: np.ndarray) -> int:
    return len(np.unique(shot.reshape(-1, 3), axis=0))


@POSIX
def test_the_simulations_command_shows_the_hand(tmp_path):
    need_chromium()
    doc, placeholder = SIMULATION
    (line,) = commands(doc, placeholder)
    assert "--screenshot=" in line
    with web_board() as (proc, path, said):
        url = re.fullmatch(r"the hand in 3-D at (http://127\.0\.0\.1:\d+/)", said)[1]
        for _ in range(TRIES):  # a busy machine may not draw it within the page's budget
            run(line.replace(placeholder, url), url, tmp_path)
            if colours(shot := picture(line, tmp_path)) > 200:
                break
        assert proc.poll() is None, "gestsim ended while the page was taken"
    width, height = map(int, re.search(r"--window-size=(\d+),(\d+)", line).groups())
    assert shot.shape == (height, width, 3)
    assert colours(shot) > 200  # drawn, not a blank page
    assert ivory(shot).mean() > 0.03, "the hand is not in the picture"  # about 0.1


@contextlib.contextmanager
def service(where: Path):
    """``gestplay serve --port sim:// --http 127.0.0.1:0`` (a virtual board with a
    memory of its own, at rest): the page's address."""
    try:
        import aiohttp  # noqa: F401
    except ImportError:
        require("aiohttp", False, "pip install 'inmoov-dsl[serve]'")
    env = {**os.environ, "INMOOV_DSL_STATE": str(where / "state")}
    proc = subprocess.Popen([sys.executable, "-m", "inmoov_dsl.cli.gestplay", "serve",
                             "--port", "sim://", "--http", "127.0.0.1:0"], env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    try:
        yield Lines(proc.stderr).until(r"(http://127\.0\.0\.1:\d+/) drives", 60)
        assert proc.poll() is None, "the service ended while its page was taken"
    finally:
        if proc.poll() is None:
            proc.kill()
        proc.communicate(timeout=10)


class Page(HTMLParser):
    """What a dumped page shows: its buttons (label, gesture), the status line, the pose
    bars' servo names, and its visible text."""

    def __init__(self, html: str):
        super().__init__()
        self.buttons: list[tuple[str, str | None]] = []
        self.bars: list[str] = []
        self.text: list[str] = []
        self.status = None
        self._open: list[tuple[str, dict]] = []
        self.feed(html)

    def handle_starttag(self, tag, attrs):
        if tag not in ("input", "meta", "link", "br", "img"):
            self._open.append((tag, dict(attrs)))
            if tag == "button":
                self.buttons.append(("", dict(attrs).get("data-gesture")))

    def handle_endtag(self, tag):
        while self._open and self._open.pop()[0] != tag:
            pass

    def handle_data(self, data):
        tags = [t for t, _ in self._open]
        if "script" in tags or "style" in tags:
            return
        self.text.append(data)
        if "button" in tags:
            label, gesture = self.buttons[-1]
            self.buttons[-1] = (label + data.strip(), gesture)
        if self._open and self._open[-1][1].get("id") == "status":
            self.status = data.strip()
        if len(self._open) >= 2 and self._open[-2][1].get("class") == "bar" and \
                self._open[-1][0] == "span":
            self.bars.append(data.strip())


@POSIX
def test_the_services_commands_show_it_connected_with_its_buttons_and_pose(tmp_path):
    need_chromium()
    need_viser()  # the page shows the hand in 3-D too (viser's page in a frame)
    doc, placeholder = SERVICE
    lines = commands(doc, placeholder)
    (shoot,) = [line for line in lines if "--screenshot=" in line]
    (dump,) = [line for line in lines if "--dump-dom" in line]
    (simulation,) = commands(*SIMULATION)
    assert flags(shoot) == flags(dump) == flags(simulation)  # "the same flags"
    with service(tmp_path) as url:
        html = run(dump.replace(placeholder, url), url, tmp_path)
        for _ in range(8):  # the 3-D frame may not be drawn yet (a busy machine is slow to
            # serve it): taken again, as the doc says
            run(shoot.replace(placeholder, url), url, tmp_path)
            if ivory(picture(shoot, tmp_path)).mean() > 0.005:
                break

    page = Page(html)
    assert page.status == "connected"
    assert "connecting" not in " ".join(page.text)
    gestures = [label for label, gesture in page.buttons if gesture is not None]
    assert all(label == gesture for label, gesture in page.buttons if gesture is not None)
    assert {"wave", "fist", "peace", "loose"} <= set(gestures) and len(gestures) > 20
    labels = Counter(label for label, _ in page.buttons)
    assert not [label for label, n in labels.items() if n > 1], labels  # one relax
    assert {"play", "stop", "relax"} <= set(labels)
    assert page.bars == [s.name for s in load_profile("rhand").servos]  # the pose

    shot = picture(shoot, tmp_path)
    width, height = map(int, re.search(r"--window-size=(\d+),(\d+)", shoot).groups())
    assert shot.shape == (height, width, 3)
    assert colours(shot) > 200
    red = np.abs(shot - (0xCC, 0x33, 0x33)).max(axis=2) < 20  # the stop button
    assert red.sum() > 500, "no stop button in the picture"
    assert ivory(shot).mean() > 0.005, "no hand in the 3-D view"  # about 0.02
