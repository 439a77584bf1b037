"""A request's compile work off the event loop (an edge): each check in a thread of its
own, AT_ONCE at a time (the others wait their turn on the loop, which goes on
answering), stopped when it has taken BUDGET seconds, and all stopped as the service
stops. The threads are daemons: none holds the process when it ends.

A check is stopped by an exception raised in its thread (CPython's
``PyThreadState_SetAsyncExc``): it takes effect at the thread's next Python step, so a
check in the middle of a long call into a library (a solver) ends when that call
returns. Where there is no such call (another interpreter), a check over its budget is
answered and left to end on its own.
"""

from __future__ import annotations

import asyncio
import contextlib
import ctypes
import ctypes.util
import threading
from collections.abc import Callable
from typing import Any, TypeVar

BUDGET = 120.0  #: s a request's check may take (the longest one a user sends: ~55 s)
AT_ONCE = 2  #: checks run at the same time; the others wait their turn

T = TypeVar("T")


class Overdue(BaseException):  # noqa: N818 (not an error of the check: its end)
    """Raised in a check's thread to stop it (a BaseException: no ``except Exception``
    of the compiler's keeps it)."""


class TooLong(Exception):  # noqa: N818
    """A check stopped: it took more than its budget, or the service stops."""

    def __init__(self, stopping: bool):
        super().__init__("the service stops" if stopping else "over budget")
        self.stopping = stopping


class _Job:
    """One check in its thread: its result or exception, handed to the loop."""

    def __init__(self, loop: asyncio.AbstractEventLoop, fn: Callable[[], Any]):
        self.loop, self.fn = loop, fn
        self.future: asyncio.Future = loop.create_future()
        self.lock = threading.Lock()
        self.done = False
        self.thread = threading.Thread(target=self._run, name="gestplay-check", daemon=True)

    def _run(self) -> None:
        try:
            try:
                outcome: tuple[bool, Any] = (True, self.fn())
            except BaseException as exc:  # noqa: BLE001 (handed to the loop)
                outcome = (False, exc)
            with self.lock:
                self.done = True
            release()
            self.loop.call_soon_threadsafe(self._hand, *outcome)
        except Overdue:  # stopped as it ended: nobody waits for it any more
            pass
        except RuntimeError:  # the loop has closed: the service has stopped
            pass

    def _hand(self, ok: bool, value: Any) -> None:
        if self.future.done():
            return
        if ok:
            self.future.set_result(value)
        elif isinstance(value, Overdue):
            self.future.set_exception(TooLong(False))
        else:
            self.future.set_exception(value)

    def stop(self) -> None:
        """Raise Overdue in the thread, if it is still checking."""
        with self.lock:
            if self.done or self.thread.ident is None:
                return
            ctypes.pythonapi.PyThreadState_SetAsyncExc(ctypes.c_ulong(self.thread.ident),
                                                       ctypes.py_object(Overdue))


def release() -> None:
    """Give back to the system the memory a check has freed (the C library keeps it for
    the thread's next allocations otherwise: a long service's memory would only grow);
    where the C library is glibc."""
    if _TRIM is not None:
        _TRIM(0)


def _malloc_trim():
    """glibc's ``malloc_trim``, or None."""
    with contextlib.suppress(OSError, AttributeError, TypeError):
        return ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6").malloc_trim
    return None


_TRIM = _malloc_trim()


class Work:
    """The checks of the service's requests."""

    def __init__(self, budget: float = BUDGET, at_once: int = AT_ONCE):
        self.budget, self.at_once = budget, at_once
        self.turns: asyncio.Semaphore | None = None  #: made on the loop, when first used
        self.running: set[_Job] = set()
        self.stopping = False

    async def run(self, fn: Callable[..., T], *args: Any) -> T:
        """``fn(*args)`` in a thread of its own, when its turn comes: its result, or its
        exception; TooLong when it takes more than the budget, or the service stops."""
        if self.turns is None:
            self.turns = asyncio.Semaphore(self.at_once)
        async with self.turns:
            if self.stopping:
                raise TooLong(True)
            job = _Job(asyncio.get_running_loop(), lambda: fn(*args))
            self.running.add(job)
            job.thread.start()
            try:
                return await asyncio.wait_for(asyncio.shield(job.future), self.budget)
            except TimeoutError:
                job.stop()
                job.future.cancel()  # what it may still hand over is for nobody
                raise TooLong(self.stopping) from None
            except asyncio.CancelledError:  # the request is given up (the service stops)
                job.stop()
                job.future.cancel()
                raise
            finally:
                self.running.discard(job)

    def stop(self) -> None:
        """Stop every check (the service stops; the loop's thread): each one's request is
        answered that the service stops."""
        self.stopping = True
        for job in list(self.running):
            job.stop()
            if not job.future.done():
                job.future.set_exception(TooLong(True))
