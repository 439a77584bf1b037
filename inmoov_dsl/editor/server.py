"""The language server's edge (pygls): the documents as the editor opens, changes and
closes them (``documents.GestServer``, ``store``), each analysed in the worker's thread
and its diagnostics published; every request answered there from the newest analysis
(``replies``), the loop free meanwhile: it answers whatever comes while a long file is
analysed. A request about a document that is not open gets the empty answer."""

from __future__ import annotations

import asyncio
import functools
import gc
import sys
from typing import Any

from lsprotocol import types as lsp

from ..errors import GestError
from .documents import GestServer
from .replies import (
    actions,
    coloured,
    completed,
    defined,
    formatted,
    hints,
    hovered,
    outlined,
    referenced,
)
from .store import document_path
from .tokens import MODIFIERS, TYPES

LEGEND = lsp.SemanticTokensLegend(list(TYPES), list(MODIFIERS))
PREVIEW = "gest.preview"  #: the command that opens the live preview page
CURSOR = "gest/cursor"  #: the editor's cursor, for the page (docs/editors.md)

server = GestServer()


@server.feature(lsp.INITIALIZE)
def initialize(ls: GestServer, params: lsp.InitializeParams) -> None:
    """Read the settings the client starts the server with, how it counts columns, and
    the folder a document that is not a file is taken to be in."""
    ls.configure(params.initialization_options)
    encoding = ls.workspace.position_encoding
    ls.documents.encoding = str(getattr(encoding, "value", encoding))
    folders = [f.uri for f in params.workspace_folders or ()] + [params.root_uri or ""]
    root = next((document_path(u) for u in folders if u.startswith("file:")), None)
    ls.documents.root = root or params.root_path


@server.feature(lsp.WORKSPACE_DID_CHANGE_CONFIGURATION)
def did_change_configuration(ls: GestServer, params: lsp.DidChangeConfigurationParams
                             ) -> None:
    """New settings: every open document analysed again (its diagnostics again)."""
    ls.configure(params.settings)
    for doc in list(ls.documents.open.values()):
        ls.analyse(doc)


@server.feature(lsp.TEXT_DOCUMENT_DID_OPEN)
def did_open(ls: GestServer, params: lsp.DidOpenTextDocumentParams) -> None:
    """A document opened: kept as the editor sent it, and analysed."""
    item = params.text_document
    ls.analyse(ls.documents.opened(item.uri, item.version, item.text))


@server.feature(lsp.TEXT_DOCUMENT_DID_CHANGE)
def did_change(ls: GestServer, params: lsp.DidChangeTextDocumentParams) -> None:
    """A document changed (typed, not only saved): analysed again. A change of a
    document that is not open is taken when it brings the whole text (the editor
    believes it open: its ``didOpen`` was lost, or sent before ``initialize``), else
    logged and left: an incremental change has no text to be made on."""
    ident = params.text_document
    was_open = ls.documents.get(ident.uri) is not None
    doc = ls.documents.changed(ident.uri, ident.version, params.content_changes)
    if not was_open:
        ls.window_log_message(lsp.LogMessageParams(lsp.MessageType.Warning, (
            f"didChange of {ident.uri}, which is not open: " +
            ("its whole text taken" if doc else "no whole text in it, left"))))
    if doc is not None:
        ls.analyse(doc)
        change = params.content_changes[-1] if params.content_changes else None
        if isinstance(change, lsp.TextDocumentContentChangePartial):
            ls.preview.edited(doc.uri, change.range.start.line, change.range.start.character)


@server.feature(CURSOR)
def on_cursor(ls: GestServer, params: Any) -> None:
    """``gest/cursor`` (VS Code's and Neovim's, docs/editors.md): where the editor's
    cursor is, for the preview page's step under it."""
    try:
        uri = params.textDocument.uri
        line, character = int(params.position.line), int(params.position.character)
    except (AttributeError, TypeError, ValueError):
        return  # not a cursor: nothing to follow
    doc = ls.documents.get(uri)
    if doc is not None and line >= 0 and character >= 0:
        ls.preview.moved(doc.uri, line, character)


@server.command(PREVIEW)
async def open_preview(ls: GestServer, *args: Any) -> dict[str, str] | None:
    """``gest.preview [uri, {"open": bool}]``: the live preview page's address, the page
    following the document ``uri`` (else the one last edited). Unless ``open`` is false,
    the editor is asked to open it in a browser (``window/showDocument``, external)."""
    uri = args[0] if args and isinstance(args[0], str) else None
    options = args[1] if len(args) > 1 and isinstance(args[1], dict) else {}
    doc = ls.documents.get(uri) if uri else None
    try:
        url = await asyncio.to_thread(ls.preview.open, doc.uri if doc else None)
    except GestError as exc:
        ls.window_show_message(lsp.ShowMessageParams(
            lsp.MessageType.Error, f"{exc.first.message} ({exc.first.hint})"
            if exc.first.hint else exc.first.message))
        return None
    followed = ls.documents.get(ls.preview.uri or "")
    if followed is not None:
        found = ls.analyses.get(followed.uri)
        if found is not None and found.checked:
            ls.preview.analysed(followed.uri, found)
    if options.get("open", True):
        try:
            await ls.window_show_document_async(lsp.ShowDocumentParams(uri=url,
                                                                       external=True))
        except Exception:  # noqa: BLE001 - an editor that cannot: the message says where
            ls.window_show_message(lsp.ShowMessageParams(
                lsp.MessageType.Info, f"the gesture's live preview: {url}"))
    return {"url": url}


