"""The language server's edge (pygls): documents as they are opened and changed, each
analysed once per version (``documents.GestServer``), its diagnostics published; every
request answered from that analysis (``knowledge``, ``timing``, ``actions``,
``tokens``)."""

from __future__ import annotations

import gc
import os
from pathlib import Path

from lsprotocol import types as lsp

from ..errors import Diagnostic, GestError
from ..language.fmt import format_source
from ..language.load import GEST_SUFFIX, read_text
from .actions import after_header, fixes
from .analysis import Analysis
from .documents import GestServer
from .knowledge import completions, definition, hover, outline, references
from .text import word_at
from .timing import label, step_times
from .tokens import MODIFIERS, TYPES, encoded, tokens

SEVERITY = {"error": lsp.DiagnosticSeverity.Error, "warning": lsp.DiagnosticSeverity.Warning}
LEGEND = lsp.SemanticTokensLegend(list(TYPES), list(MODIFIERS))

server = GestServer()


def to_lsp(d: Diagnostic, path: str) -> lsp.Diagnostic:
    """Our diagnostic as the editor's: its place (0-based), its severity, its message
    and hint (one of another file: at the top, naming that file and line)."""
    message = d.message + (f"\nhint: {d.hint}" if d.hint else "")
    if d.pos is None or d.pos.file != path:
        where = f"{d.pos.file}:{d.pos.line}:{d.pos.column}: " if d.pos else ""
        return lsp.Diagnostic(_range(0, 0, 0), where + message, SEVERITY[d.severity],
                              source="gestc")
    return lsp.Diagnostic(_range(d.pos.line - 1, d.pos.column - 1, max(1, d.pos.width)),
                          message, SEVERITY[d.severity], source="gestc")


def _range(line: int, column: int, width: int) -> lsp.Range:
    return lsp.Range(lsp.Position(line, column), lsp.Position(line, column + width))


def publish(ls: GestServer, uri: str) -> None:
    """Analyse the document ``uri`` as it is now and tell the editor its diagnostics."""
    found = ls.analysis(uri)
    ls.text_document_publish_diagnostics(lsp.PublishDiagnosticsParams(
        uri=uri, version=ls.analyses[uri][0],
        diagnostics=[to_lsp(d, found.path) for d in found.diagnostics]))


@server.feature(lsp.INITIALIZE)
def initialize(ls: GestServer, params: lsp.InitializeParams) -> None:
    """Read the settings the client starts the server with."""
    ls.configure(params.initialization_options)


@server.feature(lsp.WORKSPACE_DID_CHANGE_CONFIGURATION)
def did_change_configuration(ls: GestServer, params: lsp.DidChangeConfigurationParams
                             ) -> None:
    """New settings: every open document's diagnostics again."""
    ls.configure(params.settings)
    for uri in list(ls.workspace.text_documents):
        publish(ls, uri)


@server.feature(lsp.TEXT_DOCUMENT_DID_OPEN)
def did_open(ls: GestServer, params: lsp.DidOpenTextDocumentParams) -> None:
    """A document opened: its diagnostics."""
    publish(ls, params.text_document.uri)


@server.feature(lsp.TEXT_DOCUMENT_DID_CHANGE)
def did_change(ls: GestServer, params: lsp.DidChangeTextDocumentParams) -> None:
    """A document changed (typed, not only saved): its diagnostics again."""
    publish(ls, params.text_document.uri)


@server.feature(lsp.TEXT_DOCUMENT_DID_CLOSE)
def did_close(ls: GestServer, params: lsp.DidCloseTextDocumentParams) -> None:
    """A document closed: its analysis forgotten, its diagnostics cleared."""
    ls.analyses.pop(params.text_document.uri, None)
    ls.memos.pop(params.text_document.uri, None)
    ls.text_document_publish_diagnostics(lsp.PublishDiagnosticsParams(
        uri=params.text_document.uri, diagnostics=[]))


