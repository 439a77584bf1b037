"""The language server's live preview (an edge: the page is viser's, ``model.livepage``):
made when an editor first asks for it (``gest.preview``), it follows one document, the
one asked for or last edited, and shows the view of its newest checked analysis with the
cursor the editor last told (``gest/cursor``; an editor that tells none, as Helix, has
the cursor where it last edited). A step clicked on the page is sent back as the place
to put the editor's cursor (``on_pick``: the server's ``window/showDocument``).

The view is made in the worker's thread (``view_of``: the plan's timeline made once and
kept while the plan stays), the page draws it in its own: the server's loop only hands
them on."""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import Any

from ..model.timeline import Span
from .analysis import Analysis

#: what the server's loop is handed: (path, 0-based line, 0-based character) to show
Pick = Callable[[str, int, int], None]


class Preview:
    """The page (None until asked for) and what it follows. ``run(fn)`` runs ``fn`` off
    the loop (the worker's thread); ``pick`` is told, from the page's thread, a step
    clicked."""

    def __init__(self, run: Callable[[Callable[[], Any]], Any], pick: Pick):
        self.run, self.pick = run, pick
        self.page = None
        self.uri: str | None = None  #: the document followed
        self.cursors: dict[str, tuple[int, int]] = {}  #: uri -> the editor's cursor
        self.edits: dict[str, tuple[int, int]] = {}  #: uri -> where it was last edited
        self.found: Analysis | None = None  #: the newest checked analysis of ``uri``
        self.player: Any = None  #: the "Play on the robot" button's (``Player``), or None
        self._lock = threading.Lock()

    def open(self, uri: str | None) -> str:
        """The page's address, made the first time (a GestError without the web
        extra); it follows ``uri`` from now on, when given."""
        if self.page is None:
            from ..model.livepage import LivePage

            self.page = LivePage(0)
            self.page.on_pick = self._picked
            self.page.on_play = self.player
        if uri is not None and uri != self.uri:
            self.uri, self.found = uri, None
        return self.page.url

    def play_on(self, player: Any) -> None:
        """The robot its button plays on (None: the button does nothing)."""
        self.player = player
        if self.page is not None:
            self.page.on_play = player

    def moved(self, uri: str, line: int, character: int) -> None:
        """The editor's cursor is at (``line``, ``character``) of ``uri``."""
        self.cursors[uri] = (line, character)
        if uri == self.uri and self.found is not None:
            self._show(self.found)

    def edited(self, uri: str, line: int, character: int) -> None:
        """An edit at (``line``, ``character``): the cursor of an editor that tells
        none, and the document followed when none is (or the page follows none)."""
        self.edits[uri] = (line, character)
        if self.page is not None and self.uri is None:
            self.uri = uri

    def analysed(self, uri: str, found: Analysis) -> None:
        """The newest checked analysis of ``uri``: shown if the page follows it."""
        if self.page is None or uri != self.uri:
            return
        self.found = found
        self._show(found)

    def close(self) -> None:
        """The page stops (the server is leaving)."""
        if self.page is not None:
            self.page.close()
            self.page = None

    def _show(self, found: Analysis) -> None:
        """The view of ``found`` at the cursor, made off the loop, then shown."""
        page, uri = self.page, self.uri
        line, character = self.cursors.get(uri) or self.edits.get(uri) or (None, 0)

        def make() -> None:
            from .preview_view import view_of

            with self._lock:  # one view at a time: each builds on the one before
                page.show(view_of(found, line, character, previous=page.view))

        self.run(make)

    def _picked(self, span: Span) -> None:
        """A step clicked on the page (its thread): the editor's cursor to it."""
        if span.file and span.line is not None:
            self.pick(span.file, span.line, span.character or 0)