@server.feature(lsp.TEXT_DOCUMENT_DID_CLOSE)
def did_close(ls: GestServer, params: lsp.DidCloseTextDocumentParams) -> None:
    """A document closed: forgotten, its diagnostics cleared."""
    ls.forget(params.text_document.uri)
    ls.text_document_publish_diagnostics(lsp.PublishDiagnosticsParams(
        uri=params.text_document.uri, diagnostics=[]))


@server.feature(lsp.TEXT_DOCUMENT_FORMATTING)
async def formatting(ls: GestServer, params: lsp.DocumentFormattingParams
                     ) -> list[lsp.TextEdit] | None:
    """The document as ``gestc fmt`` writes it (nothing for a text that does not
    parse), made in a thread of its own: it reads no analysis."""
    doc = ls.documents.get(params.text_document.uri)
    return None if doc is None else await asyncio.to_thread(formatted, doc.text)


@server.feature(lsp.TEXT_DOCUMENT_HOVER)
async def on_hover(ls: GestServer, params: lsp.HoverParams) -> lsp.Hover | None:
    """What is under the cursor: a servo, group, pose or gesture, a ``use`` path, a
    ``say``, and the step of the line (when it plays, whether it was stretched)."""
    return await ls.ask(params.text_document.uri,
                        functools.partial(hovered, at=params.position))


@server.feature(lsp.TEXT_DOCUMENT_COMPLETION,
                lsp.CompletionOptions(trigger_characters=['"']))
async def on_completion(ls: GestServer, params: lsp.CompletionParams
                        ) -> lsp.CompletionList:
    """What the grammar lets be typed at the cursor: the names in scope and the library's
    gestures (a ``use`` line added with one) where a step starts, the keywords and the
    units where they go, the profiles after ``robot``, the files in a ``use`` or ``say``.
    Each replaces the word being typed (a unit right after its number too)."""
    listed = await ls.ask(params.text_document.uri, functools.partial(
        completed, at=params.position, lib=list(ls.library)))
    return listed or lsp.CompletionList(False, [])


@server.feature(lsp.TEXT_DOCUMENT_DEFINITION)
async def on_definition(ls: GestServer, params: lsp.DefinitionParams
                        ) -> lsp.Location | None:
    """Where the group, pose or gesture under the cursor is defined, across ``use`` and
    the library."""
    uri = params.text_document.uri
    return await ls.ask(uri, functools.partial(defined, uri=uri, at=params.position))


@server.feature(lsp.TEXT_DOCUMENT_REFERENCES)
async def on_references(ls: GestServer, params: lsp.ReferenceParams
                        ) -> list[lsp.Location]:
    """Every place the name under the cursor is written: in this document, the files it
    uses, and the gesture files beside it (as open in the editor, else as saved)."""
    uri = params.text_document.uri
    held = {doc.path: doc.text for doc in ls.documents.open.values()}
    return await ls.ask(uri, functools.partial(referenced, uri=uri, at=params.position,
                                               held=held)) or []


@server.feature(lsp.TEXT_DOCUMENT_DOCUMENT_SYMBOL)
async def on_outline(ls: GestServer, params: lsp.DocumentSymbolParams
                     ) -> list[lsp.DocumentSymbol]:
    """The file's groups, poses and gestures, in its order."""
    return await ls.ask(params.text_document.uri, outlined) or []


@server.feature(lsp.TEXT_DOCUMENT_INLAY_HINT)
async def on_inlay_hints(ls: GestServer, params: lsp.InlayHintParams
                         ) -> list[lsp.InlayHint]:
    """After each step of the range: when it starts and how long it lasts, as planned
    (once the file's gestures are checked)."""
    return await ls.ask(params.text_document.uri,
                        functools.partial(hints, within=params.range), checked=True) or []


@server.feature(lsp.TEXT_DOCUMENT_CODE_ACTION,
                lsp.CodeActionOptions(code_action_kinds=[lsp.CodeActionKind.QuickFix,
                                                         lsp.CodeActionKind.RefactorRewrite]))
async def on_code_action(ls: GestServer, params: lsp.CodeActionParams
                         ) -> list[lsp.CodeAction]:
    """The fixes the hints of the range's diagnostics offer (once they are told), and
    each place of the range written as the servo values it solves to."""
    uri = params.text_document.uri
    return await ls.ask(uri, functools.partial(actions, uri=uri, within=params.range),
                        checked=True) or []


@server.feature(lsp.TEXT_DOCUMENT_SEMANTIC_TOKENS_FULL, LEGEND)
async def on_semantic_tokens(ls: GestServer, params: lsp.SemanticTokensParams
                             ) -> lsp.SemanticTokens:
    """Every token as what it is: a servo, a group, a pose or a gesture as the compiler
    resolves it, keywords, numbers, units, strings, comments."""
    return await ls.ask(params.text_document.uri, coloured) or lsp.SemanticTokens(data=[])


GC_THRESHOLD = 50_000  #: new objects between two young collections (Python's: 700)


def main() -> None:
    """Serve on standard input and output; anything else that would write to standard
    output (a library's print: viser's, the preview page's) goes to standard error,
    where it cannot break the protocol's stream. An edit that moves every block of a
    long file makes tens of thousands of small objects: collected less often, it
    answers in about half the time (benchmarks/lsp.py)."""
    gc.set_threshold(GC_THRESHOLD, *gc.get_threshold()[1:])
    stdout = sys.stdout.buffer
    sys.stdout = sys.stderr
    server.start_io(sys.stdin.buffer, stdout)
