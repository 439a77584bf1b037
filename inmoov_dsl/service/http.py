"""The service's HTTP edge (aiohttp, the optional extra ``serve``): the routes, the
guard on every request, the events WebSocket and the page.

The server runs in a thread of its own with its own event loop (``server.Server``);
the drive loop keeps the main thread (where Ctrl-C and SIGTERM arrive, and CANCEL goes
out as the command line's always does). A request's compile work runs in a check's
thread (``work``), never on the event loop. Requests reach the drive loop through
``Service``'s queue; what the loop tells comes back as events to every WebSocket.
"""

from __future__ import annotations

import asyncio
import json
import sys
import uuid
from importlib import metadata, resources
from typing import Any

from aiohttp import WSCloseCode, WSMsgType, web

from ..access import Guard
from ..errors import Diagnostic, GestError
from ..live.orders import Control
from . import core, openapi, work
from .hub import QUEUE, Lost, Service
from .work import TooLong

TICKER = web.AppKey("ticker", asyncio.Task)  #: the pose events' clock
SOCKETS = web.AppKey("sockets", set)  #: the open events sockets, closed as it stops
POSE_EVERY = 0.020  #: s between pose events while the hand moves, at most one per frame


def app(service: Service, guard: Guard) -> web.Application:
    """The routes."""
    application = web.Application(middlewares=[_guarded(guard)], client_max_size=core.MAX_BODY)
    application.add_routes([
        web.get("/", _page), web.get("/api/openapi.json", _openapi),
        web.get("/api/gestures", lambda r: _gestures(r, service)),
        web.post("/api/play", lambda r: _play(r, service)),
        web.post("/api/stop", lambda r: _control(r, service, "stop")),
        web.post("/api/relax", lambda r: _control(r, service, "relax")),
        web.get("/api/pose", lambda r: _pose(r, service)),
        web.get("/api/events", lambda r: _events(r, service)),
        web.get("/api/view", lambda r: _view(service)),
    ])
    application[SOCKETS] = set()
    application.on_startup.append(lambda a: _start_ticker(a, service))
    application.on_shutdown.append(_close_sockets)
    return application


def _json(body: Any, status: int = 200) -> web.Response:
    return web.json_response(body, status=status, headers={"Cache-Control": "no-store"})


def _guarded(guard: Guard):
    @web.middleware
    async def middleware(request: web.Request, handler):
        refused = guard.refuse(request.method, request.headers, request.query)
        if refused is not None:
            return _json(core.BadRequest(refused[1]).json(), refused[0])
        try:
            return await handler(request)
        except web.HTTPException as exc:
            if exc.status == 413:
                return _json(core.BadRequest(f"the body is larger than "
                                             f"{core.MAX_BODY:,} bytes").json(), 400)
            return _json(core.BadRequest(exc.reason).json(), exc.status)
        except (ConnectionResetError, asyncio.CancelledError):
            raise
        except Exception as exc:  # noqa: BLE001 (a person gets a line, never a traceback)
            print(f"gestplay serve: error: {type(exc).__name__}: {exc}", file=sys.stderr)
            return _json(core.BadRequest("the service could not answer this request").json(),
                         500)
    return middleware


async def _body(request: web.Request) -> dict[str, Any]:
    """A request's JSON object (an empty body is ``{}``): all of it, however many
    segments it comes in, and never more than MAX_BODY + 1 bytes of it read."""
    size = request.content_length
    if size is not None and size > core.MAX_BODY:
        raise core.BadRequest(f"the body is larger than {core.MAX_BODY:,} bytes")
    body = bytearray()
    while len(body) <= core.MAX_BODY:  # to its end (its Content-Length, or the last chunk)
        part = await request.content.read(core.MAX_BODY + 1 - len(body))
        if not part:
            break
        body += part
    if len(body) > core.MAX_BODY:
        raise core.BadRequest(f"the body is larger than {core.MAX_BODY:,} bytes")
    if not body.strip():
        return {}
    if request.content_type != "application/json":
        raise core.BadRequest("the body must be JSON, sent as Content-Type: application/json",
                              "curl --json '{\"gesture\": \"peace\"}' ...")
    return core.read_json(body)


async def _play(request: web.Request, service: Service) -> web.Response:
    """A play request: read on the loop, compiled and checked in a check's thread
    (``Work``: the loop goes on answering meanwhile), queued for the drive loop."""
    try:
        doc = await _body(request)
        order, warnings = await service.work.run(service.prepare, doc, _new_id())
    except core.BadRequest as exc:
        return _json(exc.json(), 400)
    except GestError as exc:  # it does not compile, or drives the robot into itself
        return _json(core.problem(exc), 422)
    except Lost as exc:
        return _lost(exc.boards)
    except TooLong as exc:
        return _too_long(exc)
    service.requests.put(order)
    said = {"warnings": [core.diagnostic(d) for d in warnings]} if warnings else {}
    return _json({"id": order.id, **said}, 202)


