"""gestc lsp against what fuzzing an editor's messages found (pytest-lsp drives the real
server): documents with no file behind them (never saved, closed, an ``untitled:`` one,
one whose folder is not there), messages out of order or malformed (before
``initialize``, a change of a document never opened, a negative line), a range to the
largest line there is, characters Python takes for line ends and the protocol does not,
and a file near the largest the compiler reads, analysed while other requests are
answered. Each test asserts what an editor would notice: an answer (never an error
where an answer is due), the right diagnostics at the right places, no error shown to
the user, and the order answers come in; no time figure."""

import asyncio
import re
from pathlib import Path

import pytest
import pytest_lsp
from lsp_client import SERVER
from lsprotocol import types as lsp
from pygls.exceptions import JsonRpcException
from pytest_lsp import ClientServerConfig, LanguageClient, client_capabilities

LIMIT = 60.0  #: s for any answer, which a loaded machine meets (most take milliseconds)
LIBRARY = Path(__file__).parent.parent / "gestures"
TOP = 2_147_483_647  #: the largest line (and column) the protocol has


async def soon(awaited):
    """``awaited``'s result, or a failure after LIMIT seconds (never a hang)."""
    return await asyncio.wait_for(awaited, LIMIT)


@pytest_lsp.fixture(config=ClientServerConfig(server_command=SERVER))
async def client(lsp_client: LanguageClient):
    record(lsp_client)
    await lsp_client.initialize_session(lsp.InitializeParams(
        capabilities=client_capabilities("visual-studio-code")))
    yield
    await lsp_client.shutdown_session()
    assert not shown_errors(lsp_client)


@pytest_lsp.fixture(config=ClientServerConfig(server_command=SERVER))
async def fresh(lsp_client: LanguageClient):
    """A server not initialized yet: the test does it (``start``)."""
    record(lsp_client)
    lsp_client.started = False
    yield
    if lsp_client.started:
        await lsp_client.shutdown_session()
    else:
        lsp_client.exit(None)  # which the server reads before initialize too
    assert not shown_errors(lsp_client)


async def start(client: LanguageClient, folder: Path | None = None,
                capabilities: lsp.ClientCapabilities | None = None) -> lsp.InitializeResult:
    found = await client.initialize_session(lsp.InitializeParams(
        capabilities=capabilities or client_capabilities("visual-studio-code"),
        workspace_folders=None if folder is None else [
            lsp.WorkspaceFolder(folder.as_uri(), folder.name)]))
    client.started = True
    return found


def shown_errors(client: LanguageClient) -> list[str]:
    """The error messages the server put in front of the user (window/showMessage)."""
    return [m.message for m in client.messages if m.type == lsp.MessageType.Error]


def record(client: LanguageClient) -> None:
    """Keep every publishDiagnostics in order (pytest-lsp keeps each document's last):
    ``told`` reads them."""
    client.published, client.read = [], 0
    method = lsp.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS
    handler = client.protocol.fm.features[method]

    def both(params: lsp.PublishDiagnosticsParams) -> None:
        client.published.append(params)
        handler(params)

    client.protocol.fm.features[method] = both


async def told(client: LanguageClient, uri: str, version: int | None = None,
               skipped: list | None = None) -> list[lsp.Diagnostic]:
    """The next diagnostics of ``uri`` (of its ``version``, when given); ``skipped``
    gets the (uri, version) of the others told before them."""
    async def arrived() -> list[lsp.Diagnostic]:
        while True:
            while client.read < len(client.published):
                params = client.published[client.read]
                client.read += 1
                if params.uri == uri and version in (None, params.version):
                    return list(params.diagnostics)
                if skipped is not None:
                    skipped.append((params.uri, params.version))
            await asyncio.sleep(0.01)

    return await soon(arrived())


def open_(client: LanguageClient, uri: str, text: str, version: int = 1) -> None:
    client.text_document_did_open(lsp.DidOpenTextDocumentParams(
        lsp.TextDocumentItem(uri=uri, language_id="gest", version=version, text=text)))


def change(client: LanguageClient, uri: str, version: int, *changes) -> None:
    client.text_document_did_change(lsp.DidChangeTextDocumentParams(
        lsp.VersionedTextDocumentIdentifier(uri=uri, version=version), list(changes)))


