"""gestplay serve, driven by clients that no part of the project wrote: curl, Python's
http.client and the websockets library, against a running service on sim:// and on a
gestsim board; the board itself (gestplay dump) says whether the service told the truth."""

import contextlib
import http.client
import json
import os
import shutil
import signal
import subprocess
import sys
import time

import numpy as np
import pytest
from sound_server import sound_server  # noqa: F401 (a fixture)
from stopping import received, wait_for
from test_web import Lines
from toolchain import require

from inmoov_dsl import access as guard
from inmoov_dsl.service import core

PEACE = {"wrist": 0, "thumb": 180, "index": 0, "middle": 0, "ring": 180, "pinky": 180}


def need_service_libraries() -> None:
    try:
        import aiohttp  # noqa: F401
        import websockets  # noqa: F401
    except ImportError:
        require("aiohttp and websockets", False, "pip install 'inmoov-dsl[serve]' websockets")


class Service:
    """A running ``gestplay serve``: its address, and a way to talk to it."""

    def __init__(self, proc: subprocess.Popen, host: str, port: int):
        self.proc, self.host, self.port = proc, host, port
        self.url = f"http://{host}:{port}"

    def call(self, method: str, path: str, body=None, headers=None):
        """(status, JSON answer, headers) through http.client."""
        conn = http.client.HTTPConnection(self.host, self.port, timeout=30)
        data = body if isinstance(body, bytes) or body is None else json.dumps(body).encode()
        sent = {"Content-Type": "application/json"} if data is not None else {}
        conn.request(method, path, body=data, headers={**sent, **(headers or {})})
        answer = conn.getresponse()
        text = answer.read()
        conn.close()
        return answer.status, json.loads(text) if text[:1] in b"[{" else text, answer.headers

    def curl(self, *args: str) -> tuple[int, dict]:
        """(HTTP status, JSON answer) through curl."""
        done = subprocess.run(["curl", "-sS", "-w", "\n%{http_code}", *args], text=True,
                              capture_output=True, timeout=30)
        assert done.returncode == 0, done.stderr
        body, _, status = done.stdout.rpartition("\n")
        return int(status), json.loads(body)

    def events(self, headers=None, path="/api/events"):
        """A websockets client on the events."""
        from websockets.sync.client import connect

        return connect(f"ws://{self.host}:{self.port}{path}", additional_headers=headers,
                       open_timeout=10)

    def stop(self, sig=signal.SIGTERM) -> tuple[int, str]:
        self.proc.send_signal(sig)
        _, err = self.proc.communicate(timeout=20)
        return self.proc.returncode, err.decode()