@server.feature(lsp.TEXT_DOCUMENT_FORMATTING)
def formatting(ls: GestServer, params: lsp.DocumentFormattingParams
               ) -> list[lsp.TextEdit] | None:
    """The document as ``gestc fmt`` writes it (nothing for a text that does not parse)."""
    doc = ls.workspace.get_text_document(params.text_document.uri)
    try:
        text = format_source(doc.source)
    except GestError:
        return None
    lines = doc.source.split("\n")
    end = lsp.Position(len(lines) - 1, len(lines[-1]))
    return [] if text == doc.source else [lsp.TextEdit(lsp.Range(lsp.Position(0, 0), end),
                                                       text)]


@server.feature(lsp.TEXT_DOCUMENT_HOVER)
def on_hover(ls: GestServer, params: lsp.HoverParams) -> lsp.Hover | None:
    """What is under the cursor: a servo, group, pose or gesture, a ``use`` path, a
    ``say``, and the step of the line (when it plays, whether it was stretched)."""
    said = hover(ls.analysis(params.text_document.uri), params.position.line,
                 params.position.character)
    return None if said is None else lsp.Hover(
        lsp.MarkupContent(lsp.MarkupKind.Markdown, said))


KINDS = {"servo": lsp.CompletionItemKind.Variable, "group": lsp.CompletionItemKind.Enum,
         "pose": lsp.CompletionItemKind.Constant, "gesture": lsp.CompletionItemKind.Function,
         "keyword": lsp.CompletionItemKind.Keyword, "unit": lsp.CompletionItemKind.Unit,
         "file": lsp.CompletionItemKind.File, "sound": lsp.CompletionItemKind.File,
         "profile": lsp.CompletionItemKind.Module}


@server.feature(lsp.TEXT_DOCUMENT_COMPLETION,
                lsp.CompletionOptions(trigger_characters=['"']))
def on_completion(ls: GestServer, params: lsp.CompletionParams) -> lsp.CompletionList:
    """What the grammar lets be typed at the cursor: the names in scope and the library's
    gestures (a ``use`` line added with one) where a step starts, the keywords and the
    units where they go, the profiles after ``robot``, the files in a ``use`` or ``say``.
    Each replaces the word being typed (a unit right after its number too)."""
    found = ls.analysis(params.text_document.uri)
    at = lsp.Position(after_header(found.text), 0)
    cursor = params.position
    return lsp.CompletionList(False, [
        lsp.CompletionItem(
            c.word, kind=KINDS[c.what], detail=c.detail,
            text_edit=None if c.start is None else lsp.TextEdit(
                lsp.Range(lsp.Position(cursor.line, min(c.start, cursor.character)), cursor),
                c.word),
            additional_text_edits=None if c.use is None else [
                lsp.TextEdit(lsp.Range(at, at), f'use "{c.use}"\n')])
        for c in completions(found, cursor.line, cursor.character, ls.library)])


def _location(pos_file: str, found: Analysis, uri: str, line: int, column: int,
              width: int) -> lsp.Location:
    there = uri if pos_file == found.path else Path(pos_file).as_uri()
    return lsp.Location(there, _range(line, column, width))


@server.feature(lsp.TEXT_DOCUMENT_DEFINITION)
def on_definition(ls: GestServer, params: lsp.DefinitionParams) -> lsp.Location | None:
    """Where the group, pose or gesture under the cursor is defined, across ``use`` and
    the library."""
    uri = params.text_document.uri
    found = ls.analysis(uri)
    pos = definition(found, params.position.line, params.position.character)
    return None if pos is None else _location(pos.file, found, uri, pos.line - 1,
                                              pos.column - 1, pos.width)