def edit(line: int, start: int, end: int, text: str) -> lsp.TextDocumentContentChangePartial:
    """An incremental change on one line, as an editor sends a keystroke."""
    return lsp.TextDocumentContentChangePartial(
        range=lsp.Range(lsp.Position(line, start), lsp.Position(line, end)), text=text)


def at(uri: str, line: int, character: int) -> dict:
    return {"text_document": lsp.TextDocumentIdentifier(uri),
            "position": lsp.Position(line, character)}


def places(found) -> list[tuple]:
    return sorted((d.range.start.line, d.range.start.character, d.range.end.character,
                   d.message.split("\n")[0]) for d in found)


# -- 1. documents with no file behind them ---------------------------------------------
@pytest.mark.asyncio
async def test_an_untitled_document_that_uses_a_file(fresh, tmp_path):
    client = fresh
    await start(client, tmp_path)  # the workspace: where an untitled document would go
    (tmp_path / "moves.gest").write_text("pose half: fingers 90\n")
    uri = "untitled:Untitled-1"
    open_(client, uri, 'use "moves.gest"\ng: half\nh: g\n')
    assert await told(client, uri) == []  # moves.gest is found, beside it in the folder
    moves = (tmp_path / "moves.gest").as_uri()
    there = await soon(client.text_document_definition_async(
        lsp.DefinitionParams(**at(uri, 1, 4))))
    assert (there.uri, there.range.start.line, there.range.start.character) == (moves, 0, 5)
    here = await soon(client.text_document_definition_async(
        lsp.DefinitionParams(**at(uri, 2, 3))))
    assert (here.uri, here.range.start.line) == (uri, 1)  # defined in the document itself
    found = await soon(client.text_document_references_async(lsp.ReferenceParams(
        context=lsp.ReferenceContext(include_declaration=True), **at(uri, 1, 4))))
    assert sorted((r.uri, r.range.start.line) for r in found) == [(moves, 0), (uri, 1)]


@pytest.mark.asyncio
async def test_an_untitled_document_without_a_folder_finds_the_library(client):
    uri = "untitled:Untitled-2"
    open_(client, uri, 'use "peace.gest"\ng: peace\n')
    assert await told(client, uri) == []
    there = await soon(client.text_document_definition_async(
        lsp.DefinitionParams(**at(uri, 1, 4))))
    assert there.uri == (LIBRARY / "peace.gest").resolve().as_uri()
    found = await soon(client.text_document_references_async(lsp.ReferenceParams(
        context=lsp.ReferenceContext(include_declaration=True), **at(uri, 1, 4))))
    assert (uri, 1) in [(r.uri, r.range.start.line) for r in found]


@pytest.mark.asyncio
async def test_references_in_a_document_whose_folder_is_not_there(client, tmp_path):
    uri = (tmp_path / "not-yet" / "new.gest").as_uri()
    open_(client, uri, "g: index 90\nh: g\ni:\n    g  # g again\n")
    assert await told(client, uri) == []
    found = await soon(client.text_document_references_async(lsp.ReferenceParams(
        context=lsp.ReferenceContext(include_declaration=True), **at(uri, 1, 3))))
    assert sorted((r.range.start.line, r.range.start.character) for r in found) == [
        (0, 0), (1, 3), (3, 4)]


@pytest.mark.asyncio
async def test_every_request_about_a_document_closed_before_it_was_saved(client, tmp_path):
    uri = (tmp_path / "never-saved.gest").as_uri()
    open_(client, uri, "a: indx 90\n")
    assert len(await told(client, uri)) == 1
    client.text_document_did_close(lsp.DidCloseTextDocumentParams(
        lsp.TextDocumentIdentifier(uri)))
    assert await told(client, uri) == []  # its diagnostics cleared
    ident, everything = lsp.TextDocumentIdentifier(uri), lsp.Range(lsp.Position(0, 0),
                                                                   lsp.Position(9, 0))
    assert await soon(client.text_document_hover_async(lsp.HoverParams(**at(uri, 0, 4)))) \
        is None
    assert await soon(client.text_document_definition_async(
        lsp.DefinitionParams(**at(uri, 0, 4)))) is None
    listed = await soon(client.text_document_completion_async(
        lsp.CompletionParams(**at(uri, 0, 4))))
    assert not listed.items
    for answer in await asyncio.gather(*(soon(request) for request in (
            client.text_document_references_async(lsp.ReferenceParams(
                context=lsp.ReferenceContext(include_declaration=True), **at(uri, 0, 4))),
            client.text_document_document_symbol_async(lsp.DocumentSymbolParams(ident)),
            client.text_document_inlay_hint_async(lsp.InlayHintParams(ident, everything)),
            client.text_document_code_action_async(lsp.CodeActionParams(
                ident, everything, lsp.CodeActionContext(diagnostics=[])))))):
        assert list(answer) == []
    tokens = await soon(client.text_document_semantic_tokens_full_async(
        lsp.SemanticTokensParams(ident)))
    assert not tokens.data
    assert await soon(client.text_document_formatting_async(lsp.DocumentFormattingParams(
        ident, lsp.FormattingOptions(4, True)))) is None


