"""The language server's state (an edge, with pygls): the open documents, each analysed
once per version with what its last analyses keep (``Memo``), and the settings
(``initializationOptions`` or ``workspace/didChangeConfiguration``, under ``gest``:
``robot``, the profile of a file without a robot line; ``library``, more gesture
folders)."""

from __future__ import annotations

from typing import Any

from lsprotocol import types as lsp
from pygls.lsp.server import LanguageServer
from pygls.protocol import LanguageServerProtocol

from .. import __version__
from ..compiling.robot import DEFAULT
from ..errors import GestError
from ..profiles.profile import load_profile
from .analysis import Analysis, analyse
from .memo import Memo


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
