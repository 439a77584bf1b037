"""Places in the editor, through the language server driven by pytest-lsp: place names
completed after ``right hand to``, what each place solves to in a hover and an inlay
hint, the code action that writes it as servo values (the file then plays the same),
and a place out of reach told as it is typed."""

from __future__ import annotations

import pytest
from lsprotocol import types as lsp
from test_lsp import apply, changed, client, hovered, offered, opened, own, soon  # noqa: F401

from inmoov_dsl import compile_source

TEXT = ("robot inmoov\n"
        "place cup (350, -200, 300) mm\n"
        "offer: right hand to cup, r_thumb 120 over 2s\n")
#: test_lsp's client is one server a module: its tests run in the module's event loop
pytestmark = pytest.mark.asyncio(loop_scope="module")


async def test_a_place_is_completed_hovered_hinted_and_written_as_values(client, tmp_path):  # noqa: F811,E501
    uri = (tmp_path / "p.gest").as_uri()
    names = own(await offered(client, uri, TEXT + "g: right hand to |"))
    assert "cup" in names and "table" in names  # the file's and the profile's
    assert not {"r_thumb", "offer", "over"} & set(names)
    found = await opened(client, uri, TEXT)
    assert not [d for d in found if d.severity == lsp.DiagnosticSeverity.Error]
    said = await hovered(client, uri, 2, 10)
    assert said.startswith("**right hand to cup**: r_omoplate ")
    values = said.split("\n")[0].split(": ", 1)[1]
    hints = await soon(client.text_document_inlay_hint_async(lsp.InlayHintParams(
        text_document=lsp.TextDocumentIdentifier(uri=uri),
        range=lsp.Range(lsp.Position(2, 0), lsp.Position(3, 0)))))
    assert (2, f"= {values}") in [(h.position.line, h.label) for h in hints]
    actions = await soon(client.text_document_code_action_async(lsp.CodeActionParams(
        text_document=lsp.TextDocumentIdentifier(uri=uri),
        range=lsp.Range(lsp.Position(2, 0), lsp.Position(2, 0)),
        context=lsp.CodeActionContext(diagnostics=[]))))
    rewrite = next(a for a in actions if a.title == "Write 'right hand to cup' as servo values")
    assert rewrite.kind == lsp.CodeActionKind.RefactorRewrite
    written = apply(TEXT, rewrite.edit.changes[uri])
    assert written.split("\n")[2] == f"offer: {values}, r_thumb 120 over 2s"
    assert [bytes(s.data) for s in compile_source(written).streams] == \
        [bytes(s.data) for s in compile_source(TEXT).streams]  # it plays the same
    found = await changed(client, uri, 2, TEXT + "far: right hand to (2000, 0, 0) mm\n")
    far = [d for d in found if d.severity == lsp.DiagnosticSeverity.Error]
    assert [(d.range.start.line, d.range.start.character) for d in far] == [(3, 5)]
    assert "is out of reach" in far[0].message
