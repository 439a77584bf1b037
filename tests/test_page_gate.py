"""No other web site reaches a page of ours (issue 49): any site the user visits can open
``ws://127.0.0.1:PORT/`` (a browser does not apply the same-origin rule to WebSockets)
or rebind its name to 127.0.0.1. The live preview (``gestc preview --live``, the
language server's page) and ``gestsim --web`` refuse a handshake from another origin or
for another host before they send anything, and answer their own page. Driven with the
websockets library and urllib, as a foreign page's browser would send them."""

from __future__ import annotations

import asyncio
import contextlib
import socket
import subprocess
import sys
import urllib.error
import urllib.request

import pytest
from lsprotocol import types as lsp
from pytest_lsp import LanguageClient
from test_web import POSIX, Lines, need_viser

LIMIT = 120.0  #: s for any answer, which a loaded machine meets
ZSTD = b"\x28\xb5\x2f\xfd"  #: where a zstd frame begins
WAVE = "wave:\n    fingers 0 over 0.7s\n    wrist 180 over 0.4s\n    wrist 0 over 0.4s\n"


def handshake(url: str, origin: str, host: str | None = None) -> tuple[int, bytes]:
    """(101 and the first messages' bytes, or the refusal's status and body) of a viser
    client's WebSocket handshake on the page ``url`` from a page of ``origin``, naming
    ``host`` (its name rebound to 127.0.0.1) or the page's own."""
    import viser
    from websockets.exceptions import InvalidStatus
    from websockets.sync.client import connect

    port = int(url.split(":")[2].strip("/"))
    ws_url = f"ws://{host or f'127.0.0.1:{port}'}/"
    try:
        with connect(ws_url, sock=socket.create_connection(("127.0.0.1", port)),
                     subprotocols=[f"viser-v{viser.__version__}"],
                     additional_headers={"Origin": origin}, open_timeout=LIMIT) as ws:
            got = b""
            while b"wrist 180 over 0.4s" not in got:  # the gesture's step, on its page
                got += unpacked(ws.recv(timeout=LIMIT))
            return 101, got
    except InvalidStatus as refused:
        return refused.response.status_code, bytes(refused.response.body)


def unpacked(message: bytes | str) -> bytes:
    """A viser message's bytes as sent before zstd compressed them."""
    import zstandard  # viser's dependency

    data = message if isinstance(message, bytes) else message.encode()
    at = data.find(ZSTD)
    return data if at < 0 else zstandard.ZstdDecompressor().decompressobj().decompress(
        data[at:])


def get(url: str, host: str) -> int:
    """The status of the page's GET naming ``host``."""
    try:
        with urllib.request.urlopen(urllib.request.Request(url, headers={"Host": host}),
                                    timeout=LIMIT) as answer:
            return answer.status
    except urllib.error.HTTPError as refused:
        return refused.code


def assert_guarded(url: str) -> None:
    """The page ``url`` answers its own origin, refuses every other before sending."""
    port = url.split(":")[2].strip("/")
    own = f"127.0.0.1:{port}"
    status, got = handshake(url, f"http://{own}")
    assert status == 101 and b"wrist 180" in got  # the page's own: the whole page
    local = f"localhost:{port}"
    assert handshake(url, f"http://{local}", local)[0] == 101
    status, said = handshake(url, "http://evil.example")
    assert (status, said) == (403, b"a request from another site (http://evil.example) "
                                   b"is refused\n")
    rebound = f"evil.example:{port}"  # a foreign page whose name now points here
    status, said = handshake(url, f"http://{rebound}", rebound)
    assert status == 403 and said.startswith(b"unknown Host 'evil.example:")
    assert get(url, own) == 200 and get(url, rebound) == 403


@contextlib.contextmanager
def live_page(tmp_path, told: list[str]):
    """``gestc preview --live`` of WAVE, its page's address given; what it said on its
    standard error, once stopped by SIGTERM, appended to ``told``."""
    need_viser()
    path = tmp_path / "w.gest"
    path.write_text(WAVE, encoding="utf-8")
    proc = subprocess.Popen([sys.executable, "-m", "inmoov_dsl.cli.gestc", "preview", "--live",
                             str(path), "--no-open"], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE)
    try:
        yield Lines(proc.stderr).until(r"at (http://127\.0\.0\.1:\d+/)", LIMIT)
        assert proc.poll() is None
    finally:
        proc.terminate()
        told.append(proc.communicate(timeout=30)[1].decode())


@POSIX
def test_gestc_preview_live_refuses_another_web_site(tmp_path):
    told: list[str] = []
    with live_page(tmp_path, told) as url:
        assert_guarded(url)
    said = told[0]
    assert "Traceback" not in said
    assert (f"the page on port {url.split(':')[2].strip('/')} refused a request: a request "
            "from another site (http://evil.example) is refused") in said


@pytest.mark.asyncio
async def test_the_language_servers_page_refuses_another_web_site(
        client: LanguageClient, tmp_path):
    need_viser()
    uri = (tmp_path / "wave.gest").as_uri()
    client.text_document_did_open(lsp.DidOpenTextDocumentParams(
        lsp.TextDocumentItem(uri=uri, language_id="gest", version=1, text=WAVE)))
    answer = await asyncio.wait_for(client.workspace_execute_command_async(
        lsp.ExecuteCommandParams("gest.preview", [uri, {"open": False}])), LIMIT)
    await asyncio.get_running_loop().run_in_executor(None, assert_guarded, answer["url"])
    assert client.shown_documents == []  # nothing a foreign page could click


def garbage(url: str, seed: int, connections: int = 20, each: int = 20) -> None:
    """Seeded garbage from the page's own origin: random bytes, text, and messages of
    viser's types with wrong fields, ``each`` on each of ``connections``."""
    import random

    import msgspec
    import viser
    from websockets.exceptions import ConnectionClosed
    from websockets.sync.client import connect

    rng, port = random.Random(seed), url.split(":")[2].strip("/")
    kinds = ["GuiUpdateMessage", "ViewerCameraMessage", "ScenePointerMessage", "Nope"]
    for _ in range(connections):
        with connect(f"ws://127.0.0.1:{port}/", subprotocols=[f"viser-v{viser.__version__}"],
                     additional_headers={"Origin": f"http://127.0.0.1:{port}"},
                     open_timeout=LIMIT) as ws:
            for n in range(each):
                pick = rng.random()
                sent = (rng.randbytes(rng.randrange(1, 50)) if pick < 0.3 else
                        f"text {n}" if pick < 0.4 else
                        msgspec.msgpack.encode({"type": rng.choice(kinds), "id": "x",
                                                "updates": {"value": rng.random()}})
                        if pick < 0.8 else msgspec.msgpack.encode([rng.random(), None]))
                try:
                    ws.send(sent)
                except ConnectionClosed:  # the page dropped it: the next connection
                    break


@POSIX
def test_garbage_on_the_pages_websocket_is_a_line_each_not_a_traceback(tmp_path):
    told: list[str] = []
    with live_page(tmp_path, told) as url:
        garbage(url, seed=49)
        port = url.split(":")[2].strip("/")
        status, got = handshake(url, f"http://127.0.0.1:{port}")  # still the whole page
        assert status == 101 and b"wrist 180" in got
    said = told[0].splitlines()
    assert "Traceback" not in told[0]
    dropped = [line for line in said if line.startswith("the page dropped a connection")]
    others = [line for line in said if not line.startswith("the page ")]
    assert dropped and others == ["gestc: stopped by SIGTERM"]