# -- 2. messages out of order, or malformed ----------------------------------------------
@pytest.mark.asyncio
async def test_before_initialize_a_request_is_told_the_server_is_not_initialized(fresh,
                                                                                 tmp_path):
    client = fresh
    uri = (tmp_path / "early.gest").as_uri()
    with pytest.raises(JsonRpcException) as raised:  # (pytest-lsp's own check let by)
        await soon(asyncio.wrap_future(client.protocol.send_request(
            lsp.TEXT_DOCUMENT_HOVER, lsp.HoverParams(**at(uri, 0, 0)))))
    assert raised.value.code == lsp.ErrorCodes.ServerNotInitialized == -32002
    open_(client, uri, "a: indx 90\n")  # dropped, as the protocol says
    await start(client)
    assert await soon(client.text_document_hover_async(lsp.HoverParams(**at(uri, 0, 3)))) \
        is None  # the document is not open: the open before initialize was dropped
    # the editor believes it open: its next change, a whole text, is taken
    change(client, uri, 2, lsp.TextDocumentContentChangeWholeDocument(text="a: indx 90\n"))
    assert places(await told(client, uri, 2)) == [(0, 3, 7, "unknown servo or group "
                                                            "'indx'")]


@pytest.mark.asyncio
async def test_a_change_of_a_document_never_opened(client, tmp_path):
    uri = (tmp_path / "stray.gest").as_uri()
    change(client, uri, 5, edit(0, 0, 0, "a: index 90\n"))  # nothing to make it on
    other = (tmp_path / "other.gest").as_uri()
    open_(client, other, "b: thum 90\n")
    assert len(await told(client, other)) == 1  # the stray change told nothing
    assert uri not in client.diagnostics
    assert any("not open" in m.message and uri in m.message for m in client.log_messages)
    assert await soon(client.text_document_hover_async(lsp.HoverParams(**at(uri, 0, 3)))) \
        is None
    change(client, uri, 6, lsp.TextDocumentContentChangeWholeDocument(text="a: indx 9\n"))
    assert len(await told(client, uri, 6)) == 1  # a whole text is taken: it is open now
    change(client, uri, 7, edit(0, 3, 7, "index"))
    assert await told(client, uri, 7) == []


@pytest.mark.asyncio
async def test_a_request_with_invalid_params_is_answered_invalid_params(client, tmp_path):
    uri = (tmp_path / "p.gest").as_uri()
    open_(client, uri, "g: index 90\n")
    assert await told(client, uri) == []
    params = lsp.HoverParams(**at(uri, 0, 4))
    object.__setattr__(params.position, "line", -1)  # what lsprotocol would not build
    with pytest.raises(JsonRpcException) as raised:
        await soon(client.text_document_hover_async(params))
    assert raised.value.code == lsp.ErrorCodes.InvalidParams == -32602
    assert "Position.line" in raised.value.message
    said = await soon(client.text_document_hover_async(lsp.HoverParams(**at(uri, 0, 4))))
    assert said.contents.value.startswith("**servo index**")  # and the server goes on


