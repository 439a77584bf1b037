"""The language server feeds the live preview page (issue 44) and checks collisions
(issue 43), driven by a client the project did not write (pytest-lsp) and the page read
in Debian's chromium, headless (tests/test_live_preview.py's helpers): ``gest.preview``
gives the page's address, an edit the client sends reaches the page, the cursor the
client tells (``gest/cursor``) highlights its step, a step clicked on the page makes the
server send ``window/showDocument`` to the client; a gesture that drives the InMoov
into itself is a warning at its step."""

from __future__ import annotations

import asyncio
import time

import pytest
from lsprotocol import types as lsp
from pytest_lsp import LanguageClient
from test_live_preview import STEPS, browser, js, steps_on, until  # noqa: F401 (fixture)

LIMIT = 120.0  #: s for any answer or page change, which a loaded machine meets
WAVE = """wave:
    fingers 0 over 0.7s
    wrist 180 over 0.4s
    wrist 0 over 0.4s
"""


async def opened(client: LanguageClient, uri: str, text: str) -> list[lsp.Diagnostic]:
    client.text_document_did_open(lsp.DidOpenTextDocumentParams(
        lsp.TextDocumentItem(uri=uri, language_id="gest", version=1, text=text)))
    await asyncio.wait_for(client.wait_for_notification(
        lsp.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS), LIMIT)
    return client.diagnostics[uri]


async def told(client: LanguageClient, uri: str, what: str) -> lsp.Diagnostic:
    """The diagnostic of ``uri`` whose message has ``what``, once the server tells it
    (a contact is told after the rest of the diagnostics, when it is found)."""
    deadline = time.monotonic() + LIMIT
    while time.monotonic() < deadline:
        if found := [d for d in client.diagnostics.get(uri, []) if what in d.message]:
            (one,) = found
            return one
        await asyncio.sleep(0.05)
    pytest.fail(f"the server did not tell {what!r} in {LIMIT} s")


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
    await opened(client, uri, "robot inmoov\n\nelbow:\n    r_rotate 125 over 1.5s\n"
                              "    r_bicep 143 over 2s\n")
    contact = await told(client, uri, "enters the chest")
    assert contact.severity == lsp.DiagnosticSeverity.Warning
    assert contact.range.start == lsp.Position(4, 4)  # the step that drives it there
    assert contact.message.startswith("at ") and "the right forearm" in contact.message


def test_a_long_motions_contacts_are_looked_for_in_steps_and_kept(tmp_path):
    """The server tells a text's diagnostics, then its contacts (``touched``): a long
    motion's look is cut short within it when a newer text comes, and is not made
    again for an edit elsewhere."""
    pytest.importorskip("fcl", reason="the [collide] extra brings python-fcl")
    from inmoov_dsl.editor.analysis import checked, loaded, touched
    from inmoov_dsl.editor.memo import Memo

    class Newer(Exception):
        pass

    path, memo = str(tmp_path / "long.gest"), Memo()
    reach = ("robot inmoov\n\nreach:\n    repeat 12:\n"
             "        r_bicep 96, r_rotate 32 over 2s\n"
             "        r_shoulder 135, r_omoplate 151 over 3s\n"
             "        r_shoulder 30, r_omoplate 10, r_bicep 5 over 2s\n")
    found = checked(loaded(reach, path, memo=memo), memo)
    assert found.plans["reach"].duration > 60
    assert not [d for d in found.diagnostics if "enters" in d.message]  # not yet
    asked = []

    def newer_at_third() -> None:
        asked.append(1)
        if len(asked) == 3:
            raise Newer

    with pytest.raises(Newer):
        touched(found, memo, newer_at_third)  # the one gesture: stopped within its plan
    asked.clear()
    whole = touched(found, memo, lambda: asked.append(1))
    assert len(asked) > 40  # a long motion's (84 s) look can be stopped every second of it
    assert [d for d in whole.diagnostics if "the right upper arm enters the chest" in d.message]
    assert any("enters" in d.message for d in whole.plans["reach"].warnings)

    asked.clear()  # a gesture added below: only its own (a second of motion) looked at
    again = checked(loaded(reach + "\nrest:\n    r_bicep 5 over 1s\n", path, memo=memo), memo)
    told = touched(again, memo, lambda: asked.append(1))
    assert len(asked) <= 3 and "rest" in told.plans  # (not the 84 s of reach again)
    assert [d.message for d in told.diagnostics if "enters" in d.message] == \
        [d.message for d in whole.diagnostics if "enters" in d.message]


def test_contacts_wait_for_the_text_to_stay_the_same(tmp_path):
    """A version whose next comes before it has stayed the same for a moment (a person
    typing) gets its diagnostics, not its contacts looked for: the newest does."""
    pytest.importorskip("fcl", reason="the [collide] extra brings python-fcl")
    import threading

    from inmoov_dsl.editor.memo import Memo
    from inmoov_dsl.editor.worker import Job, Worker

    class Looking(Memo):  # which texts' contacts were looked for
        def touch(self, program, check, step=None):
            looked.append(program.texts[path][-3:-1])
            return super().touch(program, check, step)

    told, looked, checked, done = [], [], threading.Event(), threading.Event()
    path = str(tmp_path / "elbow.gest")
    memo = Looking()
    text = "robot inmoov\n\nelbow:\n    r_rotate 125 over 1.5s\n    r_bicep 143 over 2s\n"

    def deliver(job: Job, found) -> None:
        told.append((job.text[-3:-1], found.checked,
                     sum("enters the chest" in d.message for d in found.diagnostics)))
        (checked if len(told) == 2 else done if len(told) == 5 else threading.Event()).set()

    worker = Worker(deliver, still=LIMIT)  # the first waits as long as a test may
    worker.submit(Job("u", text, path, "inmoov", (), memo))
    assert checked.wait(LIMIT)
    worker.still = 0  # the next is still at once
    worker.submit(Job("u", text.replace("2s", "3s"), path, "inmoov", (), memo))
    assert done.wait(LIMIT)
    assert told == [("2s", False, 0), ("2s", True, 0),
                    ("3s", False, 0), ("3s", True, 0), ("3s", True, 1)]
    assert looked == ["3s"]  # the first's never looked for, not even begun


def test_another_document_s_diagnostics_do_not_wait_for_the_contacts(tmp_path):
    """While a document waits to be still before its contacts are looked for, another
    document opened meanwhile is checked and told at once."""
    pytest.importorskip("fcl", reason="the [collide] extra brings python-fcl")
    import threading

    from inmoov_dsl.editor.memo import Memo
    from inmoov_dsl.editor.worker import Job, Worker

    told, first, other = [], threading.Event(), threading.Event()
    elbow = "robot inmoov\n\nelbow:\n    r_rotate 125 over 1.5s\n    r_bicep 143 over 2s\n"

    def deliver(job: Job, found) -> None:
        told.append((job.uri, found.checked, len(found.diagnostics)))
        if found.checked:
            (first if job.uri == "a" else other).set()

    worker = Worker(deliver, still=LIMIT)  # the first waits as long as a test may
    worker.submit(Job("a", elbow, str(tmp_path / "a.gest"), "inmoov", (), Memo()))
    assert first.wait(LIMIT)
    worker.submit(Job("b", "s: indx 9\n", str(tmp_path / "b.gest"), "rhand", (), Memo()))
    assert other.wait(LIMIT)  # not after the first one's wait
    worker.stop("a")
    assert told == [("a", False, 0), ("a", True, 0), ("b", False, 0), ("b", True, 1)]


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
