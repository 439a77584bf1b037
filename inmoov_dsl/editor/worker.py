"""Where the editor's server computes (an edge: a thread of its own): every analysis and
every answer read from one, so that the server's loop only talks to the editor and
answers whatever it is asked while a long file is analysed.

One thread does it all, so that no analysis (its memo, the program's resolver) is ever
used by two at once. A document's analysis is a ``Job``: loaded (``analysis.loaded``),
then checked gesture by gesture (``analysis.checked``), then each plan's contacts looked
for (``analysis.touched``: the editor has the rest of the diagnostics meanwhile); between
two gestures (and within a long plan's contacts) the thread
answers the requests waiting (``call``), stops a job whose document has a newer version
(the gestures checked so far are kept in its memo: the next version's check starts
from them), and lets another document's job go first once this one has had its turn."""

from __future__ import annotations

import logging
import threading
import time
import traceback
from collections import deque
from collections.abc import Callable
from concurrent.futures import Future
from dataclasses import dataclass
from typing import Any

from ..errors import Diagnostic, Pos
from .analysis import Analysis, checked, loaded, touched
from .memo import Memo

log = logging.getLogger(__name__)

TURN = 0.25  #: s a job checks while another waits, before it lets that one go first
STILL = 0.2  #: s the text stays the same before its contacts are looked for (typing: not)


class Stopped(Exception):
    """The job's document has a newer version, or is closed."""


class _Turn(Exception):
    """Another document waits: this job goes back in line."""


@dataclass(eq=False)
class Job:
    """The analysis of one version of one document: its text, the file it is, the
    settings it is read with, the document's memo; what is done of it (``loaded``)."""

    uri: str
    text: str
    path: str
    robot: str
    library: tuple[str, ...]
    memo: Memo
    loaded: Analysis | None = None
    found: Analysis | None = None  #: checked (told), its contacts not yet looked for
    still_until: float | None = None  #: when its contacts may be looked for (monotonic)
    stopped: bool = False  #: a newer version came, or the document closed
    turns: int = 0  #: how many times it let another go first


Deliver = Callable[[Job, Analysis], None]  #: called in the thread with each result


class Worker:
    """The thread, its jobs (one per document: its newest version) and the calls
    waiting for it. ``deliver`` gets each job's loaded analysis, then its checked one,
    then (when they add to it) the one with its contacts, in the thread."""

    def __init__(self, deliver: Deliver, still: float = STILL) -> None:
        self._deliver = deliver
        self.still = still  #: s a text stays the same before its contacts are looked for
        self._lock = threading.Condition()
        self._jobs: dict[str, Job] = {}  #: waiting, first come first
        self._calls: deque[tuple[Callable[[], Any], Future]] = deque()
        self._running: Job | None = None
        self._thread: threading.Thread | None = None

    def submit(self, job: Job) -> None:
        """Analyse ``job``; the document's older job stops (waiting or running)."""
        with self._lock:
            self._stop(job.uri)
            self._jobs[job.uri] = job
            self._wake()

    def stop(self, uri: str) -> None:
        """Analyse the document ``uri`` no more (it closed)."""
        with self._lock:
            self._stop(uri)
            self._lock.notify()  # (a job waiting for its text to stay the same ends)

    def call(self, fn: Callable[[], Any]) -> Future:
        """``fn()`` run in the thread as soon as it is between two steps: its result
        (or its exception) in the future. A future cancelled before it runs is not
        run."""
        future: Future = Future()
        with self._lock:
            self._calls.append((fn, future))
            self._wake()
        return future

    def _stop(self, uri: str) -> None:
        old = self._jobs.pop(uri, None)
        if old is not None:
            old.stopped = True
        if self._running is not None and self._running.uri == uri:
            self._running.stopped = True

    def _wake(self) -> None:
        if self._thread is None:
            self._thread = threading.Thread(target=self._loop, name="gest-analysis",
                                            daemon=True)
            self._thread.start()
        self._lock.notify()

    def _loop(self) -> None:
        while True:
            with self._lock:
                while not self._jobs and not self._calls:
                    self._lock.wait()
                job = None
                if self._jobs and not self._calls:
                    job = self._jobs.pop(next(iter(self._jobs)))
                    self._running = job
            try:
                if job is None:
                    self._answer()
                else:
                    self._analyse(job)
            except Exception:  # noqa: BLE001 - the thread goes on: a bug is logged
                log.exception("the analysis thread")
            finally:
                with self._lock:
                    self._running = None

    def _answer(self) -> None:
        """Run the calls waiting, in order."""
        while True:
            with self._lock:
                if not self._calls:
                    return
                fn, future = self._calls.popleft()
            if not future.set_running_or_notify_cancel():
                continue
            try:
                future.set_result(fn())
            except BaseException as exc:  # noqa: BLE001 - the caller's to tell
                future.set_exception(exc)

    def _analyse(self, job: Job) -> None:
        """Load ``job`` (told), then check it in steps (told), unless it stops."""
        began = time.monotonic()

        def step() -> None:
            self._answer()
            if job.stopped:
                raise Stopped
            if self._jobs and time.monotonic() - began > TURN * 4 ** job.turns:
                raise _Turn

        try:
            if job.loaded is None:
                job.loaded = loaded(job.text, job.path, job.robot, job.library, job.memo)
                if job.stopped:
                    return
                self._deliver(job, job.loaded)
            if job.found is None:
                job.found = checked(job.loaded, job.memo, step)
                if job.stopped:
                    return
                self._deliver(job, job.found)
            self._until_still(job, step)
            found = touched(job.found, job.memo, step)
            if len(found.diagnostics) == len(job.found.diagnostics):
                return  # no contact: nothing more to tell
        except Stopped:
            return
        except _Turn:
            with self._lock:
                if not job.stopped and job.uri not in self._jobs:
                    job.turns += 1
                    self._jobs[job.uri] = job
            return
        except Exception as exc:  # noqa: BLE001 - a bug: told in the file, not a crash
            log.exception("analysing %s", job.uri)
            found = failed(job, exc)
        if not job.stopped:
            self._deliver(job, found)

    def _until_still(self, job: Job, step: Callable[[], None]) -> None:
        """Wait until ``still`` s after the job was checked (answering the calls that
        come), unless a newer version of the document comes first (``step`` raises):
        while a person types, the costly check of the robot's parts waits and the page
        and the diagnostics have the thread. A document waiting for its diagnostics
        goes first meanwhile (the job goes back in line)."""
        if job.still_until is None:
            job.still_until = time.monotonic() + self.still
        while True:
            step()
            with self._lock:
                if any(other.found is None for other in self._jobs.values()):
                    raise _Turn
                left = job.still_until - time.monotonic()
                if left <= 0:
                    return
                if not self._calls and not job.stopped:
                    self._lock.wait(left)


def failed(job: Job, exc: Exception) -> Analysis:
    """What the editor is told when analysing ``job`` raised: an error at the top of
    the file, naming the exception and where it was raised (a bug of the server)."""
    where = traceback.extract_tb(exc.__traceback__)[-1] if exc.__traceback__ else None
    at = f" (at {where.filename}:{where.lineno})" if where else ""
    message = f"gestc lsp failed on this text: {type(exc).__name__}: {exc}{at}"
    return Analysis(job.text, job.path, diagnostics=[Diagnostic(
        "error", message, Pos(job.path, 1, 1), "a bug of the language server: please "
        "report it with this file")], checked=True)
