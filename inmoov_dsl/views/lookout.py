"""The live preview's contacts, looked for aside (a thread): a plan's contacts take a
tenth of a second and more on the whole robot (``timeline.contacts``), so the page draws
a new plan at once and its contacts when they are found. Only the newest plan asked
for is looked at, once no newer one has come for QUIET seconds (while a person types,
the work, and the interpreter's lock it holds, would slow every key's page); the last
one found is kept, for the views of the same plan that follow (an edit elsewhere in the
file keeps the plan's tracks)."""

from __future__ import annotations

import dataclasses
import threading
import time
from collections.abc import Callable
from typing import Any

from ..compiling.plan import Plan
from .timeline import Mark, View, contacts

QUIET = 0.3  #: s without a newer plan before one's contacts are looked for


class Lookout:
    """Looks for the contacts of the newest plan it is given; tells ``found(plan,
    marks)`` (marks None: they cannot be looked for) from its thread."""

    def __init__(self, found: Callable[[Plan, tuple[Mark, ...] | None], None]):
        self.found = found
        self.last: tuple[Any, tuple[Mark, ...] | None] | None = None  #: (tracks, marks)
        self._wanted: Plan | None = None
        self._asked = 0.0  #: when it was asked for (time.monotonic)
        self._lock = threading.Lock()
        self._wake, self._closing = threading.Event(), threading.Event()
        self._thread = threading.Thread(target=self._run, name="live-contacts", daemon=True)
        self._thread.start()

    def known(self, plan: Plan) -> tuple[bool, tuple[Mark, ...] | None]:
        """(whether ``plan``'s contacts were found already, what they are)."""
        last = self.last
        if last is not None and last[0] is plan.tracks:
            return True, last[1]
        return False, None

    def filled(self, view: View) -> View:
        """``view`` with its contacts, when they were found already."""
        if view.contacts is not None or view.plan is None:
            return view
        known, marks = self.known(view.plan)
        return dataclasses.replace(view, contacts=marks or ()) if known else view

    def ask(self, plan: Plan) -> None:
        """Look for ``plan``'s contacts next (instead of any plan asked for before)."""
        with self._lock:
            self._wanted, self._asked = plan, time.monotonic()
        self._wake.set()

    def close(self) -> None:
        """Stop the thread (a look under way ends first)."""
        self._closing.set()
        self._wake.set()
        self._thread.join(timeout=5)

    def _run(self) -> None:
        while True:
            self._wake.wait()
            self._wake.clear()
            if self._closing.is_set():
                return
            while (left := self._asked + QUIET - time.monotonic()) > 0:
                if self._closing.wait(left):
                    return
            with self._lock:
                plan, self._wanted = self._wanted, None
            if plan is None:
                continue
            try:
                marks = contacts(plan)
            except Exception:  # noqa: BLE001 (the check is another module's; the page goes on)
                marks = None
            self.last = (plan.tracks, marks)
            self.found(plan, marks)
