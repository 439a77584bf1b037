"""The door of every page viser serves here (an edge): a request is answered only when
it names this computer's own address for the page's port and comes from no other web
site (``access.py``'s rule, the service's), the WebSocket's handshake too, before the
page sends anything. viser 1.1 checks neither: any site the user visits could open
``ws://127.0.0.1:PORT/``, read the gesture and press "Play on the robot".

viser opens its server through ``websockets.asyncio.server.serve`` in a thread of its
own, with no hook for this; ``install`` gives viser's module a view of the websockets
package whose ``serve`` puts the check before viser's own handling of each request.
Nothing else in the process sees a change.
"""

from __future__ import annotations

import http
import logging
import sys
from typing import Any

from ..access import foreign_host, foreign_origin, own_hosts
from ..errors import Diagnostic, GestError

HOST = "127.0.0.1"  #: this computer only: a page is a view, not a service


class _Overlay:
    """``base`` with some of its attributes replaced."""

    def __init__(self, base: Any, **over: Any):
        self._base, self._over = base, over

    def __getattr__(self, name: str) -> Any:
        return self._over[name] if name in self._over else getattr(self._base, name)


def refusal(headers: Any, port: int) -> str | None:
    """Why a request to the page on ``port`` is refused (None: it is the page's own)."""
    return foreign_host(headers, own_hosts(HOST, port)) or foreign_origin(headers)


def _guarded(process_request: Any) -> Any:
    """viser's ``process_request`` behind the check (a refusal: 403 and why, and the
    connection closed; nothing of the page sent)."""

    def check(connection: Any, request: Any) -> Any:
        try:
            why = refusal(request.headers, connection.local_address[1])
        except LookupError:  # websockets' MultipleValuesError: two of a header
            why = "a request naming two Hosts or two Origins is refused"
        if why:
            port = connection.local_address[1]
            print(f"the page on port {port} refused a request: {why}", file=sys.stderr)
            return connection.respond(http.HTTPStatus.FORBIDDEN, why + "\n")
        return None if process_request is None else process_request(connection, request)

    return check


class _OneLine(logging.Handler):
    """What viser's and websockets' own code says of a connection it could not read
    (garbage sent to the page): a line on standard error, not a traceback (through
    ``gestc lsp`` it lands in the editor's log)."""

    def emit(self, record: logging.LogRecord) -> None:
        exc = record.exc_info[1] if record.exc_info else None
        what = ("dropped a connection that sent what it cannot read" if exc is not None
                else record.getMessage())
        print(one_line(what, exc), file=sys.stderr)


def one_line(what: str, exc: BaseException | None) -> str:
    """The line said of a page's connection that failed (``what``, and ``exc``)."""
    why = f" ({type(exc).__name__}: {exc})" if exc is not None else ""
    text = f"the page {what}{why}".replace("\n", " ")
    return text if len(text) <= 200 else text[:200] + "...)"


def quiet(server: Any) -> None:
    """A failure in ``server``'s own event loop (a message it could not handle) told
    in a line, as websockets' are."""
    loop = getattr(getattr(server, "_websock_server", None), "_background_event_loop", None)
    if loop is None:
        return

    def told(_loop: Any, context: dict[str, Any]) -> None:
        what = context.get("message") or "could not handle a message"
        print(one_line(f"said: {what}", context.get("exception")), file=sys.stderr)

    loop.call_soon_threadsafe(loop.set_exception_handler, told)


def install() -> None:
    """Put the check on every viser server started from now on (once a process)."""
    try:
        from viser.infra import _infra

        real = _infra.websockets
        real.asyncio.server.serve  # noqa: B018 (where viser opens its server)
    except (ImportError, AttributeError):  # a viser this was not written for: no page
        raise GestError(Diagnostic(
            "error", "this viser opens its pages in a way not known here: they could not "
            "refuse other web sites", hint="pip install 'viser>=1.1,<2'")) from None
    if isinstance(real, _Overlay):
        return
    serve = real.asyncio.server.serve

    def guarded_serve(*args: Any, process_request: Any = None, **kwargs: Any) -> Any:
        return serve(*args, process_request=_guarded(process_request), **kwargs)

    said = logging.getLogger("websockets")
    said.addHandler(_OneLine(logging.WARNING))
    said.propagate = False
    server = _Overlay(real.asyncio.server, serve=guarded_serve)
    _infra.websockets = _Overlay(real, asyncio=_Overlay(real.asyncio, server=server))
