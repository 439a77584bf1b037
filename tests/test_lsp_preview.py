"""The language server feeds the live preview page (issue 44) and checks collisions
(issue 43), driven by a client the project did not write (pytest-lsp) and the page read
in Debian's chromium, headless (tests/test_live_preview.py's helpers): ``gest.preview``
gives the page's address, an edit the client sends reaches the page, the cursor the
client tells (``gest/cursor``) highlights its step, a step clicked on the page makes the
server send ``window/showDocument`` to the client; a gesture that drives the InMoov
into itself is a warning at its step."""

from __future__ import annotations

import asyncio
import sys
import time

import pytest
import pytest_lsp
from lsprotocol import types as lsp
from pytest_lsp import ClientServerConfig, LanguageClient, client_capabilities
from test_live_preview import STEPS, browser, js, steps_on, until  # noqa: F401 (fixture)

SERVER = [sys.executable, "-m", "inmoov_dsl.cli.gestc", "lsp"]
LIMIT = 120.0  #: s for any answer or page change, which a loaded machine meets
WAVE = """wave:
    fingers 0 over 0.7s
    wrist 180 over 0.4s
    wrist 0 over 0.4s
"""


@pytest_lsp.fixture(config=ClientServerConfig(server_command=SERVER))
async def client(lsp_client: LanguageClient):
    await lsp_client.initialize_session(lsp.InitializeParams(
        capabilities=client_capabilities("visual-studio-code")))
    yield
    await lsp_client.shutdown_session()


async def opened(client: LanguageClient, uri: str, text: str) -> list[lsp.Diagnostic]:
    client.text_document_did_open(lsp.DidOpenTextDocumentParams(
        lsp.TextDocumentItem(uri=uri, language_id="gest", version=1, text=text)))
    await asyncio.wait_for(client.wait_for_notification(
        lsp.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS), LIMIT)
    return client.diagnostics[uri]


async def until_async(browser, expression: str, what: str):  # noqa: F811
    """``until``, letting the client's loop run (the server's messages are read)."""
    deadline = time.monotonic() + LIMIT
    while time.monotonic() < deadline:
        if value := js(browser, expression):
            return value
        await asyncio.sleep(0.05)
    pytest.fail(f"the page did not show {what} in {LIMIT} s")


@pytest.mark.asyncio
async def test_a_contact_is_a_warning_at_its_step(client: LanguageClient, tmp_path):
    uri = (tmp_path / "elbow.gest").as_uri()
    said = await opened(client, uri, "robot inmoov\n\nelbow:\n    r_rotate 125 over 1.5s\n"
                                     "    r_bicep 143 over 2s\n")
    (contact,) = [d for d in said if "enters the chest" in d.message]
    assert contact.severity == lsp.DiagnosticSeverity.Warning
    assert contact.range.start == lsp.Position(4, 4)  # the step that drives it there
    assert contact.message.startswith("at ") and "the right forearm" in contact.message


@pytest.mark.asyncio
async def test_the_page_follows_the_editor_and_a_click_shows_the_step(
        client: LanguageClient, browser, tmp_path):  # noqa: F811
    uri = (tmp_path / "wave.gest").as_uri()
    await opened(client, uri, WAVE)
    answer = await asyncio.wait_for(client.workspace_execute_command_async(
        lsp.ExecuteCommandParams("gest.preview", [uri, {"open": False}])), LIMIT)
    assert answer["url"].startswith("http://127.0.0.1:")
    assert client.shown_documents == []  # {"open": false}: the editor shows it itself
    browser.navigate(answer["url"])
    await until_async(browser, f"{STEPS}[1] === '2. 0.70–1.10 s · wrist 180 over 0.4s'",
                      "the gesture's steps")

    client.text_document_did_change(lsp.DidChangeTextDocumentParams(
        lsp.VersionedTextDocumentIdentifier(uri=uri, version=2),
        [lsp.TextDocumentContentChangePartial(
            range=lsp.Range(lsp.Position(2, 19), lsp.Position(2, 22)), text="0.8")]))
    await until_async(browser, f"{STEPS}[1] === '2. 0.70–1.50 s · wrist 180 over 0.8s'",
                      "the edit")  # typed, not saved: the file was never written

    client.protocol.notify("gest/cursor", {"textDocument": {"uri": uri},
                                           "position": {"line": 3, "character": 6}})
    await until_async(browser, "document.getElementById('gl-step').textContent === '3'",
                      "the cursor's step")

    js(browser, "[...document.querySelectorAll('button')].find(b => "
                "b.textContent.trim().startsWith('2. ')).click()")
    deadline = time.monotonic() + LIMIT
    while not client.shown_documents and time.monotonic() < deadline:
        await asyncio.sleep(0.05)
    (shown,) = client.shown_documents
    assert shown.uri == uri and shown.selection.start == lsp.Position(2, 4)


@pytest.mark.asyncio
async def test_the_preview_without_a_document_asks_the_editor_to_open_it(
        client: LanguageClient, tmp_path):
    uri = (tmp_path / "wave.gest").as_uri()
    await opened(client, uri, WAVE)
    client.text_document_did_change(lsp.DidChangeTextDocumentParams(
        lsp.VersionedTextDocumentIdentifier(uri=uri, version=2),
        [lsp.TextDocumentContentChangePartial(
            range=lsp.Range(lsp.Position(1, 12), lsp.Position(1, 12)), text="")]))
    answer = await asyncio.wait_for(client.workspace_execute_command_async(
        lsp.ExecuteCommandParams("gest.preview")), LIMIT)  # Helix: no arguments
    (shown,) = client.shown_documents
    assert shown.external and shown.uri == answer["url"]
