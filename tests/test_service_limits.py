"""gestplay serve under what a fuzzer found: a body in several TCP segments, requests
whose check is long (while the service goes on answering, and stops on SIGTERM), a
request's sounds, and the limit of a gesture's length on every path. Clients the project
did not write: a raw socket, curl, http.client and the websockets library."""

import contextlib
import json
import shutil
import signal
import socket
import subprocess
import sys
import threading
import time

import pytest
from test_service import Service, need_service_libraries, serving, until
from test_web import Lines
from toolchain import require

STEPS = b'{"steps": "index 90 over 0.5s"}'


def segments(host: str, port: int, head: bytes, parts: list[bytes], pause: float = 0.2,
             read_all: bool = True) -> bytes:
    """Send ``head`` (a request's line and headers, with Expect: 100-continue), wait for
    the service's 100 Continue (its handler is reading the body: the event), then each
    of ``parts`` with a pause between; the answer (its first bytes when not
    ``read_all``)."""
    with socket.create_connection((host, port), timeout=30) as s:
        s.sendall(head + b"Expect: 100-continue\r\n\r\n")
        assert s.recv(4096).startswith(b"HTTP/1.1 100 Continue")
        for part in parts:
            s.sendall(part)
            time.sleep(pause)  # the service reads what came so far (on a busy machine
            # perhaps not: then it reads more at once, which it must take too)
        answer = b""
        while chunk := s.recv(65536):
            answer += chunk
            if not read_all or b"\r\n\r\n" in answer and answer.endswith(b"}"):
                break
        return answer


def head(service, more: bytes) -> bytes:
    return (b"POST /api/play HTTP/1.1\r\nHost: %s:%d\r\nContent-Type: application/json\r\n"
            % (service.host.encode(), service.port)) + more


def chunked(data: bytes, size: int) -> list[bytes]:
    """``data`` as HTTP chunks of ``size`` bytes (without the last, empty one)."""
    return [b"%x\r\n%s\r\n" % (len(data[i:i + size]), data[i:i + size])
            for i in range(0, len(data), size)]


def test_a_body_in_several_segments_is_read_whole_and_a_large_one_is_not_read():
    with serving() as service:
        answer = segments(service.host, service.port,
                          head(service, b"Content-Length: %d\r\n" % len(STEPS)),
                          [STEPS[:10], STEPS[10:20], STEPS[20:]])
        assert answer.startswith(b"HTTP/1.1 202 "), answer
        assert json.loads(answer.partition(b"\r\n\r\n")[2])["id"]
        answer = segments(service.host, service.port,
                          head(service, b"Transfer-Encoding: chunked\r\n"),
                          [*chunked(STEPS, 7), b"0\r\n\r\n"])
        assert answer.startswith(b"HTTP/1.1 202 "), answer
        # a body that grows past the limit is refused once the limit is passed: the
        # service answers without waiting for the rest (the last chunk is never sent)
        big = b'{"steps": "' + b"x" * 70_000
        answer = segments(service.host, service.port,
                          head(service, b"Transfer-Encoding: chunked\r\n"),
                          chunked(big, 16_384), pause=0.05, read_all=False)
        assert answer.startswith(b"HTTP/1.1 400 "), answer[:200]
        assert b"the body is larger than 65,536 bytes" in answer
        assert service.call("GET", "/api/pose")[0] == 200


# -- a gesture's length ---------------------------------------------------------------------
HOURS = [  # (what a request sends, the lines and column the 422 may point at: the step
    # that passes the hour, which depends on where the hand starts)
    ({"text": "g:\n  repeat 7:\n    wait 600s"}, {3}, 10),
    ({"text": "g:\n  repeat 7:\n    wait 600s", "loop": 3}, {3}, 10),
    ({"text": "g:\n  repeat 1000:\n    repeat 49:\n      index 90 over 0.02s\n"
              "      index 0 over 0.02s"}, {4, 5}, 7),
]


def test_a_gesture_lasts_at_most_an_hour_on_a_robot_without_a_contact_check():
    """On rhand (whose profile has no collision model, so nothing was planned before a
    request was queued), a sent text that lasts more than 3600 s is a 422 at its place,
    as the compiler says it, and nothing moves."""
    if shutil.which("curl") is None:
        require("curl", False, "apt-get install curl")
    with serving() as service:
        for body, lines, column in HOURS:
            status, answer = service.curl("--json", json.dumps(body), f"{service.url}"
                                          "/api/play")
            assert status == 422, answer
            assert answer["error"] == "the gesture lasts more than 3600 s"
            where = answer["diagnostics"][0]
            assert where["line"] in lines and where["column"] == column
            assert where["hint"] == "split it into shorter gestures"
        _, pose, _ = service.call("GET", "/api/pose")
        assert pose["playing"] is None


