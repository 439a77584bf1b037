"""The documents an editor has open, as it sent them (pure): each one's text and version,
kept by ``didOpen`` and ``didChange`` (incremental changes made by the protocol's line
ends, ``lines``) and dropped by ``didClose``. The server never reads an open document
from the disk, and a document it does not have is not read either: what the editor has
not opened (or has closed) is no document."""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass
from urllib.parse import unquote, urlparse

from lsprotocol import types as lsp

from .lines import edited


@dataclass(frozen=True)
class Document:
    """One open document: its ``uri``, the file the compiler reads it as (``path``),
    the editor's ``version`` and ``text``."""

    uri: str
    path: str
    version: int | None
    text: str


def document_path(uri: str, root: str | None = None) -> str:
    """The file the compiler takes the document ``uri`` for: a ``file:`` URI's own; for
    another (``untitled:Untitled-1``, never saved), a file of its name in ``root`` (the
    workspace's folder, else the server's working directory), where its ``use`` lines
    are looked for as they would be once it is saved there."""
    parsed = urlparse(uri)
    if parsed.scheme == "file":
        path = unquote(parsed.path)
        if parsed.netloc:  # a share: //host/path
            path = f"//{parsed.netloc}{path}"
        elif os.name == "nt" and len(path) > 2 and path[0] == "/" and path[2] == ":":
            path = path[1:]  # /C:/x is C:/x
        return os.path.normpath(path)
    name = os.path.basename(unquote(parsed.path).rstrip("/")) or "untitled"
    return os.path.join(os.path.abspath(root or os.getcwd()), name)


class Documents:
    """The open documents by URI, and the folder a document that is not a file is
    taken to be in (``root``)."""

    def __init__(self) -> None:
        self.open: dict[str, Document] = {}
        self.root: str | None = None
        self.encoding = "utf-16"  #: how the editor counts columns (``initialize``)

    def get(self, uri: str) -> Document | None:
        """The document ``uri`` as the editor has it, or None (not open)."""
        return self.open.get(_key(uri))

    def opened(self, uri: str, version: int | None, text: str) -> Document:
        """``didOpen``: the document's text (again, when it was open)."""
        doc = Document(uri, document_path(uri, self.root), version, text)
        self.open[_key(uri)] = doc
        return doc

    def changed(self, uri: str, version: int | None,
                changes: Sequence[lsp.TextDocumentContentChangeEvent]) -> Document | None:
        """``didChange``: each change made in order. None for a document that is not
        open and no whole text in the changes to take it from (a change of a text the
        server never had: nothing to make it on); a whole text opens it."""
        doc = self.get(uri)
        text = None if doc is None else doc.text
        for change in changes:
            if isinstance(change, lsp.TextDocumentContentChangePartial):
                if text is not None:
                    r = change.range
                    text = edited(text, (r.start.line, r.start.character),
                                  (r.end.line, r.end.character), change.text, self.encoding)
            else:
                text = change.text
        if text is None:
            return None
        if doc is None:
            return self.opened(uri, version, text)
        doc = Document(doc.uri, doc.path, version, text)
        self.open[_key(uri)] = doc
        return doc

    def closed(self, uri: str) -> Document | None:
        """``didClose``: the document forgotten (what it was, or None)."""
        return self.open.pop(_key(uri), None)


def _key(uri: str) -> str:
    """One spelling of a URI (``file:///a%3Ab`` and ``file:///a:b`` are one)."""
    return unquote(uri)
