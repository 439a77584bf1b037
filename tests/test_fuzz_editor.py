"""The editor's side of the compiler never fails on what is typed: the gesture fuzzer's
seeded mutants of the library, each analysed and asked every question an editor asks
(hover and completion everywhere on a line, definition, references, outline, inlay
hints, fixes, semantic tokens), and fed to a running ``gestc lsp`` as edits: diagnostics
each time, never an exception, a hang or a dead server."""

import asyncio
import random
import sys

import pytest
import pytest_lsp
from lsprotocol import types as lsp
from mutate import mutate, seeds, within
from pytest_lsp import ClientServerConfig, LanguageClient, client_capabilities

from inmoov_dsl.editor.actions import fixes
from inmoov_dsl.editor.analysis import analyse
from inmoov_dsl.editor.knowledge import completions, definition, hover, outline, references
from inmoov_dsl.editor.timing import step_times
from inmoov_dsl.editor.tokens import encoded, tokens

MUTANTS = 20  #: analysed and asked everything (about 4 s)
EDITS = 8  #: fed to the server (about 3 s)
LIMIT = 30.0  #: s per mutant, which a loaded machine meets (most take milliseconds; a
#: mutant of 3,000 lines whose 1,000 gestures call each other takes 6 s on an idle one)


@pytest.fixture(scope="module")
def library():
    return seeds()["gest"]


def ask_everything(text: str, path: str, rng: random.Random) -> None:
    found = analyse(text, path)
    for d in found.diagnostics:
        assert d.severity in ("error", "warning") and d.message
    lines = text.split("\n")
    for _ in range(4):
        line = rng.randrange(len(lines))
        column = rng.randrange(len(lines[line]) + 1)
        hover(found, line, column)
        completions(found, line, column)
        definition(found, line, column)
        fixes(found, line)
        references(text, "index")
    outline(found)
    step_times(found)
    data = encoded(tokens(found))
    assert len(data) % 5 == 0 and min(data, default=0) >= 0


def test_every_question_on_mutants_has_an_answer(library, tmp_path):
    problems = []
    for n in range(MUTANTS):
        rng = random.Random(f"editor:{n}")
        seed = rng.choice(library)
        text = mutate(seed.data, rng, "gest").decode("utf-8", "replace")
        path = str(tmp_path / seed.name.split("/")[-1])
        try:
            within(LIMIT, lambda text=text, path=path, rng=rng: ask_everything(text, path,
                                                                               rng))
        except BaseException as exc:  # noqa: BLE001 - what we are looking for
            problems.append(f"mutant {n} of {seed.name}: {type(exc).__name__}: {exc}"[:300])
    assert not problems, "\n".join(problems[:5])


SERVER = [sys.executable, "-m", "inmoov_dsl.cli.gestc", "lsp"]


@pytest_lsp.fixture(config=ClientServerConfig(server_command=SERVER))
async def client(lsp_client: LanguageClient):
    await lsp_client.initialize_session(lsp.InitializeParams(
        capabilities=client_capabilities("visual-studio-code")))
    yield
    await lsp_client.shutdown_session()


@pytest.mark.asyncio
async def test_the_server_takes_mutants_as_edits(client, library, tmp_path):
    uri = (tmp_path / "typed.gest").as_uri()
    client.text_document_did_open(lsp.DidOpenTextDocumentParams(lsp.TextDocumentItem(
        uri=uri, language_id="gest", version=1, text="")))
    await asyncio.wait_for(client.wait_for_notification(
        lsp.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS), LIMIT * 4)
    told = 0
    for n in range(EDITS):
        rng = random.Random(f"edits:{n}")
        text = mutate(rng.choice(library).data, rng, "gest").decode("utf-8", "replace")
        client.text_document_did_change(lsp.DidChangeTextDocumentParams(
            lsp.VersionedTextDocumentIdentifier(uri=uri, version=n + 2),
            [lsp.TextDocumentContentChangeWholeDocument(text=text)]))
        await asyncio.wait_for(client.wait_for_notification(
            lsp.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS), LIMIT * 4)
        told += len(client.diagnostics[uri])
        last = len(text.split("\n")) - 1
        where = lsp.Range(lsp.Position(0, 0), lsp.Position(last, 0))
        ident = lsp.TextDocumentIdentifier(uri=uri)
        for request in (
                client.text_document_hover_async(lsp.HoverParams(ident, lsp.Position(
                    rng.randrange(last + 1), rng.randrange(12)))),
                client.text_document_inlay_hint_async(lsp.InlayHintParams(ident, where)),
                client.text_document_code_action_async(lsp.CodeActionParams(
                    ident, where, lsp.CodeActionContext(diagnostics=[]))),
                client.text_document_semantic_tokens_full_async(
                    lsp.SemanticTokensParams(ident))):
            await asyncio.wait_for(request, LIMIT * 4)  # an answer, not an error
    assert told > 0  # the mutants do have problems, and the server told them
    assert not client.error