# -- long checks ----------------------------------------------------------------------------
#: gestplay serve with two slow steps put in (what a test cannot send in 64 KB in a known
#: time): a text that names ``held`` is compiled only once a line comes on standard
#: input; one whose gesture is ``endless`` is checked for ever (Python at work, as a
#: long check is). Each says on standard error when it begins.
SLOW = """
import sys
from inmoov_dsl.service import core, hub

compile_order, check = core.play_order, hub.Service.check

def play_order(doc, *args):
    if "held" in str(doc.get("text")):
        print("test: compiling held", file=sys.stderr, flush=True)
        sys.stdin.readline()
    return compile_order(doc, *args)

def endless(self, order):
    if order.what.name == "endless":
        print("test: checking endless", file=sys.stderr, flush=True)
        while True:
            sum(range(10_000))
    return check(self, order)

core.play_order, hub.Service.check = play_order, endless
from inmoov_dsl.cli import gestplay
sys.exit(gestplay.main(sys.argv[1:]))
"""


@contextlib.contextmanager
def slow_serving(tmp_path):
    """``gestplay serve --port sim://`` with SLOW's steps: the service and its log."""
    need_service_libraries()
    script = tmp_path / "slow_serve.py"
    script.write_text(SLOW)
    proc = subprocess.Popen([sys.executable, str(script), "serve", "--port", "sim://?boot=0",
                             "--http", "127.0.0.1:0"], stdin=subprocess.PIPE,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    try:
        log = Lines(proc.stderr)
        url = log.until(r"(http://\S+)/ drives", 60)
        host, _, number = url[len("http://"):].rpartition(":")
        yield Service(proc, host, int(number)), log
    finally:
        if proc.poll() is None:
            proc.kill()
        proc.communicate(timeout=10)


def in_background(service: Service, body: dict) -> tuple[threading.Thread, dict]:
    """POST ``body`` to /api/play from a thread: the thread, and the answer once it
    has come (``status``, ``answer``)."""
    got: dict = {}

    def post() -> None:
        with contextlib.suppress(OSError):  # the service may end before it answers
            got["status"], got["answer"], _ = service.call("POST", "/api/play", body)

    thread = threading.Thread(target=post, daemon=True)
    thread.start()
    return thread, got


def test_the_service_answers_while_a_request_is_compiled(tmp_path):
    """A request's compile work is off the event loop: while one is being compiled
    (held until the test lets it go), the pose is answered, and another request is
    checked, played and told on the events socket."""
    with slow_serving(tmp_path) as (service, log), service.events() as ws:
        thread, got = in_background(service, {"text": "held: index 90 over 0.5s"})
        log.until(r"(compiling held)", 30)
        status, pose, _ = service.call("GET", "/api/pose")
        assert status == 200 and "index" in pose["servos"]
        status, a, _ = service.call("POST", "/api/play", {"steps": "middle 90 over 0.3s"})
        assert status == 202
        until(ws, "done", a["id"])
        assert not got  # the held request is still being compiled
        service.proc.stdin.write(b"go\n")
        service.proc.stdin.flush()
        thread.join(30)
        assert got["status"] == 202
        until(ws, "done", got["answer"]["id"])


def test_sigterm_ends_the_service_while_a_check_runs(tmp_path):
    """SIGTERM during a check that would never end: the service stops it, tells its
    client that it stops (503), sends CANCEL and ends, as it does when idle."""
    with slow_serving(tmp_path) as (service, log):
        thread, got = in_background(service, {"text": "endless: index 90 over 0.5s"})
        log.until(r"(checking endless)", 30)
        service.proc.send_signal(signal.SIGTERM)
        try:
            service.proc.wait(timeout=20)  # ends within a few seconds
        except subprocess.TimeoutExpired:
            pytest.fail("gestplay serve had not ended 20 s after SIGTERM")
        err = service.proc.stderr.read().decode()
        thread.join(30)
    assert service.proc.returncode == 143, err
    assert "stopped by SIGTERM: CANCEL sent" in err and "Traceback" not in err
    assert got.get("status") in (None, 503)  # told, or the connection closed
    if got:
        assert got["answer"]["error"] == "the service stops: the request was not checked"


# -- the checks' work, in-process -------------------------------------------------------------
def test_a_check_over_its_budget_is_stopped_and_so_are_all_as_the_service_stops():
    pytest.importorskip("aiohttp")
    import asyncio

    from inmoov_dsl.service.work import TooLong, Work

    began = threading.Event()
    ended: list[threading.Thread] = []

    def endless() -> None:
        ended.append(threading.current_thread())
        began.set()
        while True:
            sum(range(10_000))

    async def over_budget() -> None:
        with pytest.raises(TooLong) as stopped:
            await Work(budget=0.2).run(endless)
        assert not stopped.value.stopping

    async def service_stops() -> None:
        work = Work()
        began.clear()
        checking = asyncio.ensure_future(work.run(endless))
        await asyncio.get_running_loop().run_in_executor(None, began.wait)
        work.stop()
        with pytest.raises(TooLong) as stopped:
            await checking
        assert stopped.value.stopping
        with pytest.raises(TooLong):  # nothing more is checked
            await work.run(lambda: 1)
        assert await Work().run(lambda x: x + 1, 1) == 2

    asyncio.run(over_budget())
    asyncio.run(service_stops())
    for thread in ended:  # each check's thread has ended (not left running)
        thread.join(10)
        assert not thread.is_alive()


# -- what a request may say -------------------------------------------------------------------
def test_a_request_that_says_too_much_is_a_422_at_its_string():
    """On a robot with a voice, a sent text may say 20 different sounds lasting 180 s
    in all (the same one said again counts once); past that, a 422 at the string, as
    the compiler words it, and the sounds after it are not made."""
    from test_voice import need_espeak

    from inmoov_dsl.service.allowance import SPLIT

    need_espeak()
    words = ("the quick brown fox jumps over a lazy dog while robots wave their hands "
             * 80).split(" ")
    long = [" ".join(words[i:i + 150])[:900] for i in range(6)]
    with serving("--profile", "inmoov") as service:
        many = "g:\n" + "\n".join(f'  say "word {i}"' for i in range(25))
        status, answer, _ = service.call("POST", "/api/play", {"text": many})
        assert status == 422
        first = answer["diagnostics"][0]
        assert first["message"] == "a request may say at most 20 different sounds"
        assert (first["line"], first["column"], first["hint"]) == (22, 7, SPLIT)
        assert first["text"].startswith('<request>:22:7: error: a request may say at most')
        talk = "g:\n" + "\n".join(f'  say "{text}"' for text in long)  # ~60 s each
        status, answer, _ = service.call("POST", "/api/play", {"text": talk})
        assert status == 422
        first = answer["diagnostics"][0]
        assert first["message"].startswith("a request's sounds may last 180 s in all: "
                                           "with this one, they last ")
        assert first["line"] in range(3, 8) and first["column"] == 7
        status, _, _ = service.call("POST", "/api/play", {"text": 'g:\n  repeat 25:\n'
                                                                  '    say "hi"'})
        assert status == 202
        assert service.call("POST", "/api/stop")[0] == 200


def test_a_request_s_sounds_are_counted_once_each_and_not_made_past_the_limit():
    import numpy as np

    from inmoov_dsl.service.allowance import Allowance
    from inmoov_dsl.voice.wav import Sound, SoundError

    made = []

    def hear(text: str, file: str, voice: str, speed: int, pitch: int) -> Sound:
        made.append(text)
        return Sound(np.zeros(6000, np.float32), 100.0, text, text)  # a minute

    said = Allowance(hear)
    for text in ("a", "b", "c", "a"):
        said(text, "<request>", "en", 150, 45)
    with pytest.raises(SoundError, match="with this one, they last 240 s"):
        said("d", "<request>", "en", 150, 45)
    with pytest.raises(SoundError, match="those before this one last 240 s"):
        said("e", "<request>", "en", 150, 45)
    assert made == ["a", "b", "c", "d"]  # "a" once, "e" never
    few = Allowance(hear, sounds=2, seconds=1e9)
    few("a", "<request>", "en", 150, 45)
    few("b", "<request>", "en", 150, 45)
    with pytest.raises(SoundError, match="at most 2 different sounds"):
        few("c", "<request>", "en", 150, 45)


def test_the_sounds_kept_are_bounded_and_those_heard_longest_ago_go_first():
    from test_voice import wav

    from inmoov_dsl.voice.hearing import Hearing

    spoken = []

    def speaker(text: str, voice: str, speed: int, pitch: int) -> bytes:
        spoken.append(text)
        return wav([0.1] * 8000, rate=8000)  # a second: 32,000 bytes of samples

    hearing = Hearing(speaker=speaker, kept=100_000)
    for text in "abcde":
        hearing(text, "<request>", "en", 150, 45)
    assert sum(s.samples.nbytes for s in hearing.made.values()) <= 100_000
    assert [key[1] for key in hearing.made] == ["c", "d", "e"]
    hearing("c", "<request>", "en", 150, 45)  # kept: not spoken again, heard last now
    hearing("a", "<request>", "en", 150, 45)  # dropped: spoken again, and "d" goes
    assert spoken == [*"abcde", "a"]
    assert [key[1] for key in hearing.made] == ["e", "c", "a"]


def test_a_mouth_track_is_fitted_once_while_it_is_kept(monkeypatch):
    from collections import OrderedDict

    from test_voice import INMOOV, JAW, vowel, wav

    from inmoov_dsl.compiling import speech
    from inmoov_dsl.voice.wav import read_wav

    monkeypatch.setattr(speech, "TRACKS", 2)
    monkeypatch.setattr(speech, "_tracks", OrderedDict())
    fitted, fit = [], speech._fit
    monkeypatch.setattr(speech, "_fit", lambda s, servo, start: fitted.append(start) or
                        fit(s, servo, start))
    said = speech.heard(read_wav(wav(vowel()), "v.wav"), JAW, INMOOV.voice)
    jaw = INMOOV.servos[JAW]
    first = speech.track(said, jaw, 0)
    again = speech.heard(read_wav(wav(vowel()), "v.wav"), JAW, INMOOV.voice)  # planned anew
    assert speech.track(again, jaw, 0) is first
    speech.track(said, jaw, 10)
    speech.track(said, jaw, 20)  # the third: the one used longest ago goes
    assert len(speech._tracks) == 2
    speech.track(said, jaw, 0)
    assert fitted == [0, 10, 20, 0]
