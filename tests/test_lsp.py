"""gestc lsp, driven by a client we did not write (pytest-lsp) with the capabilities of
VS Code and of Neovim: diagnostics as the text changes, with gestc check's wording,
places and hints; formatting by gestc fmt's rules."""

import sys

import pytest
import pytest_lsp
from lsprotocol import types as lsp
from pytest_lsp import ClientServerConfig, LanguageClient, client_capabilities

SERVER = [sys.executable, "-m", "inmoov_dsl.cli.gestc", "lsp"]


@pytest_lsp.fixture(config=ClientServerConfig(server_command=SERVER),
                    params=["visual-studio-code", "neovim"])
async def client(request, lsp_client: LanguageClient):
    await lsp_client.initialize_session(
        lsp.InitializeParams(capabilities=client_capabilities(request.param)))
    yield
    await lsp_client.shutdown_session()


async def opened(client: LanguageClient, uri: str, text: str) -> list[lsp.Diagnostic]:
    client.text_document_did_open(lsp.DidOpenTextDocumentParams(
        lsp.TextDocumentItem(uri=uri, language_id="gest", version=1, text=text)))
    await client.wait_for_notification(lsp.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    return client.diagnostics[uri]


@pytest.mark.asyncio
async def test_every_error_as_it_is_typed_and_gone_once_fixed(client, tmp_path):
    uri = (tmp_path / "typos.gest").as_uri()
    found = await opened(client, uri, "a: indx 90, midle 90\nb: thum 90\nc: ring 90\n")
    assert [(d.range.start.line, d.range.start.character, d.range.end.character,
             d.severity) for d in found] == [(0, 3, 7, lsp.DiagnosticSeverity.Error),
                                             (0, 12, 17, lsp.DiagnosticSeverity.Error),
                                             (1, 3, 7, lsp.DiagnosticSeverity.Error)]
    assert found[0].message == ("unknown servo or group 'indx'\nhint: did you mean "
                                "'index'?")
    # typed, not saved: the first line fixed
    client.text_document_did_change(lsp.DidChangeTextDocumentParams(
        lsp.VersionedTextDocumentIdentifier(uri=uri, version=2),
        [lsp.TextDocumentContentChangeWholeDocument(
            text="a: index 90, middle 90\nb: thum 90\nc: ring 90\n")]))
    await client.wait_for_notification(lsp.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    assert [d.range.start.line for d in client.diagnostics[uri]] == [1]
    # a syntax error in one gesture does not hide another's
    found = await opened(client, (tmp_path / "syntax.gest").as_uri(),
                         "a: index 90 ove 1s\nb: index 9x\n")
    assert [(d.range.start.line, d.range.start.character) for d in found] == [(0, 12),
                                                                              (1, 10)]
    assert found[0].message.endswith("hint: did you mean 'over'?")


@pytest.mark.asyncio
async def test_formatting_is_gestc_fmt(client, tmp_path):
    uri = (tmp_path / "f.gest").as_uri()
    assert not await opened(client, uri, "g:\n  index   90  over 1s\n")
    edits = await client.text_document_formatting_async(lsp.DocumentFormattingParams(
        lsp.TextDocumentIdentifier(uri=uri), lsp.FormattingOptions(tab_size=4,
                                                                   insert_spaces=True)))
    assert [e.new_text for e in edits] == ["g:\n    index 90 over 1s\n"]


@pytest.mark.asyncio
async def test_hover_and_completion_know_the_robot(client, tmp_path):
    uri = (tmp_path / "h.gest").as_uri()
    text = "pose half: fingers 90\ng: half, wrist 30 over 1s\n"
    assert not await opened(client, uri, text)

    async def hovered(line, character):
        said = await client.text_document_hover_async(lsp.HoverParams(
            lsp.TextDocumentIdentifier(uri=uri), lsp.Position(line, character)))
        return said.contents.value

    assert (await hovered(1, 10)).startswith("**servo wrist** (profile rhand): board 181 "
                                             "(right hand), pin 2; values 0..180, rest 0")
    assert await hovered(0, 12) == "**group fingers**: thumb, index, middle, ring, pinky"
    assert await hovered(1, 4) == "**pose half**: fingers 90"
    assert await hovered(1, 0) == "**gesture g**: 1 step, 1.00 s as planned"
    listed = await client.text_document_completion_async(lsp.CompletionParams(
        lsp.TextDocumentIdentifier(uri=uri), lsp.Position(1, 3)))
    items = {i.label: i.detail for i in listed.items}
    assert {"wrist": "servo", "fingers": "group", "half": "pose", "g": "gesture",
            "over": "keyword", "ms": "unit"}.items() <= items.items()


@pytest.mark.asyncio
async def test_definition_references_and_outline(client, tmp_path):
    (tmp_path / "moves.gest").write_text("pose half: fingers 90\n")
    uri = (tmp_path / "main.gest").as_uri()
    text = ('use "moves.gest"\ngroup two: index, middle\ng: half, two 30 over 1s\n'
            'h:\n    g  # g again\n    half\n')
    assert not await opened(client, uri, text)

    async def defined(line, character):
        return await client.text_document_definition_async(lsp.DefinitionParams(
            lsp.TextDocumentIdentifier(uri=uri), lsp.Position(line, character)))

    there = await defined(2, 4)  # 'half', in the file main uses
    assert there.uri == (tmp_path / "moves.gest").as_uri()
    assert (there.range.start.line, there.range.start.character) == (0, 5)
    here = await defined(4, 4)  # 'g', in this file
    assert here.uri == uri and here.range.start.line == 2
    found = await client.text_document_references_async(lsp.ReferenceParams(
        context=lsp.ReferenceContext(include_declaration=True),
        text_document=lsp.TextDocumentIdentifier(uri=uri), position=lsp.Position(2, 4)))
    assert sorted((r.range.start.line, r.range.start.character) for r in found) == [
        (2, 3), (5, 4)]  # not in the comment
    symbols = await client.text_document_document_symbol_async(lsp.DocumentSymbolParams(
        lsp.TextDocumentIdentifier(uri=uri)))
    assert [(s.name, s.detail) for s in symbols] == [("two", "group"), ("g", "gesture"),
                                                     ("h", "gesture")]