@server.feature(lsp.TEXT_DOCUMENT_REFERENCES)
def on_references(ls: GestServer, params: lsp.ReferenceParams) -> list[lsp.Location]:
    """Every place the name under the cursor is written: in this document, the files it
    uses, and the gesture files beside it (as open in the editor, else as saved)."""
    uri = params.text_document.uri
    found = ls.analysis(uri)
    word = word_at(found.text, params.position.line, params.position.character)
    if word is None:
        return []
    texts = {found.path: found.text}
    if found.program is not None:
        texts.update((f, t) for f, t in found.program.texts.items() if f not in texts)
    for name in sorted(os.listdir(os.path.dirname(found.path) or ".")):
        beside = os.path.join(os.path.dirname(found.path), name)
        if name.endswith(GEST_SUFFIX) and beside not in texts:
            texts[beside] = _saved(beside)
    for doc in ls.workspace.text_documents.values():  # what the editor holds wins
        if doc.path in texts:
            texts[doc.path] = doc.source
    return [_location(f, found, uri, *place) for f, text in texts.items()
            for place in references(text, word)]


def _saved(path: str) -> str:
    """A gesture file as saved, read as ``use`` reads one ("" when it cannot be)."""
    try:
        return read_text(path)
    except (GestError, OSError, ValueError):
        return ""


SYMBOLS = {"group": lsp.SymbolKind.Enum, "pose": lsp.SymbolKind.Constant,
           "gesture": lsp.SymbolKind.Function}


@server.feature(lsp.TEXT_DOCUMENT_DOCUMENT_SYMBOL)
def on_outline(ls: GestServer, params: lsp.DocumentSymbolParams
               ) -> list[lsp.DocumentSymbol]:
    """The file's groups, poses and gestures, in its order."""
    out = []
    for name, kind, pos in outline(ls.analysis(params.text_document.uri)):
        where = _range(pos.line - 1, pos.column - 1, pos.width)
        out.append(lsp.DocumentSymbol(name, SYMBOLS[kind], where, where, detail=kind))
    return out


@server.feature(lsp.TEXT_DOCUMENT_INLAY_HINT)
def on_inlay_hints(ls: GestServer, params: lsp.InlayHintParams) -> list[lsp.InlayHint]:
    """After each step of the range: when it starts and how long it lasts, as planned."""
    first, last = params.range.start.line, params.range.end.line
    return [lsp.InlayHint(lsp.Position(line, step.end_column), label(step),
                          padding_left=True)
            for line, step in sorted(step_times(ls.analysis(params.text_document.uri)).items())
            if first <= line <= last]


@server.feature(lsp.TEXT_DOCUMENT_CODE_ACTION,
                lsp.CodeActionOptions(code_action_kinds=[lsp.CodeActionKind.QuickFix]))
def on_code_action(ls: GestServer, params: lsp.CodeActionParams) -> list[lsp.CodeAction]:
    """The fixes the hints of the range's diagnostics offer."""
    uri = params.text_document.uri
    found = ls.analysis(uri)
    out = []
    for line in range(params.range.start.line, params.range.end.line + 1):
        for fix in fixes(found, line):
            edit = lsp.TextEdit(lsp.Range(lsp.Position(fix.line, fix.column),
                                          lsp.Position(fix.line, fix.end)), fix.text)
            out.append(lsp.CodeAction(
                fix.title, kind=lsp.CodeActionKind.QuickFix,
                diagnostics=[to_lsp(fix.diagnostic, found.path)],
                is_preferred=fix.preferred,
                edit=lsp.WorkspaceEdit(changes={uri: [edit]})))
    return out


@server.feature(lsp.TEXT_DOCUMENT_SEMANTIC_TOKENS_FULL, LEGEND)
def on_semantic_tokens(ls: GestServer, params: lsp.SemanticTokensParams
                       ) -> lsp.SemanticTokens:
    """Every token as what it is: a servo, a group, a pose or a gesture as the compiler
    resolves it, keywords, numbers, units, strings, comments."""
    return lsp.SemanticTokens(data=encoded(tokens(ls.analysis(params.text_document.uri))))


GC_THRESHOLD = 50_000  #: new objects between two young collections (Python's: 700)


def main() -> None:
    """Serve on standard input and output. An edit that moves every block of a long
    file makes tens of thousands of small objects: collected less often, it answers in
    about half the time (benchmarks/lsp.py)."""
    gc.set_threshold(GC_THRESHOLD, *gc.get_threshold()[1:])
    server.start_io()