@contextlib.contextmanager
def serving(*args: str, port: str = "sim://?boot=0"):
    """``gestplay serve --port PORT ARGS`` on a free port of 127.0.0.1."""
    need_service_libraries()
    if not any(a.startswith("--http") for a in args):
        args = (*args, "--http", "127.0.0.1:0")
    proc = subprocess.Popen([sys.executable, "-m", "inmoov_dsl.cli.gestplay", "serve",
                             "--port", port, *args],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    try:
        url = Lines(proc.stderr).until(r"(http://\S+)/ drives", 60)
        host, _, number = url[len("http://"):].rpartition(":")
        yield Service(proc, host.strip("[]"), int(number))
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate(timeout=10)


def until(ws, event: str, request_id: str | None = None, timeout: float = 30) -> list[dict]:
    """Events read until ``event`` (of ``request_id``) comes: all of them, in order."""
    seen = []
    deadline = time.monotonic() + timeout
    while True:
        seen.append(json.loads(ws.recv(timeout=max(0.01, deadline - time.monotonic()))))
        if seen[-1]["event"] == event and request_id in (None, seen[-1].get("id")):
            return seen


def moved(ws, servo: str, timeout: float = 30) -> list[dict]:
    """Events read until a pose shows ``servo`` on its way (a request under way: what a
    test waits for, rather than a time that a busy machine may not keep)."""
    seen = []
    deadline = time.monotonic() + timeout
    while not (seen and seen[-1]["event"] == "pose" and 0 < seen[-1]["servos"][servo] < 180):
        seen.append(json.loads(ws.recv(timeout=max(0.01, deadline - time.monotonic()))))
    return seen


def still(service, timeout: float = 30, headers=None) -> dict:
    """The pose, once no request plays and no servo moves (polled: a stop's last bytes
    reach the board in their time)."""
    deadline = time.monotonic() + timeout
    while True:
        status, pose, _ = service.call("GET", "/api/pose", headers=headers)
        assert status == 200
        if pose["playing"] is None and not any(s["moving"] for s in pose["servos"].values()):
            return pose
        assert time.monotonic() < deadline, "the hand never came to rest"
        time.sleep(0.05)


def gone(ws) -> int:
    """The close code of an events socket, once what it was told before is read."""
    from websockets.exceptions import ConnectionClosed

    try:
        while True:
            ws.recv(timeout=10)
    except ConnectionClosed as closed:
        return closed.rcvd.code if closed.rcvd else 1006


def values(pose: dict) -> dict:
    return {name: s["value"] for name, s in pose["servos"].items()}


def dump(port: str, tries: int = 3) -> dict:
    """What the board says it holds (``gestplay dump``). gestplay waits a second for the
    answer, which a board on a desk gives in milliseconds; simavr on a machine too busy
    to keep its board in real time may give it later: asked again then (the board keeps
    its pose across the reset an open makes)."""
    for _ in range(tries):
        done = subprocess.run([sys.executable, "-m", "inmoov_dsl.cli.gestplay", "dump",
                               "--port", port], capture_output=True, text=True, timeout=60)
        if "no DUMP reply" not in done.stderr:
            break
    assert done.returncode == 0, done.stderr
    return {w[0]: int(w[-1]) for w in map(str.split, done.stdout.splitlines()[1:])}


# -- with curl and the board itself -------------------------------------------------------
def test_curl_plays_a_gesture_and_the_board_holds_what_the_service_says():
    if shutil.which("curl") is None:
        require("curl", False, "apt-get install curl")
    with serving() as service, service.events() as ws:
        status, answer = service.curl("--json", '{"gesture": "peace"}', f"{service.url}"
                                      "/api/play")
        assert status == 202
        told = until(ws, "done", answer["id"])
        assert [e["event"] for e in told if e["event"] != "pose"] == ["started", "done"]
        assert told[-2]["event"] == "pose" and told[-2]["servos"] == PEACE
        status, pose = service.curl(f"{service.url}/api/pose")
        assert status == 200 and values(pose) == PEACE and pose["playing"] is None
        code, err = service.stop()
        gone(ws)
    assert code == 143 and "CANCEL sent" in err and "Traceback" not in err
    assert dump("sim://") == PEACE  # the board (its memory) holds what the service said


def test_the_library_and_the_openapi_document_are_served():
    with serving() as service:
        status, gestures, _ = service.call("GET", "/api/gestures")
        assert status == 200
        peace = next(g for g in gestures if g["name"] == "peace")
        assert peace == {"name": "peace", "file": "peace.gest", "profile": "rhand",
                         "duration": 0.7, "description": peace["description"]}
        assert "hello" not in {g["name"] for g in gestures}  # the whole robot's: not here
        status, doc, _ = service.call("GET", "/api/openapi.json")
        assert status == 200 and doc["openapi"].startswith("3.")
        assert set(doc["paths"]) == {"/api/gestures", "/api/play", "/api/stop",
                                     "/api/relax", "/api/pose", "/api/events", "/api/view"}
        play = doc["components"]["schemas"]["Play"]
        assert set(play["properties"]) == set(core.PLAY_FIELDS)


# -- requests that are not right ----------------------------------------------------------
ONE_OF = "give one of 'gesture', 'steps' and 'text'"
BAD = [
    (b"not json", 400, "the body is not JSON"),
    (b"[1, 2]", 400, "the body is not a JSON object"),
    (b'{"gesture": "peace", "speed": 2}', 400, "unknown field 'speed'"),
    (b'{"gesture": "peace", "steps": "index 9"}', 400, ONE_OF),
    (b"{}", 400, ONE_OF),
    (b'{"text": "w: index 9", "steps": "index 9"}', 400, ONE_OF),
    (b'{"text": 7}', 400, "'text' must be a string"),
    (b'{"gesture": 7}', 400, "'gesture' must be a string"),
    (b'{"gesture": "peace", "when": "later"}', 400, "'when' must be one of \"now\", "
                                                   "\"after\""),
    (b'{"gesture": "peace", "loop": 0}', 400, "'loop' must be true, false or a whole number "
                                             "from 1 to 1,000"),
    (b'{"gesture": "peace", "side": "up"}', 400, "'side' must be one of \"right\", \"left\""),
    (b'{"gesture": "' + b"x" * 70_000 + b'"}', 400, "the body is larger than 65,536 bytes"),
    (b'{"gesture": "pease"}', 422, "no library gesture 'pease'"),
    (b'{"steps": "indx 90"}', 422, "unknown servo or group 'indx'"),
    (b'{"steps": "index 90\\nmiddle 90"}', 422, "steps are one line"),
    (b'{"steps": "use \\"/etc/passwd\\""}', 422, "'use' is a keyword, not a servo, group, "
                                                  "pose or gesture"),
    (b'{"gesture": "peace", "side": "left"}', 422, "profile 'rhand' has no [sides]: it "
                                                  "cannot play 'peace' on the left"),
    (b'{"text": "use \\"/etc/x.gest\\"\\nw: index 9"}', 422, "use reads a file, and "
     "<request> names no file of this computer"),
    (b'{"text": "a: index 9\\nb: index 8"}', 422, "the text has 2 gestures: name the one "
                                                    "to play"),
    (b'{"text": "a: index 9", "gesture": "peace"}', 422, "no gesture 'peace' in the text"),
]


def test_bad_requests_are_400_or_422_with_the_cli_s_words():
    with serving() as service:
        for body, status, error in BAD:
            got, answer, _ = service.call("POST", "/api/play", body)
            assert (got, answer["error"]) == (status, error), body[:60]
        _, problem, _ = service.call("POST", "/api/play", b'{"steps": "indx 90"}')
        assert problem["text"] == ("<request>:1:1: error: unknown servo or group 'indx'\n"
                                   "    indx 90\n    ^~~~\n  hint: did you mean 'index'?")
        assert problem["diagnostics"][0] | {"text": ""} == {
            "severity": "error", "message": "unknown servo or group 'indx'", "line": 1,
            "column": 1, "width": 4, "source": "indx 90", "hint": "did you mean 'index'?",
            "text": ""}
        got, answer, _ = service.call("POST", "/api/play", b'{"gesture": "peace"}',
                                      {"Content-Type": "text/plain"})
        assert got == 400 and "Content-Type: application/json" in answer["error"]
        assert service.call("POST", "/api/stop", b'{"now": 1}')[0] == 400
        assert service.call("GET", "/api/nothing")[0] == 404
        assert service.call("DELETE", "/api/play")[0] == 405
        assert service.proc.poll() is None  # it serves on


# -- events -------------------------------------------------------------------------------
def test_a_request_takes_over_after_queues_and_stop_empties_the_queue():
    with serving() as service, service.events() as ws:
        _, a, _ = service.call("POST", "/api/play", {"steps": "index 180 over 2s"})
        until(ws, "started", a["id"])
        _, b, _ = service.call("POST", "/api/play", {"steps": "index 0 over 1s"})
        told = until(ws, "started", b["id"])
        assert {"event": "stopped", "id": a["id"]} in told
        _, c, _ = service.call("POST", "/api/play", {"gesture": "fist", "when": "after"})
        until(ws, "done", b["id"])
        until(ws, "started", c["id"])
        moved(ws, "thumb")
        _, s, _ = service.call("POST", "/api/stop")
        told = until(ws, "stopped", c["id"])
        assert not [e for e in told if e["event"] == "done" and e["id"] == c["id"]]
        held = values(still(service))
        fingers = [held[f] for f in ("thumb", "index", "middle", "ring", "pinky")]
        assert any(0 < v < 180 for v in fingers)  # fist was stopped on its way


def test_pose_events_come_at_most_every_servo_frame_while_the_hand_moves():
    with serving() as service, service.events() as ws:
        _, a, _ = service.call("POST", "/api/play", {"steps": "fingers 180 over 1s"})
        start = time.monotonic()
        told = until(ws, "done", a["id"])
        poses = [e for e in told if e["event"] == "pose"]
        assert 10 <= len(poses) <= (time.monotonic() - start) / 0.020 + 1
        assert all(e["id"] == a["id"] for e in poses)
        assert poses[-1]["servos"]["index"] == 180


# -- safety and security ------------------------------------------------------------------
def test_another_site_cannot_move_the_hand():
    with serving() as service:
        here = f"{service.host}:{service.port}"
        for headers in ({"Origin": "http://evil.example"},
                        {"Origin": f"http://{here}.evil.example"},
                        {"Host": f"evil.example:{service.port}"},  # DNS rebinding
                        {"Host": f"evil.example:{service.port}", "Origin":
                         f"http://evil.example:{service.port}"}):
            status, answer, _ = service.call("POST", "/api/play", {"gesture": "fist"}, headers)
            assert status == 403, headers
        status, _, answered = service.call("OPTIONS", "/api/play", None, {
            "Origin": "http://evil.example", "Access-Control-Request-Method": "POST"})
        assert status == 403 and "Access-Control-Allow-Origin" not in answered
        from websockets.exceptions import InvalidStatus

        with pytest.raises(InvalidStatus), service.events({"Origin": "http://evil.example"}):
            pass
        status, pose, _ = service.call("GET", "/api/pose", None, {"Origin": f"http://{here}"})
        assert status == 200 and values(pose) == dict.fromkeys(PEACE, 0)  # nothing moved


def test_beyond_this_computer_a_token_is_needed(tmp_path):
    need_service_libraries()
    done = subprocess.run([sys.executable, "-m", "inmoov_dsl.cli.gestplay", "serve", "--port",
                           "sim://", "--http", "0.0.0.0:0"], capture_output=True, text=True,
                          timeout=60)
    assert done.returncode == 1
    assert done.stderr.startswith("gestplay: error: 0.0.0.0 is reachable from other "
                                  "computers: the service moves a machine, so it needs a "
                                  "token there\n")
    secret = tmp_path / "token"
    secret.write_text("s3cret-s3cret-s3cret\n")
    with serving("--http", "0.0.0.0:0", "--token-file", str(secret)) as service:
        service.host = "127.0.0.1"
        assert service.call("GET", "/api/pose")[0] == 401
        assert service.call("GET", "/api/pose", None, {"Authorization": "Bearer nope"})[0] == 401
        bearer = {"Authorization": "Bearer s3cret-s3cret-s3cret"}
        assert service.call("GET", "/api/pose", None, bearer)[0] == 200
        assert service.call("POST", "/api/play", {"gesture": "peace"}, bearer)[0] == 202
        with service.events(path="/api/events?token=s3cret-s3cret-s3cret") as ws:
            ws.send("hello")  # what a client sends is read and ignored
        from websockets.exceptions import InvalidStatus

        with pytest.raises(InvalidStatus), service.events():
            pass


def test_the_guard_s_rules():
    g = guard.Guard("127.0.0.1", 8180, None)
    assert g.refuse("GET", {"Host": "127.0.0.1:8180"}, {}) is None
    assert g.refuse("GET", {"Host": "localhost:8180"}, {}) is None
    assert g.refuse("GET", {"Host": "127.0.0.1:8180", "Origin": "http://127.0.0.1:8180"},
                    {}) is None
    assert g.refuse("GET", {"Host": "localhost:8181"}, {})[0] == 403
    assert g.refuse("GET", {"Host": "127.0.0.1:8180", "Origin": "null"}, {})[0] == 403
    assert guard.is_loopback("::1") and guard.is_loopback("127.3.0.1")
    assert not guard.is_loopback("0.0.0.0") and not guard.is_loopback("192.168.1.2")
    t = guard.Guard("0.0.0.0", 8180, "a" * 20)
    assert t.refuse("GET", {"Host": "robot.local:8180"}, {"token": "a" * 20}) is None
    assert t.refuse("GET", {"Host": "robot.local:8180"}, {"token": "a" * 19})[0] == 401


@pytest.mark.skipif(not hasattr(os, "openpty"), reason="gestsim's pseudo-terminals are POSIX")
def test_sigterm_mid_move_sends_cancel_to_the_board(gestsim):
    _, path, log = gestsim
    with serving(port=path) as service, service.events() as ws:
        _, a, _ = service.call("POST", "/api/play", {"steps": "fingers 180 over 3s"})
        until(ws, "started", a["id"])
        time.sleep(0.5)
        code, err = service.stop()
        assert gone(ws) == 1001  # a client is told the service goes away
    assert code == 143 and "stopped by SIGTERM: CANCEL sent" in err
    assert err.strip().endswith("the hand holds its pose")  # and nothing after it
    wait_for(lambda: received(log)[1][-1:] == [255], "the stop's CANCEL at the board")
    sent = received(log)[1]
    assert sent.count(255) >= 2  # the gesture's CANCEL, then the stop's


# -- the page, in a browser ---------------------------------------------------------------
def test_the_page_plays_a_button_shows_the_pose_and_an_error_at_its_column(tmp_path):
    import tempfile

    from test_web import Browser, chromium

    exe = chromium()
    with serving() as service, tempfile.TemporaryDirectory(prefix="chromium-") as profile:
        browser = Browser(exe, profile)
        try:
            page(browser, service)
        finally:
            browser.close()


def page(browser, service: Service) -> None:
    def value(expression: str):
        return browser.call("Runtime.evaluate", expression=expression,
                            returnByValue=True)["result"].get("value")

    def wait_for(expression: str, timeout: float = 20):
        deadline = time.monotonic() + timeout
        while not (found := value(expression)):
            assert time.monotonic() < deadline, f"the page never showed {expression}"
            time.sleep(0.1)
        return found

    def click(selector: str) -> None:
        box = value(f"JSON.stringify(document.querySelector('{selector}')"
                    f".getBoundingClientRect())")
        rect = json.loads(box)
        x, y = rect["x"] + rect["width"] / 2, rect["y"] + rect["height"] / 2
        for kind in ("mousePressed", "mouseReleased"):
            browser.call("Input.dispatchMouseEvent", type=kind, x=x, y=y, button="left",
                         clickCount=1)

    browser.navigate(f"{service.url}/")
    wait_for("document.querySelectorAll('#gestures button').length > 20")
    wait_for("document.getElementById('status').textContent === 'connected'")
    ring = "document.querySelectorAll('#pose .bar b')[4].textContent"
    assert value(ring) == "0"
    click("[data-gesture=fist]")
    wait_for(f"{ring} === '180'")
    click("#line")
    browser.call("Input.insertText", text="indx 90")
    for kind in ("keyDown", "keyUp"):
        browser.call("Input.dispatchKeyEvent", type=kind, key="Enter", code="Enter",
                     windowsVirtualKeyCode=13, text="\r" if kind == "keyDown" else "")
    error = wait_for("document.getElementById('error').textContent")
    assert error.splitlines() == ["error: unknown servo or group 'indx'", "indx 90", "^~~~",
                                  "hint: did you mean 'index'?"]
    view = value("document.getElementById('view').src")  # the hand in 3-D (viser)
    assert not value("document.getElementById('view').hidden")
    assert view.startswith("http://127.0.0.1:") and any(u.startswith(view)
                                                        for u in browser.requests)
    here = ("http://127.0.0.1:", "ws://127.0.0.1:", "data:", "blob:")  # all from here
    off = [url for url in browser.requests if not url.startswith(here)]
    assert browser.requests and not off, off


# -- on the firmware, in simavr -----------------------------------------------------------
from test_firmware import boards, build, firmware_pty, simboard  # noqa: E402, F401


def test_on_the_firmware_the_board_holds_what_the_service_says(firmware_pty):  # noqa: F811
    with serving(port=firmware_pty) as service, service.events() as ws:
        _, a, _ = service.call("POST", "/api/play", {"gesture": "rockon"})
        until(ws, "done", a["id"], timeout=60)
        _, b, _ = service.call("POST", "/api/play", {"steps": "index 120 over 1s"})
        until(ws, "started", b["id"])
        moved(ws, "index")
        service.call("POST", "/api/stop")
        pose = still(service)
        code, _ = service.stop()
        gone(ws)
    assert code == 143
    assert 0 < pose["servos"]["index"]["value"] < 120  # stopped on its way
    assert dump(firmware_pty) == values(pose)  # the firmware's own answer to DUMP


# -- a board unplugged while serving ------------------------------------------------------
def board_on(link) -> subprocess.Popen:
    """A gestsim board, and ``link`` (a symlink, as udev names a board) pointing at it."""
    proc = subprocess.Popen([sys.executable, "-m", "inmoov_dsl.cli.gestsim", "--quiet",
                             "--boot", "0.1"], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    path = Lines(proc.stdout).until(r"^(/dev/\S+)$", 30)
    spare = link.with_suffix(".new")
    os.symlink(path, spare)
    os.replace(spare, link)
    return proc


@pytest.mark.skipif(not hasattr(os, "openpty"), reason="gestsim's pseudo-terminals are POSIX")
def test_a_board_unplugged_is_an_event_and_a_503_until_it_comes_back(tmp_path):
    link = tmp_path / "hand"
    first = board_on(link)
    try:
        with serving(port=str(link)) as service, service.events() as ws:
            _, a, _ = service.call("POST", "/api/play", {"steps": "index 90 over 0.3s"})
            until(ws, "done", a["id"])
            first.kill()  # the cable is pulled
            first.wait()
            assert until(ws, "board-lost")[-1]["board"] == 181
            status, answer, _ = service.call("POST", "/api/play", {"gesture": "fist"})
            assert status == 503 and answer["error"] == ("board 181 is not there: its link "
                                                         "was lost")
            second = board_on(link)  # plugged in again (a new board, at rest)
            try:
                assert until(ws, "board-back")[-1]["board"] == 181
                _, pose, _ = service.call("GET", "/api/pose")
                assert values(pose) == dict.fromkeys(PEACE, 0)  # what the board holds
                status, b, _ = service.call("POST", "/api/play", {"steps": "index 45"})
                assert status == 202
                until(ws, "done", b["id"])
                code, err = service.stop()
                gone(ws)
                assert code == 143 and "Traceback" not in err
            finally:
                second.kill()
                second.wait()
    finally:
        if first.poll() is None:
            first.kill()


# -- any request, a clear answer ----------------------------------------------------------
from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from inmoov_dsl.errors import GestError  # noqa: E402
from inmoov_dsl.live.drive import library_program  # noqa: E402
from inmoov_dsl.profiles.profile import load_profile  # noqa: E402

PROGRAM, RHAND = library_program(), load_profile("rhand")
JSON = st.recursive(st.none() | st.booleans() | st.integers() | st.floats() | st.text(),
                    lambda inner: st.lists(inner) | st.dictionaries(st.text(), inner),
                    max_leaves=8)
FIELDS = st.dictionaries(st.sampled_from([*core.PLAY_FIELDS, "x"]),
                         JSON | st.sampled_from(["peace", "index 90", "now", "after", "left",
                                                 "indx 9", "fist & wave", "wait 1s"]),
                         max_size=5)


@settings(max_examples=300, deadline=None, derandomize=True)
@given(body=st.binary(max_size=300) | FIELDS.map(lambda d: json.dumps(d).encode()))
def test_any_body_is_an_order_a_400_or_a_422(body):
    try:
        order = core.play_order(core.read_json(body), PROGRAM, RHAND, "id")
    except core.BadRequest as exc:
        assert exc.message and json.dumps(exc.json())
    except GestError as exc:
        assert core.problem(exc)["text"].startswith("<request>:")
    else:
        assert order.id == "id" and order.what.actions and order.loop >= 0


# -- the service speaks ---------------------------------------------------------------------
class Loudest:
    """The loudest sample a raw 16-bit stream has carried, read as it comes."""

    def __init__(self, pipe):
        import threading

        self.pipe, self.peak, self.samples = pipe, 0, 0
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self) -> None:
        while chunk := self.pipe.read1(3200):
            data = np.frombuffer(chunk[:len(chunk) // 2 * 2], np.int16).astype(float)
            self.samples += len(data)
            self.peak = max(self.peak, float(np.abs(data).max(initial=0)))


def test_the_service_speaks_on_its_computer(sound_server, tmp_path):  # noqa: F811
    import shutil as which

    if which.which("espeak-ng") is None:
        require("espeak-ng", False, "apt-get install espeak-ng")
    with serving("--profile", "inmoov") as service, service.events() as ws:
        status, answer, _ = service.call("POST", "/api/play",
                                         {"steps": 'say "hello.wav"'})
        assert status == 422 and answer["error"] == ("a request names no file: it may say "
                                                     "text, not a .wav")
        record = subprocess.Popen(["parec", "-d", "speaker.monitor", "--raw",
                                   "--format=s16le", "--channels=1", "--rate=8000"],
                                  stdout=subprocess.PIPE)
        try:
            loudest = Loudest(record.stdout)
            wait_for(lambda: loudest.samples > 0, "the sink's monitor recording")
            _, a, _ = service.call("POST", "/api/play", {"steps": 'say "Hello, I am InMoov" '
                                                                   '& neck 100 over 1s'})
            told = until(ws, "done", a["id"], timeout=30)
            jaw = [e["servos"]["jaw"] for e in told if e["event"] == "pose"]
            # the mouth opened (how wide the poses caught it, a busy machine decides:
            # the service shows at most a pose a frame, fewer when it runs late)
            assert max(jaw) > jaw[-1] + 15
            # and the sink heard the voice (when, on a busy machine: its own time)
            wait_for(lambda: loudest.peak > 1000, "the voice at the sink", 30)
        finally:
            record.kill()
            record.wait()
        assert service.stop()[0] == 143
        gone(ws)


def answer(host: str, port: int, data: bytes, leave: bool = False, whole: bool = True
           ) -> bytes:
    """The first bytes of the answer; b"" if the client left first, or the service
    waits for the rest of a request that is not whole (it would close it in time)."""
    import socket

    with socket.create_connection((host, port), timeout=30) as s:
        s.sendall(data)
        if leave:
            return b""
        s.settimeout(30 if whole else 0.3)
        try:
            return s.recv(4096)
        except ConnectionResetError:
            return b""
        except TimeoutError:
            assert not whole, data[:300]  # a whole request is answered
            return b""


def test_malformed_http_and_handshakes_are_400s_and_a_line_at_most():
    """A WebSocket handshake with a key that is not ASCII is a bad request (400), not a
    500; malformed request lines and headers, and a client gone mid-body, put no
    traceback and none of the request's bytes in the service's log: a line each at
    most. The service goes on answering."""
    with serving() as service:
        host = f"{service.host}:{service.port}".encode()
        handshake = (b"GET /api/events HTTP/1.1\r\nHost: " + host +
                     b"\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
                     b"Sec-WebSocket-Version: 13\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZ\xc3"
                     b"\xa9==\r\n\r\n")
        got = answer(service.host, service.port, handshake)
        assert got.startswith(b"HTTP/1.1 400 ") and b"Sec-WebSocket-Key" in got
        flood = b"X" * 7000
        bad = [b"GET / HTTP/1.1\r\nHost: x\r\nBad Header " + flood + b"\r\n\r\n",
               b"GARBAGE\x01\x02 /" + flood + b" HTTP/1.1\r\n\r\n",
               b"GET / HTTP/9.9\r\n\r\n"]
        for data in bad:
            assert answer(service.host, service.port, data).startswith(b"HTTP/1.0 400 ")
        half = (b"POST /api/play HTTP/1.1\r\nHost: x\r\nContent-Type: application/json"
                b"\r\nContent-Length: 5000\r\n\r\n{\"steps\": ")
        answer(service.host, service.port, half, leave=True)
        assert service.call("GET", "/api/pose")[0] == 200
        _, log = service.stop()
    lines = [line for line in log.splitlines()[1:] if line]  # after where it serves
    assert "Traceback" not in log and "XXXX" not in log
    assert len(lines) <= len(bad) + 2
    assert all(line.startswith("gestplay serve: ") for line in lines), lines


def test_a_flood_of_bad_requests_is_ten_lines_a_minute_then_a_count(capsys):
    pytest.importorskip("aiohttp")
    import logging

    from inmoov_dsl.service.log import OneLine

    clock = {"t": 100.0}
    line = OneLine(now=lambda: clock["t"])
    try:
        raise ValueError("Bad status line: b'" + "X" * 5000 + "'")
    except ValueError:
        record = logging.LogRecord("aiohttp.server", logging.ERROR, "", 0,
                                   "Error handling request from %s", ("127.0.0.1",),
                                   sys.exc_info())
    for _ in range(25):
        line.emit(record)
        clock["t"] += 1
    clock["t"] += 60
    line.emit(record)
    lines = capsys.readouterr().err.splitlines()
    assert len(lines) == 12
    assert lines[0] == ("gestplay serve: Error handling request from 127.0.0.1: ValueError: "
                        "Bad status line: b'" + "X" * 61)
    assert lines[10] == "gestplay serve: and 15 more requests it could not read in that minute"


@pytest.mark.parametrize(("given", "address"), [
    (None, ("127.0.0.1", 8180)), ("8181", ("127.0.0.1", 8181)), (":0", ("127.0.0.1", 0)),
    ("0.0.0.0:80", ("0.0.0.0", 80)), ("[::1]:8180", ("::1", 8180))])
def test_http_is_host_and_port_or_a_bare_port_on_this_computer(given, address):
    """``--http`` as gestsim takes it too: HOST:PORT, or a bare PORT on 127.0.0.1."""
    from inmoov_dsl.cli import gestplay

    more = [] if given is None else ["--http", given]
    args = gestplay.parser("serve").parse_args(["serve", "--port", "sim://", *more])
    assert args.http == address


@pytest.mark.parametrize("given", ["robot.local", "::1", "127.0.0.1:65536", ""])
def test_an_http_address_that_is_not_one_is_a_usage_error(given, capsys):
    from inmoov_dsl.cli import gestplay

    with pytest.raises(SystemExit) as exit_:
        gestplay.main(["serve", "--port", "sim://", "--http", given])
    assert exit_.value.code == 2
    assert capsys.readouterr().err.splitlines()[-1] == (
        f"gestplay serve: error: argument --http: '{given}' is not HOST:PORT or PORT (a "
        "port is 0 to 65535; an IPv6 host in brackets: [::1]:8180)")