def _too_long(exc: TooLong) -> web.Response:
    """A check that was stopped: the service stops (503), or it took its budget (422)."""
    if exc.stopping:
        return _json({"error": "the service stops: the request was not checked"}, 503)
    return _json(core.problem(GestError(Diagnostic(
        "error", f"checking the request took more than {work.BUDGET:g} s: it was stopped",
        hint="send less in one request: a shorter text, fewer sounds"))), 422)


async def _control(request: web.Request, service: Service, kind: str) -> web.Response:
    try:
        doc = await _body(request)
    except core.BadRequest as exc:
        return _json(exc.json(), 400)
    if doc:
        return _json(core.BadRequest(f"/api/{kind} takes no fields").json(), 400)
    control = Control(kind, _new_id())  # type: ignore[arg-type]
    service.requests.put(control)
    return _json({"id": control.id})


def _lost(boards: set[int]) -> web.Response:
    boards = ", ".join(map(str, sorted(boards)))
    return _json({"error": f"board {boards} is not there: its link was lost",
                  "hint": "plug it back in: the service picks it up again"}, 503)


async def _view(service: Service) -> web.Response:
    try:  # making the view takes a moment: not on the loop
        return _json({"url": await service.work.run(service.view_url)})
    except TooLong as exc:
        return _too_long(exc)


async def _pose(request: web.Request, service: Service) -> web.Response:
    return _json(service.pose())


async def _gestures(request: web.Request, service: Service) -> web.Response:
    return _json(service.listing())


async def _openapi(request: web.Request) -> web.Response:
    return _json(openapi.document(_version(), core.MAX_BODY, core.MAX_LOOP))


def _version() -> str:
    try:
        return metadata.version("inmoov-dsl")
    except metadata.PackageNotFoundError:  # a source tree that was never installed
        return "0"


async def _page(request: web.Request) -> web.Response:
    page = resources.files(__package__).joinpath("page.html").read_text(encoding="utf-8")
    return web.Response(text=page, content_type="text/html", headers={
        "Cache-Control": "no-store", "Content-Security-Policy":
        "default-src 'self'; script-src 'unsafe-inline' 'self'; style-src 'unsafe-inline'; "
        "connect-src 'self' ws: ; img-src 'self' data:; frame-src http://127.0.0.1:*"})


async def _events(request: web.Request, service: Service) -> web.StreamResponse:
    ws = web.WebSocketResponse(heartbeat=20, max_msg_size=1024)
    try:
        await ws.prepare(request)
    except ValueError:  # aiohttp's word on a Sec-WebSocket-Key that is not ASCII
        return _json(core.BadRequest("the WebSocket handshake is malformed (its "
                                     "Sec-WebSocket-Key is not base64)").json(), 400)
    request.app[SOCKETS].add(ws)
    listener: asyncio.Queue = asyncio.Queue(QUEUE)
    service.listeners.add(listener)
    reader = asyncio.ensure_future(_drain(ws))
    try:
        while not ws.closed:
            getting = asyncio.ensure_future(listener.get())
            done, _ = await asyncio.wait({getting, reader}, return_when=asyncio.FIRST_COMPLETED)
            if reader in done:
                getting.cancel()
                break
            await ws.send_str(json.dumps(getting.result()))
    finally:
        service.listeners.discard(listener)
        request.app[SOCKETS].discard(ws)
        reader.cancel()
    return ws


async def _close_sockets(application: web.Application) -> None:
    """As the service stops: every events socket closed (going away), not waited on."""
    for ws in list(application[SOCKETS]):
        await ws.close(code=WSCloseCode.GOING_AWAY, message=b"the service stops")


async def _drain(ws: web.WebSocketResponse) -> None:
    """Read (and ignore) what a client sends, until it closes."""
    async for message in ws:
        if message.type in (WSMsgType.ERROR, WSMsgType.CLOSE):
            break


async def _start_ticker(application: web.Application, service: Service) -> None:
    application[TICKER] = asyncio.ensure_future(_tick(service))


async def _tick(service: Service) -> None:
    """A pose event at most every POSE_EVERY while the hand moves (and once as it
    stops), when the pose has changed: with the id of the request that moves it (the
    pose as it stops, too: the drive loop may have ended that request already; and
    none before the drive loop names the request that begins to move it)."""
    last, was_moving, mover = None, False, None
    while True:
        await asyncio.sleep(POSE_EVERY)
        moving, playing = service.moving(), service.drive.tracker.playing
        if moving and not was_moving and playing is None:
            continue  # a move is submitted, not begun: its request is named with its bytes
        mover = playing or (mover if was_moving else None)
        if service.listeners and (moving or was_moving):
            held = service.drive.mirror.held()
            if held != last:
                last = held
                if service.view is not None:
                    service.view.pose(held)
                service.publish({"event": "pose", "id": mover,
                                 "servos": dict(zip(service.profile.names, held,
                                                    strict=True))})
        was_moving = moving


def _new_id() -> str:
    return uuid.uuid4().hex[:12]
