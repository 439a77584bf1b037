"""The language server's edge (pygls): documents as they are opened and changed, each
analysed once per version (``analysis``), its diagnostics published; every request
answered from that analysis (``knowledge``, ``timing``, ``actions``, ``tokens``).
Settings (``initializationOptions`` or ``workspace/didChangeConfiguration``, under
``gest``): ``robot``, the profile of a file without a robot line; ``library``, more
gesture folders."""

from __future__ import annotations

import gc
import os
from pathlib import Path
from typing import Any

from lsprotocol import types as lsp
from pygls.lsp.server import LanguageServer
from pygls.protocol import LanguageServerProtocol

from .. import __version__
from ..compiling.robot import DEFAULT
from ..errors import Diagnostic, GestError
from ..language.fmt import format_source
from ..language.load import GEST_SUFFIX
from ..profiles.profile import load_profile
from .actions import fixes
from .analysis import Analysis, analyse
from .knowledge import completions, definition, hover, outline, references
from .memo import Memo
from .text import word_at
from .timing import label, step_times
from .tokens import MODIFIERS, TYPES, encoded, tokens

SEVERITY = {"error": lsp.DiagnosticSeverity.Error, "warning": lsp.DiagnosticSeverity.Warning}
LEGEND = lsp.SemanticTokensLegend(list(TYPES), list(MODIFIERS))


class _Protocol(LanguageServerProtocol):
    """pygls's protocol, without its one leak: pygls 2.1 keeps the future of every
    notification it hands on from a handler of its own (didOpen, didChange, didClose...)
    forever, about 2 KB an edit (benchmarks/lsp.py measured the server growing by 2 MB
    every thousand edits); a future done is dropped here."""

    def _handle_notification(self, method_name: str, params: Any) -> None:
        super()._handle_notification(method_name, params)
        done = [k for k, f in self._request_futures.items() if f.done()]
        for key in done:  # a request's answer is sent by its own callback all the same
            del self._request_futures[key]


class GestServer(LanguageServer):
    """The server, with each open document's latest analysis and the settings."""

    def __init__(self) -> None:
        super().__init__("gestc-lsp", __version__, protocol_cls=_Protocol)
        self.robot = DEFAULT
        self.library: list[str] = []
        self.analyses: dict[str, tuple[int | None, Analysis]] = {}
        self.memos: dict[str, Memo] = {}  #: what each document's last analyses keep

    def configure(self, settings: Any) -> None:
        """Take ``{"robot": ..., "library": [...]}`` (or the same under ``gest``);
        every open document is analysed again."""
        if not isinstance(settings, dict):
            return
        settings = settings.get("gest", settings)
        if not isinstance(settings, dict):
            return
        robot, library = settings.get("robot"), settings.get("library")
        self.robot = robot if isinstance(robot, str) and robot else DEFAULT
        try:
            load_profile(self.robot)
        except GestError as exc:
            self.window_show_message(lsp.ShowMessageParams(
                lsp.MessageType.Warning, f"gest.robot: {exc.first.message}; the files "
                f"without a robot line are for {DEFAULT}"))
            self.robot = DEFAULT
        self.library = [d for d in library if isinstance(d, str)] if isinstance(
            library, list) else []
        self.analyses.clear()

    def analysis(self, uri: str) -> Analysis:
        """The document ``uri`` as it is now, analysed (once per version)."""
        doc = self.workspace.get_text_document(uri)
        seen = self.analyses.get(uri)
        if seen is None or seen[0] != doc.version or seen[1].text != doc.source:
            memo = self.memos.setdefault(uri, Memo())
            seen = (doc.version, analyse(doc.source, doc.path, self.robot, self.library,
                                         memo))
            self.analyses[uri] = seen
        return seen[1]


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
         "file": lsp.CompletionItemKind.File, "sound": lsp.CompletionItemKind.File}


@server.feature(lsp.TEXT_DOCUMENT_COMPLETION,
                lsp.CompletionOptions(trigger_characters=['"']))
def on_completion(ls: GestServer, params: lsp.CompletionParams) -> lsp.CompletionList:
    """The names in scope, the keywords, the units; the files in a ``use`` or ``say``."""
    found = ls.analysis(params.text_document.uri)
    return lsp.CompletionList(False, [
        lsp.CompletionItem(word, kind=KINDS[what], detail=what) for word, what in
        completions(found, params.position.line, params.position.character, ls.library)])


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
    try:
        with open(path, encoding="utf-8") as f:
            return f.read(1 << 20)
    except (OSError, ValueError):
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
