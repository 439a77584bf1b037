"""The language server's state (an edge, with pygls and the worker's thread): the open
documents (``store``), each one's newest analysis, the requests waiting for one, and the
settings (``initializationOptions`` or ``workspace/didChangeConfiguration``, under
``gest``: ``robot``, the profile of a file without a robot line; ``library``, more
gesture folders).

Each version of a document is analysed in the worker's thread (``worker``), the newer
stopping the older; its loaded analysis, then its checked one, come back to the loop,
which answers the requests waiting for them and tells the editor the diagnostics of the
checked one (one publication per version, every diagnostic in it: none flickers)."""

from __future__ import annotations

import asyncio
import functools
import os
from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar

from lsprotocol import types as lsp
from pygls.lsp.server import LanguageServer

from .. import __version__
from ..compiling.robot import DEFAULT
from ..errors import GestError
from ..profiles.profile import load_profile
from .analysis import Analysis
from .memo import Memo
from .preview_feed import Preview
from .preview_play import Player
from .protocol import GestProtocol
from .replies import diagnostics
from .store import Document, Documents
from .worker import Job, Worker

T = TypeVar("T")


class GestServer(LanguageServer):
    """The server, with the open documents, their analyses and the settings."""

    def __init__(self) -> None:
        super().__init__("gestc-lsp", __version__, protocol_cls=GestProtocol)
        self.robot = DEFAULT
        self.library: list[str] = []
        self.documents = Documents()
        self.memos: dict[str, Memo] = {}  #: what each document's last analyses keep
        self.jobs: dict[str, Job] = {}  #: each document's newest
        self.analyses: dict[str, Analysis] = {}  #: the newest job's newest result
        self.waiting: dict[str, list[tuple[bool, asyncio.Future]]] = {}
        self.worker = Worker(self._arrived)
        self.loop: asyncio.AbstractEventLoop | None = None
        #: the live preview page, made when an editor asks (``gest.preview``)
        self.preview = Preview(self._pick)

    def configure(self, settings: Any) -> None:
        """Take ``{"robot": ..., "library": [...]}`` (or the same under ``gest``)."""
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
        serve, token = settings.get("serve"), settings.get("token")
        self.preview.play_on(Player(serve, token if isinstance(token, str) else None)
                             if isinstance(serve, str) and serve else None)

    def analyse(self, doc: Document) -> None:
        """Analyse ``doc`` as it is now (its older version's analysis stops)."""
        self.loop = asyncio.get_running_loop()
        job = Job(doc.uri, doc.text, doc.path, self.robot, tuple(self.library),
                  self.memos.setdefault(doc.uri, Memo()))
        self.jobs[doc.uri] = job
        self.analyses.pop(doc.uri, None)
        self.worker.submit(job)

    def forget(self, uri: str) -> None:
        """The document ``uri`` closed: its analyses stop, what waits for one gets
        nothing."""
        doc = self.documents.closed(uri)
        key = uri if doc is None else doc.uri
        self.worker.stop(key)
        for store in (self.memos, self.jobs, self.analyses):
            store.pop(key, None)
        for _, future in self.waiting.pop(key, []):
            if not future.done():
                future.set_result(None)

    async def analysed(self, uri: str, checked: bool = False) -> Analysis | None:
        """The newest analysis of the document ``uri``, once it is ``checked`` (else
        once it is loaded); None for a document that is not open."""
        doc = self.documents.get(uri)
        if doc is None:
            return None
        found = self.analyses.get(doc.uri)
        if found is not None and (found.checked or not checked):
            return found
        future = asyncio.get_running_loop().create_future()
        self.waiting.setdefault(doc.uri, []).append((checked, future))
        return await future

    async def ask(self, uri: str, answer: Callable[[Analysis], T], checked: bool = False
                  ) -> T | None:
        """``answer`` of the newest analysis of ``uri`` (``analysed``), computed in the
        worker's thread; None for a document that is not open."""
        found = await self.analysed(uri, checked)
        if found is None:
            return None
        return await asyncio.wrap_future(self.worker.call(functools.partial(answer, found)))

    def _arrived(self, job: Job, found: Analysis) -> None:
        """In the worker's thread: ``found`` (with its diagnostics for the editor, when
        checked) handed to the loop."""
        told = diagnostics(found) if found.checked else None
        if self.loop is not None:
            self.loop.call_soon_threadsafe(self._take, job, found, told)

    def _take(self, job: Job, found: Analysis, told: list[lsp.Diagnostic] | None) -> None:
        """On the loop: ``found`` is the newest analysis of its document, unless a newer
        version came; the requests it answers go on; the editor gets its diagnostics."""
        if self.jobs.get(job.uri) is not job:
            return
        self.analyses[job.uri] = found
        waiting = self.waiting.pop(job.uri, [])
        still = [(c, f) for c, f in waiting if c and not found.checked and not f.done()]
        for checked, future in waiting:
            if (checked, future) not in still and not future.done():
                future.set_result(found)
        if still:
            self.waiting[job.uri] = still
        if told is not None:
            doc = self.documents.get(job.uri)
            self.text_document_publish_diagnostics(lsp.PublishDiagnosticsParams(
                uri=job.uri, diagnostics=told, version=doc.version if doc else None))
            self.preview.analysed(job.uri, found)

    def _pick(self, path: str, line: int, character: int) -> None:
        """A step clicked on the preview page (its thread): the editor shows it."""
        if self.loop is None:
            return
        at = lsp.Position(line, character)
        params = lsp.ShowDocumentParams(uri=Path(os.path.abspath(path)).as_uri(),
                                        take_focus=True, selection=lsp.Range(at, at))
        self.loop.call_soon_threadsafe(
            lambda: asyncio.ensure_future(self.window_show_document_async(params)))

    def report_server_error(self, error: Exception, source: Any) -> None:
        """An error outside a request (a notification's handler, a message that does
        not read): in the editor's log, not a message in front of the user (a request's
        own error is its answer)."""
        self.window_log_message(lsp.LogMessageParams(
            lsp.MessageType.Error, f"gestc lsp: {type(error).__name__}: {error}"))
