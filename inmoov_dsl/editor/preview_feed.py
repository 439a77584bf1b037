"""The language server's live preview (an edge: the page is viser's, ``views.livepage``):
made when an editor first asks for it (``gest.preview``), it follows one document, the
one asked for or last edited, and shows the view of its newest checked analysis with the
cursor the editor last told (``gest/cursor``; an editor that tells none, as Helix, has
the cursor where it last edited). A step clicked on the page is sent back as the place
to put the editor's cursor (``on_pick``: the server's ``window/showDocument``).

The view is made in a thread of the preview's own (``view_of``: the plan's timeline made
once and kept while the plan stays), only for the newest analysis and cursor (one that
a newer one overtook is skipped), so the worker's analyses never wait for it; the page
draws it in its own: the server's loop only hands them on."""

from __future__ import annotations

import gc
import logging
import threading
from collections.abc import Callable
from typing import Any

from ..views.timeline import Span
from .analysis import Analysis

log = logging.getLogger(__name__)

#: what the server's loop is handed: (path, 0-based line, 0-based character) to show
Pick = Callable[[str, int, int], None]


class Preview:
    """The page (None until asked for) and what it follows. ``pick`` is told, from the
    page's thread, a step clicked."""

    def __init__(self, pick: Pick):
        self.pick = pick
        self.page = None
        self.uri: str | None = None  #: the document followed
        self.cursors: dict[str, tuple[int, int]] = {}  #: uri -> the editor's cursor
        self.edits: dict[str, tuple[int, int]] = {}  #: uri -> where it was last edited
        self.found: Analysis | None = None  #: the newest checked analysis of ``uri``
        self.player: Any = None  #: the "Play on the robot" button's (``Player``), or None
        self._wanted: tuple | None = None  #: the newest (analysis, line, character) to show
        self._wake = threading.Condition()
        self._thread: threading.Thread | None = None

    def open(self, uri: str | None) -> str:
        """The page's address, made the first time (a GestError without the web
        extra); it follows ``uri`` from now on, when given."""
        if self.page is None:
            from ..views.livepage import LivePage

            self.page = LivePage(0)
            self.page.on_pick = self._picked
            self.page.on_play = self.player
            gc.collect()  # what the page brought (viser, the model's meshes: 150,000
            gc.freeze()  # objects) lives as long as the server: never scanned again
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
        """Show the view of ``found`` at the cursor: made in the preview's thread, the
        newest wanted only."""
        line, character = self.cursors.get(self.uri) or self.edits.get(self.uri) or (None, 0)
        with self._wake:
            self._wanted = (found, line, character)
            if self._thread is None:
                self._thread = threading.Thread(target=self._run, name="gest-preview",
                                                daemon=True)
                self._thread.start()
            self._wake.notify()

    def _run(self) -> None:
        """The preview's thread: each newest view made and handed to the page."""
        from .preview_view import view_of

        while True:
            with self._wake:
                while self._wanted is None:
                    self._wake.wait()
                (found, line, character), self._wanted = self._wanted, None
            page = self.page
            if page is None:
                continue
            try:
                page.show(view_of(found, line, character, previous=page.view))
            except Exception:  # noqa: BLE001 - the page shows the last view; the editor goes on
                log.exception("the preview's view")

    def _picked(self, span: Span) -> None:
        """A step clicked on the page (its thread): the editor's cursor to it."""
        if span.file and span.line is not None:
            self.pick(span.file, span.line, span.character or 0)