# -- 3. a range to the largest line -----------------------------------------------------
@pytest.mark.asyncio
async def test_a_range_to_the_largest_line_costs_what_the_text_holds(client, tmp_path):
    uri = (tmp_path / "r.gest").as_uri()
    open_(client, uri, "a: indx 90\nb: index 180 over 0.05s\n")
    assert len(await told(client, uri)) == 2
    ident = lsp.TextDocumentIdentifier(uri)
    everything = lsp.Range(lsp.Position(0, 0), lsp.Position(TOP, TOP))
    actions = await soon(client.text_document_code_action_async(lsp.CodeActionParams(
        ident, everything, lsp.CodeActionContext(diagnostics=[]))))
    assert [a.title for a in actions] == ["Change to 'index'",
                                          "Ask for 0.52 s, the time the limits need"]
    backwards = lsp.Range(lsp.Position(TOP, 0), lsp.Position(1, 0))
    actions = await soon(client.text_document_code_action_async(lsp.CodeActionParams(
        ident, backwards, lsp.CodeActionContext(diagnostics=[]))))
    assert [a.title for a in actions] == ["Ask for 0.52 s, the time the limits need"]
    hints = await soon(client.text_document_inlay_hint_async(lsp.InlayHintParams(
        ident, everything)))
    assert sorted(h.position.line for h in hints) == [1]
    far = at(uri, TOP, TOP)
    assert await soon(client.text_document_hover_async(lsp.HoverParams(**far))) is None
    assert not (await soon(client.text_document_completion_async(
        lsp.CompletionParams(**far)))).items
    said = await soon(client.text_document_hover_async(lsp.HoverParams(**at(uri, 1, 4))))
    assert said.contents.value.startswith("**servo index**")


# -- 4. the protocol's line ends, not Python's ------------------------------------------
NOT_ENDS = "\u2028\f\x85\x1c\u2029\x1d\x1e\v"  #: str.splitlines splits on each of these


@pytest.mark.asyncio
async def test_characters_python_takes_for_line_ends_are_not_line_ends(client, tmp_path):
    uri = (tmp_path / "ends.gest").as_uri()
    text = f"# a comment{NOT_ENDS}with them all\ng: indx 90  # {NOT_ENDS}\nh: g\n"
    open_(client, uri, text)
    assert places(await told(client, uri, 1)) == [(1, 3, 7, "unknown servo or group "
                                                            "'indx'")]
    change(client, uri, 2, edit(1, 3, 7, "index"))  # on the line the editor sees
    assert await told(client, uri, 2) == []  # the server's text is the editor's
    change(client, uri, 3, edit(2, 3, 4, "h"))  # h: h
    assert places(await told(client, uri, 3)) == [
        (2, 3, 4, "gesture 'h' calls itself: h -> h")]
    said = await soon(client.text_document_hover_async(lsp.HoverParams(**at(uri, 1, 4))))
    assert said.contents.value.startswith("**servo index**")
    change(client, uri, 4, edit(2, 3, 4, "g"), edit(0, 0, 0, "g2:   index   9\n"))
    assert await told(client, uri, 4) == []
    edits = await soon(client.text_document_formatting_async(lsp.DocumentFormattingParams(
        lsp.TextDocumentIdentifier(uri), lsp.FormattingOptions(4, True))))
    assert edits[0].new_text.startswith(f"g2: index 9\n# a comment{NOT_ENDS}with them all\n")
    assert (edits[0].range.end.line, edits[0].range.end.character) == (4, 0)


@pytest.mark.asyncio
async def test_a_lone_carriage_return_is_a_line_end_to_the_editor(client, tmp_path):
    uri = (tmp_path / "cr.gest").as_uri()
    open_(client, uri, "a: index 90\rb: index 90\nc: thum 9\n")  # the compiler: 2 lines
    assert places(await told(client, uri)) == [
        (0, 11, 12, "unexpected character U+000D"),  # at the end of the editor's line 0
        (2, 3, 7, "unknown servo or group 'thum'")]  # on the editor's line 2
    change(client, uri, 2, edit(2, 3, 7, "thumb"))
    assert places(await told(client, uri, 2)) == [(0, 11, 12, "unexpected character "
                                                              "U+000D")]


