"""pygls's protocol as the editor's server speaks it (an edge, with pygls): what the
Language Server Protocol asks of a server that pygls 2.1 does not do.

- A request before ``initialize`` is answered with the error ServerNotInitialized
  (-32002), a notification then is dropped (but ``exit``); pygls raised, and the editor
  got an internal error with a traceback.
- A message whose params are not what its method takes (a negative line) is answered,
  when it is a request, with InvalidParams (-32602) saying what is wrong; pygls never
  answered it, and showed an error. A notification of the kind is dropped and logged.
- The open documents are the server's own (``store.Documents``, by the protocol's line
  ends): pygls's workspace is told none of them, so nothing reads a document from the
  disk, and its ``splitlines`` never makes a line where the editor has none.
- The position encoding is the one the server counts in, code points (``utf-32``),
  when the editor offers it, else UTF-16 (which every editor has); never UTF-8.
- The future of every notification handled is dropped once done (pygls 2.1 kept each
  one forever: about 2 KB an edit, benchmarks/lsp.py)."""

from __future__ import annotations

import logging
from collections.abc import Generator
from typing import Any

from lsprotocol import types as lsp
from pygls.protocol import LanguageServerProtocol
from pygls.protocol.language_server import lsp_method

log = logging.getLogger(__name__)

ANSWERED = object()  #: a message already answered: nothing more to do with it
ALWAYS = {lsp.INITIALIZE, lsp.EXIT}  #: what is read before ``initialize``
ENCODINGS = (lsp.PositionEncodingKind.Utf32, lsp.PositionEncodingKind.Utf16)


class GestProtocol(LanguageServerProtocol):
    """pygls's protocol, as the module says."""

    @property
    def initialized(self) -> bool:
        """Has ``initialize`` come?"""
        return self._workspace is not None

    def structure_message(self, data: dict[str, Any]) -> Any:
        """``data`` as its method's message; a request whose params are wrong is
        answered InvalidParams here, anything else wrong is logged and dropped."""
        try:
            return super().structure_message(data)
        except Exception as exc:  # noqa: BLE001 - pygls wraps what cattrs raised
            why = _why(exc)
        method = data.get("method")
        if "id" in data and method is not None:
            self._send_response(data["id"], error=lsp.ResponseError(
                lsp.ErrorCodes.InvalidParams, f"invalid params for {method}: {why}"))
        else:
            log.warning("dropped a message that does not read (%s): %s", method, why)
        return ANSWERED

    def handle_message(self, message: Any) -> None:
        """Hand ``message`` on, unless it is answered already."""
        if message is not ANSWERED:
            super().handle_message(message)

    def _handle_request(self, msg_id: Any, method_name: str, params: Any) -> None:
        if not self.initialized and method_name not in ALWAYS:
            self._send_response(msg_id, error=lsp.ResponseError(
                lsp.ErrorCodes.ServerNotInitialized,
                f"{method_name} before initialize: the server is not initialized"))
            return
        super()._handle_request(msg_id, method_name, params)

    def _handle_notification(self, method_name: str, params: Any) -> None:
        if not self.initialized and method_name not in ALWAYS:
            log.warning("dropped %s, sent before initialize", method_name)
            return
        super()._handle_notification(method_name, params)
        done = [k for k, f in self._request_futures.items() if f.done()]
        for key in done:  # a request's answer is sent by its own callback all the same
            del self._request_futures[key]

    @lsp_method(lsp.INITIALIZE)
    def lsp_initialize(self, params: lsp.InitializeParams
                       ) -> Generator[Any, Any, lsp.InitializeResult]:
        """pygls's ``initialize``, offered only the encodings the server counts in."""
        general = params.capabilities.general
        if general is not None and general.position_encodings:
            general.position_encodings = [e for e in ENCODINGS
                                          if e in general.position_encodings] or None
        return (yield from super().lsp_initialize(params))

    @lsp_method(lsp.TEXT_DOCUMENT_DID_OPEN)
    def lsp_text_document__did_open(self, params: lsp.DidOpenTextDocumentParams
                                    ) -> Generator[Any, Any, None]:
        """The server's handler alone (it keeps the document)."""
        yield from self._own(lsp.TEXT_DOCUMENT_DID_OPEN, params)

    @lsp_method(lsp.TEXT_DOCUMENT_DID_CHANGE)
    def lsp_text_document__did_change(self, params: lsp.DidChangeTextDocumentParams
                                      ) -> Generator[Any, Any, None]:
        """The server's handler alone (it makes the change)."""
        yield from self._own(lsp.TEXT_DOCUMENT_DID_CHANGE, params)

    @lsp_method(lsp.TEXT_DOCUMENT_DID_CLOSE)
    def lsp_text_document__did_close(self, params: lsp.DidCloseTextDocumentParams
                                     ) -> Generator[Any, Any, None]:
        """The server's handler alone (it forgets the document)."""
        yield from self._own(lsp.TEXT_DOCUMENT_DID_CLOSE, params)

    def _own(self, method: str, params: Any) -> Generator[Any, Any, None]:
        if (handler := self.fm.features.get(method)) is not None:
            yield handler, (params,), None


def _why(exc: BaseException) -> str:
    """What is wrong, in the words of the innermost error."""
    while exc.__cause__ is not None:
        exc = exc.__cause__
    while getattr(exc, "exceptions", None):
        exc = exc.exceptions[0]
    if isinstance(exc, KeyError):
        return f"{exc.args[0]!r} is missing"
    return str(exc) or type(exc).__name__
