"""Each answer of the editor's server, in the protocol's types, from an Analysis (pure
but for reading the gesture files beside a file, for references): the compiler's
places as the protocol's (``lines.place``), every range brought into the text
(``lines.clamp``), so that an answer costs what the text holds, whatever is asked."""

from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path

from lsprotocol import types as lsp

from ..errors import Diagnostic, GestError, Pos
from ..language.fmt import format_source
from ..language.load import GEST_SUFFIX, read_text
from . import places
from .actions import after_header, fixes
from .analysis import Analysis, planned_at
from .knowledge import completions, definition, hover, outline, references
from .lines import clamp, end, place, rows
from .text import word_at
from .timing import label, step_times
from .tokens import encoded, tokens

SEVERITY = {"error": lsp.DiagnosticSeverity.Error, "warning": lsp.DiagnosticSeverity.Warning}
KINDS = {"servo": lsp.CompletionItemKind.Variable, "group": lsp.CompletionItemKind.Enum,
         "pose": lsp.CompletionItemKind.Constant, "gesture": lsp.CompletionItemKind.Function,
         "keyword": lsp.CompletionItemKind.Keyword, "unit": lsp.CompletionItemKind.Unit,
         "file": lsp.CompletionItemKind.File, "sound": lsp.CompletionItemKind.File,
         "profile": lsp.CompletionItemKind.Module, "place": lsp.CompletionItemKind.Reference}
SYMBOLS = {"group": lsp.SymbolKind.Enum, "pose": lsp.SymbolKind.Constant,
           "gesture": lsp.SymbolKind.Function}


def to_lsp(d: Diagnostic, found: Analysis) -> lsp.Diagnostic:
    """Our diagnostic as the editor's: its place, its severity, its message and hint
    (one of another file: at the top, naming that file and line)."""
    message = d.message + (f"\nhint: {d.hint}" if d.hint else "")
    if d.pos is None or d.pos.file != found.path:
        where = f"{d.pos.file}:{d.pos.line}:{d.pos.column}: " if d.pos else ""
        return lsp.Diagnostic(_range(0, 0, 0), where + message, SEVERITY[d.severity],
                              source="gestc")
    line, column = place(found.text, d.pos.line, d.pos.column)
    return lsp.Diagnostic(_range(line, column, max(1, d.pos.width)), message,
                          SEVERITY[d.severity], source="gestc")


def diagnostics(found: Analysis) -> list[lsp.Diagnostic]:
    """Every diagnostic of ``found``, as the editor is told them."""
    return [to_lsp(d, found) for d in found.diagnostics]


def _range(line: int, column: int, width: int) -> lsp.Range:
    return lsp.Range(lsp.Position(line, column), lsp.Position(line, column + width))


def formatted(text: str) -> list[lsp.TextEdit] | None:
    """``text`` as ``gestc fmt`` writes it: one edit of the whole text, none when it is
    so already, None when it does not parse."""
    try:
        new = format_source(text)
    except GestError:
        return None
    return [] if new == text else [lsp.TextEdit(lsp.Range(lsp.Position(0, 0),
                                                          lsp.Position(*end(text))), new)]


def hovered(found: Analysis, at: lsp.Position) -> lsp.Hover | None:
    """What is under the cursor (``knowledge.hover``); the step of the line planned
    alone when the file's gestures are not checked yet."""
    said = hover(planned_at(found, at.line), at.line, at.character)
    return None if said is None else lsp.Hover(
        lsp.MarkupContent(lsp.MarkupKind.Markdown, said))


def completed(found: Analysis, at: lsp.Position, lib: list[str]) -> lsp.CompletionList:
    """What may be typed at the cursor (``knowledge.completions``), each item replacing
    the word being typed; a library gesture brings its ``use`` line."""
    if at.line >= len(rows(found.text)):
        return lsp.CompletionList(False, [])
    cursor = lsp.Position(*clamp(found.text, at.line, at.character))
    top = lsp.Position(after_header(found.text), 0)
    return lsp.CompletionList(False, [
        lsp.CompletionItem(
            c.word, kind=KINDS[c.what], detail=c.detail,
            text_edit=None if c.start is None else lsp.TextEdit(
                lsp.Range(lsp.Position(cursor.line, min(c.start, cursor.character)), cursor),
                c.word),
            additional_text_edits=None if c.use is None else [
                lsp.TextEdit(lsp.Range(top, top), f'use "{c.use}"\n')])
        for c in completions(found, cursor.line, cursor.character, lib)])


