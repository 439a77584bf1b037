"""The language server's edge (pygls): documents as they are opened and changed, their
diagnostics published (``diagnose``), formatting by ``gestc fmt``'s rules."""

from __future__ import annotations

from pathlib import Path

from lsprotocol import types as lsp
from pygls.lsp.server import LanguageServer

from .. import __version__
from ..errors import Diagnostic, GestError
from ..language.fmt import format_source
from .diagnose import diagnose
from .knowledge import completions, definition, hover, outline, references

SEVERITY = {"error": lsp.DiagnosticSeverity.Error, "warning": lsp.DiagnosticSeverity.Warning}

server = LanguageServer("gestc-lsp", __version__)


def to_lsp(d: Diagnostic, path: str) -> lsp.Diagnostic:
    """Our diagnostic as the editor's: its place (0-based), its severity, its message
    and hint (one of another file: at the top, naming that file and line)."""
    message = d.message + (f"\nhint: {d.hint}" if d.hint else "")
    if d.pos is None or d.pos.file != path:
        where = f"{d.pos.file}:{d.pos.line}:{d.pos.column}: " if d.pos else ""
        start = lsp.Position(0, 0)
        return lsp.Diagnostic(lsp.Range(start, start), where + message, SEVERITY[d.severity],
                              source="gestc")
    start = lsp.Position(d.pos.line - 1, d.pos.column - 1)
    end = lsp.Position(d.pos.line - 1, d.pos.column - 1 + max(1, d.pos.width))
    return lsp.Diagnostic(lsp.Range(start, end), message, SEVERITY[d.severity],
                          source="gestc")


def publish(ls: LanguageServer, uri: str) -> None:
    """Diagnose the document ``uri`` as it is now and tell the editor."""
    doc = ls.workspace.get_text_document(uri)
    found = [to_lsp(d, doc.path) for d in diagnose(doc.source, doc.path)]
    ls.text_document_publish_diagnostics(
        lsp.PublishDiagnosticsParams(uri=uri, version=doc.version, diagnostics=found))


@server.feature(lsp.TEXT_DOCUMENT_DID_OPEN)
def did_open(ls: LanguageServer, params: lsp.DidOpenTextDocumentParams) -> None:
    """A document opened: its diagnostics."""
    publish(ls, params.text_document.uri)


@server.feature(lsp.TEXT_DOCUMENT_DID_CHANGE)
def did_change(ls: LanguageServer, params: lsp.DidChangeTextDocumentParams) -> None:
    """A document changed (typed, not only saved): its diagnostics again."""
    publish(ls, params.text_document.uri)


@server.feature(lsp.TEXT_DOCUMENT_FORMATTING)
def formatting(ls: LanguageServer, params: lsp.DocumentFormattingParams
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
def on_hover(ls: LanguageServer, params: lsp.HoverParams) -> lsp.Hover | None:
    """What the name under the cursor is: a servo's board, range, rest and limits, a
    group's members, a pose's values, a gesture's planned length."""
    doc = ls.workspace.get_text_document(params.text_document.uri)
    said = hover(doc.source, doc.path, params.position.line, params.position.character)
    return None if said is None else lsp.Hover(
        lsp.MarkupContent(lsp.MarkupKind.Markdown, said))


KINDS = {"servo": lsp.CompletionItemKind.Variable, "group": lsp.CompletionItemKind.Enum,
         "pose": lsp.CompletionItemKind.Constant, "gesture": lsp.CompletionItemKind.Function,
         "keyword": lsp.CompletionItemKind.Keyword, "unit": lsp.CompletionItemKind.Unit}


@server.feature(lsp.TEXT_DOCUMENT_COMPLETION)
def on_completion(ls: LanguageServer, params: lsp.CompletionParams) -> lsp.CompletionList:
    """The names in scope (servos, groups, poses, gestures), the keywords, the units."""
    doc = ls.workspace.get_text_document(params.text_document.uri)
    return lsp.CompletionList(False, [lsp.CompletionItem(word, kind=KINDS[what], detail=what)
                                      for word, what in completions(doc.source, doc.path)])


def _range(line: int, column: int, width: int) -> lsp.Range:
    return lsp.Range(lsp.Position(line, column), lsp.Position(line, column + width))


@server.feature(lsp.TEXT_DOCUMENT_DEFINITION)
def on_definition(ls: LanguageServer, params: lsp.DefinitionParams) -> lsp.Location | None:
    """Where the group, pose or gesture under the cursor is defined, across ``use`` and
    the library."""
    doc = ls.workspace.get_text_document(params.text_document.uri)
    pos = definition(doc.source, doc.path, params.position.line, params.position.character)
    if pos is None:
        return None
    uri = params.text_document.uri if pos.file == doc.path else Path(pos.file).as_uri()
    return lsp.Location(uri, _range(pos.line - 1, pos.column - 1, pos.width))


@server.feature(lsp.TEXT_DOCUMENT_REFERENCES)
def on_references(ls: LanguageServer, params: lsp.ReferenceParams) -> list[lsp.Location]:
    """Every place in the document the name under the cursor is written."""
    doc = ls.workspace.get_text_document(params.text_document.uri)
    return [lsp.Location(params.text_document.uri, _range(*place)) for place in
            references(doc.source, doc.path, params.position.line,
                       params.position.character)]


SYMBOLS = {"group": lsp.SymbolKind.Enum, "pose": lsp.SymbolKind.Constant,
           "gesture": lsp.SymbolKind.Function}


@server.feature(lsp.TEXT_DOCUMENT_DOCUMENT_SYMBOL)
def on_outline(ls: LanguageServer, params: lsp.DocumentSymbolParams
               ) -> list[lsp.DocumentSymbol]:
    """The file's groups, poses and gestures, in its order."""
    doc = ls.workspace.get_text_document(params.text_document.uri)
    out = []
    for name, kind, pos in outline(doc.source, doc.path):
        where = _range(pos.line - 1, pos.column - 1, pos.width)
        out.append(lsp.DocumentSymbol(name, SYMBOLS[kind], where, where, detail=kind))
    return out


def main() -> None:
    """Serve on standard input and output."""
    server.start_io()
