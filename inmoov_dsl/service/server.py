"""The HTTP server in a thread of its own, with its own event loop (an edge): started
before the drive loop takes the main thread, stopped within STOPPING s when it ends
(Ctrl-C, SIGTERM): the checks under way stopped, each request given SHUTDOWN s to be
answered."""

from __future__ import annotations

import asyncio
import logging
import threading

from aiohttp import web

from ..access import Guard
from .http import app
from .hub import Service
from .log import one_line

SHUTDOWN = 1.0  #: s a request has to be answered as the service stops
STOPPING = 5.0  #: s the server's thread may take to stop; then the service ends anyway


class Server:
    """The HTTP server in its own thread."""

    def __init__(self, service: Service, guard: Guard, host: str, port: int):
        self.service, self.guard, self.host, self.port = service, guard, host, port
        self.ready = threading.Event()
        self.error: BaseException | None = None
        self.thread = threading.Thread(target=self._run, name="gestplay-serve", daemon=True)

    def start(self) -> int:
        """Listen; the port it listens on (``port`` 0: a free one). OSError if it cannot."""
        self.thread.start()
        self.ready.wait()
        if self.error is not None:
            raise self.error
        return self.port

    def _run(self) -> None:
        loop = asyncio.new_event_loop()
        self.service.loop = loop
        try:
            loop.run_until_complete(self._serve())
        except BaseException as exc:  # noqa: BLE001 (handed to the thread that started it)
            self.error = exc
            self.ready.set()
        finally:  # a client that sent half a request still has its handler waiting
            pending = asyncio.all_tasks(loop)
            for task in pending:
                task.cancel()
            loop.run_until_complete(asyncio.gather(*pending, return_exceptions=True))
            loop.close()

    async def _serve(self) -> None:
        one_line(logging.getLogger("aiohttp.server"))
        runner = web.AppRunner(app(self.service, self.guard), access_log=None,
                               handle_signals=False, shutdown_timeout=SHUTDOWN)
        await runner.setup()
        site = web.TCPSite(runner, self.host, self.port, reuse_address=True)
        await site.start()
        self.port = runner.addresses[0][1]
        self.guard.bind(self.port)
        self.stopping = asyncio.Event()
        self.ready.set()
        try:
            await self.stopping.wait()
        finally:
            await runner.cleanup()

    def stop(self) -> None:
        """Stop listening: the checks under way stopped (their requests answered 503),
        then every request given SHUTDOWN s to be answered; at most STOPPING s in all."""
        loop = self.service.loop
        if loop is not None and self.thread.is_alive() and hasattr(self, "stopping"):
            loop.call_soon_threadsafe(self._stop)
            self.thread.join(timeout=STOPPING)

    def _stop(self) -> None:
        self.service.work.stop()
        self.stopping.set()
