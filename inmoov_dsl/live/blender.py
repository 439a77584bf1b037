"""Blender Servo Animation's live mode as a puppeteer's input (``gestplay blender``):
while the artist scrubs or plays in Blender, its add-on sends each servo's new position
as a command (``<``, ID, two bytes, ``>``) in a binary WebSocket message; they are read
as BSA's own library reads them (``interchange.bsa.Commands``) and each becomes the
servo's value, for the drive loop (``puppet.Puppet``: limits, the guard refusing a move
into the body, the pose held at the end).

The listener is a WebSocket server in a thread of its own (aiohttp, the ``serve``
extra), guarded as the service is (``access.Guard``): loopback by default and then only
its own ``Host``; any other address needs a token (``?token=`` in the add-on's path); a
request from a web page (an ``Origin`` not its own) is refused before the handshake.
"""

from __future__ import annotations

import asyncio
import queue
import threading
import time
from collections.abc import Callable, Mapping

import numpy as np

from ..access import Guard
from ..boards.pulses import widths
from ..errors import Diagnostic, GestError
from ..hardware import Servo
from ..interchange.bsa import Commands
from ..interchange.frames import from_units
from .puppet import Got, Reading

MAX_MESSAGE = 1024  #: bytes in one WebSocket message (a command is 5)
STOPPING = 5.0  #: s the server is given to stop


class Listener:
    """Blender's commands as ``(s, ID, position)``, an input of ``Puppet``."""

    def __init__(self, host: str, port: int, token: str | None):
        from aiohttp import web

        self.web, self.guard = web, Guard(host, port, token)
        self.host, self.port = host, port
        self.got: queue.SimpleQueue[tuple[float, int, int]] = queue.SimpleQueue()
        self.ready, self.error = threading.Event(), None
        self.thread = threading.Thread(target=self._run, name="blender", daemon=True)
        self.thread.start()
        self.ready.wait(STOPPING)
        if self.error is not None or not self.ready.is_set():
            raise GestError(Diagnostic("error", f"cannot listen on {host}:{port}: "
                                       f"{self.error or 'it did not start'}",
                                       hint="another port: --listen 127.0.0.1:0"))

    def _run(self) -> None:
        self.loop = asyncio.new_event_loop()
        try:
            self.loop.run_until_complete(self._serve())
        except BaseException as exc:  # noqa: BLE001 (told by the thread that started it)
            self.error = exc
            self.ready.set()
        finally:
            self.loop.close()

    async def _serve(self) -> None:
        web = self.web
        app = web.Application()
        app.add_routes([web.get("/{tail:.*}", self._socket)])
        runner = web.AppRunner(app, access_log=None, handle_signals=False)
        await runner.setup()
        await web.TCPSite(runner, self.host, self.port, reuse_address=True).start()
        self.port = runner.addresses[0][1]
        self.guard.bind(self.port)
        self.stopping = asyncio.Event()
        self.ready.set()
        try:
            await self.stopping.wait()
        finally:
            await runner.cleanup()

    async def _socket(self, request):
        web = self.web
        refused = self.guard.refuse(request.method, request.headers, request.query)
        if refused is not None:
            return web.Response(status=refused[0], text=refused[1] + "\n")
        ws = web.WebSocketResponse(max_msg_size=MAX_MESSAGE, heartbeat=20)
        if not ws.can_prepare(request).ok:
            return web.Response(status=400, text="a WebSocket: ws://HOST:PORT/\n")
        await ws.prepare(request)
        reader = Commands()
        async for message in ws:
            if message.type == web.WSMsgType.BINARY:
                for byte in message.data:
                    if (moved := reader.feed(byte)) is not None:
                        self.got.put((time.monotonic(), *moved))
        return ws

    def wait(self, timeout: float) -> Got:
        """The commands that came within ``timeout`` s (all that have, once one has)."""
        try:
            out = [self.got.get(timeout=max(timeout, 0.0))]
        except queue.Empty:
            return False
        while not self.got.empty():
            out.append(self.got.get_nowait())
        return out

    def close(self) -> None:
        """Stop listening."""
        if self.thread.is_alive() and hasattr(self, "stopping"):
            self.loop.call_soon_threadsafe(self.stopping.set)
            self.thread.join(STOPPING)


def reading(servos: Mapping[int, Servo], unit: str, tick: float,
            unknown: Callable[[int], None]) -> Reading:
    """Blender's (s, ID, position) as (s, servo ID, value): the servo an ID is
    (``servos``), the position (in ``unit``) as its nearest whole value within its
    range; an ID of no servo is passed to ``unknown`` (once each) and left out."""
    told: set[int] = set()

    def read(got: list) -> list[tuple[float, int, int]]:
        out = []
        for t, sid, position in got:
            servo = servos.get(sid)
            if servo is None:
                if sid not in told:
                    told.add(sid)
                    unknown(sid)
                continue
            us = float(from_units(np.asarray([position]), unit, tick)[0])
            value = min(max(widths(servo).value(us), servo.lo), servo.hi)
            out.append((t, servo.id, value))
        return out
    return read