@pytest.mark.asyncio
async def test_columns_are_code_points_when_the_editor_offers_them(fresh, tmp_path):
    client = fresh
    capabilities = client_capabilities("neovim")  # which offers UTF-8 first
    capabilities.general = lsp.GeneralClientCapabilities(position_encodings=[
        lsp.PositionEncodingKind.Utf8, lsp.PositionEncodingKind.Utf16,
        lsp.PositionEncodingKind.Utf32])
    found = await start(client, capabilities=capabilities)
    assert found.capabilities.position_encoding == lsp.PositionEncodingKind.Utf32
    uri = (tmp_path / "wide.gest").as_uri()
    open_(client, uri, 'g:   indx 90  # \U0001f600 é\nh: thum 9  # é \U0001f600 é\n')
    assert [d.range.start.character for d in await told(client, uri)] == [5, 3]
    change(client, uri, 2, edit(1, 17, 17, "!"))  # after the emoji: a code point each
    change(client, uri, 3, edit(1, 3, 7, "thumb"))
    assert places(await told(client, uri, 3)) == [(0, 5, 9, "unknown servo or group "
                                                            "'indx'")]
    said = await soon(client.text_document_hover_async(lsp.HoverParams(**at(uri, 1, 4))))
    assert said.contents.value.startswith("**servo thumb**")
    edits = await soon(client.text_document_formatting_async(lsp.DocumentFormattingParams(
        lsp.TextDocumentIdentifier(uri), lsp.FormattingOptions(4, True))))
    assert edits[0].new_text.endswith("h: thumb 9  # é \U0001f600 !é\n")


# -- 5. a file near the largest the compiler reads ---------------------------------------
def long_file(gestures: int) -> str:
    """``gestures`` one-line gestures: the library's, each name numbered, over and over."""
    rows = [row for path in sorted(LIBRARY.glob("*.gest"))
            for row in path.read_text().split("\n") if re.match(r"^\w+: \w+ \d", row)]
    return "".join(f"{rows[k % len(rows)].replace(':', f'_{k}:', 1)}\n"
                   for k in range(gestures))


LONG = 3000  #: gestures: seconds of checking, while the other requests are answered


@pytest.mark.asyncio
async def test_requests_are_answered_while_a_long_file_is_analysed(client, tmp_path):
    uri = (tmp_path / "long.gest").as_uri()
    text = long_file(LONG)
    order: list[str] = []
    open_(client, uri, text)
    hover = asyncio.ensure_future(client.text_document_hover_async(
        lsp.HoverParams(**at(uri, 0, 1))))
    hover.add_done_callback(lambda _: order.append("hover"))
    fixes = asyncio.wrap_future(client.protocol.send_request(  # waits for the checks
        lsp.TEXT_DOCUMENT_CODE_ACTION, lsp.CodeActionParams(
            lsp.TextDocumentIdentifier(uri), lsp.Range(lsp.Position(0, 0),
                                                       lsp.Position(0, 0)),
            lsp.CodeActionContext(diagnostics=[])), msg_id="fixes"))
    small = (tmp_path / "small.gest").as_uri()  # another document, opened meanwhile
    open_(client, small, "s: indx 9\n")
    assert len(await told(client, small)) == 1
    order.append("small")
    client.cancel_request(lsp.CancelParams(id="fixes"))  # the editor gives up on it
    with pytest.raises(JsonRpcException) as raised:
        await soon(fixes)
    assert raised.value.code == lsp.LSPErrorCodes.RequestCancelled
    order.append("cancelled")
    assert await told(client, uri) == []
    order.append("long")
    assert (await soon(hover)).contents.value.startswith("**gesture ")
    # none waited for the long file (the hover and the other document's diagnostics come
    # in either order: the hover waits for the long file's loading, the other's check
    # for its turn)
    assert order[-1] == "long" and sorted(order[:-1]) == ["cancelled", "hover", "small"]


@pytest.mark.asyncio
async def test_a_newer_version_of_a_long_file_supersedes_the_older(client, tmp_path):
    uri = (tmp_path / "long.gest").as_uri()
    text = long_file(LONG)
    open_(client, uri, text)
    last = text.count("\n")
    change(client, uri, 2, edit(last, 0, 0, "x: indx 9\n"))
    change(client, uri, 3, edit(last, 3, 7, "index"), edit(last + 1, 0, 0, "y: thum 9\n"))
    skipped: list = []
    assert places(await told(client, uri, 3, skipped)) == [
        (last + 1, 3, 7, "unknown servo or group 'thum'")]
    small = (tmp_path / "small.gest").as_uri()
    open_(client, small, "s: index 9\n")
    assert await told(client, small, skipped=skipped) == []
    assert skipped == []  # the older versions never told, nor anything after the newest
    ident = lsp.TextDocumentIdentifier(uri)
    actions = await soon(client.text_document_code_action_async(lsp.CodeActionParams(
        ident, lsp.Range(lsp.Position(last + 1, 0), lsp.Position(last + 1, 0)),
        lsp.CodeActionContext(diagnostics=[]))))
    assert [a.title for a in actions] == ["Change to 'thumb'"]