def located(found: Analysis, uri: str, pos: Pos) -> lsp.Location:
    """Where ``pos`` is: in the document ``uri`` (``found``) or in another file."""
    text = found.text if pos.file == found.path else (
        found.program.texts.get(pos.file) if found.program else None)
    line, column = (pos.line - 1, pos.column - 1) if text is None else \
        place(text, pos.line, pos.column)
    there = uri if pos.file == found.path else Path(os.path.abspath(pos.file)).as_uri()
    return lsp.Location(there, _range(line, column, pos.width))


def defined(found: Analysis, uri: str, at: lsp.Position) -> lsp.Location | None:
    """Where the name under the cursor is defined (``knowledge.definition``)."""
    pos = definition(found, at.line, at.character)
    return None if pos is None else located(found, uri, pos)


def referenced(found: Analysis, uri: str, at: lsp.Position, held: Mapping[str, str]
               ) -> list[lsp.Location]:
    """Every place the name under the cursor is written: this document, the files it
    uses, the gesture files beside it (``held``: the texts the editor has open, by
    path, which win over the saved ones)."""
    word = word_at(found.text, at.line, at.character)
    if word is None:
        return []
    texts = {found.path: found.text}
    if found.program is not None:
        texts.update((f, t) for f, t in found.program.texts.items() if f not in texts)
    folder = os.path.dirname(found.path) or "."
    try:
        beside = sorted(os.listdir(folder))
    except OSError:  # a folder that is not there (yet): nothing beside
        beside = []
    for name in beside:
        path = os.path.join(folder, name)
        if name.endswith(GEST_SUFFIX) and path not in texts:
            texts[path] = _saved(path)
    texts.update((p, t) for p, t in held.items() if p in texts and p != found.path)
    out = []
    for f, text in texts.items():
        there = uri if f == found.path else Path(os.path.abspath(f)).as_uri()
        out += [lsp.Location(there, _range(*at)) for at in references(text, word)]
    return out


def _saved(path: str) -> str:
    """A gesture file as saved, read as ``use`` reads one ("" when it cannot be)."""
    try:
        return read_text(path)
    except (GestError, OSError, ValueError):
        return ""


def outlined(found: Analysis) -> list[lsp.DocumentSymbol]:
    """The file's groups, poses and gestures, in its order."""
    out = []
    for name, kind, pos in outline(found):
        where = _range(*place(found.text, pos.line, pos.column), pos.width)
        out.append(lsp.DocumentSymbol(name, SYMBOLS[kind], where, where, detail=kind))
    return out


def hints(found: Analysis, within: lsp.Range) -> list[lsp.InlayHint]:
    """After each step of the range: when it starts and how long it lasts."""
    first, last = sorted((within.start.line, within.end.line))
    out = [lsp.InlayHint(lsp.Position(s.line, s.end), f"= {s.text}", padding_left=True)
           for s in places.solved(found) if first <= s.line <= last]
    return out + [lsp.InlayHint(lsp.Position(line, step.end_column), label(step),
                                padding_left=True)
                  for line, step in sorted(step_times(found).items()) if first <= line <= last]


def actions(found: Analysis, uri: str, within: lsp.Range) -> list[lsp.CodeAction]:
    """The fixes the hints of the range's diagnostics offer (``actions.fixes``): what
    the range holds of the text, wherever it ends."""
    first, last = sorted((within.start.line, within.end.line))
    out = []
    for fix in fixes(found, clamp(found.text, first, 0)[0], clamp(found.text, last, 0)[0]):
        edit = lsp.TextEdit(lsp.Range(lsp.Position(fix.line, fix.column),
                                      lsp.Position(fix.line, fix.end)), fix.text)
        out.append(lsp.CodeAction(
            fix.title, kind=lsp.CodeActionKind.QuickFix,
            diagnostics=[to_lsp(fix.diagnostic, found)], is_preferred=fix.preferred,
            edit=lsp.WorkspaceEdit(changes={uri: [edit]})))
    for item in places.solved(found):  # a place written as the values it solves to
        if first <= item.line <= last and len(item.values) == 1:
            edit = lsp.TextEdit(lsp.Range(lsp.Position(item.line, item.column),
                                          lsp.Position(item.line, item.end)), item.values[0])
            out.append(lsp.CodeAction(f"Write '{item.label}' as servo values",
                                      kind=lsp.CodeActionKind.RefactorRewrite,
                                      edit=lsp.WorkspaceEdit(changes={uri: [edit]})))
    return out


def coloured(found: Analysis) -> lsp.SemanticTokens:
    """Every token as what it is (``tokens``)."""
    return lsp.SemanticTokens(data=encoded(tokens(found)))
