"""Commands written whole when they are due, and no faster than the board reads them:
the sender of a kind with no filler (``Timed``, which ``pace.pacer`` picks).

A board whose own loop, not the wire, bounds how fast it reads (MrlComm: each move makes
it publish servo events it waits to see out, about 1.6 ms) declares its receive buffer
and what each command costs it (``Controller.receive_buffer``, ``cost``). The sender
keeps that board's account: a command reaches it when the wire has sent it, the board
reads it once it is done with the one before, and is done with it ``cost`` later. A
command is in flight from its writing until the board is done with it, and one is
written only while what is in flight fits the buffer, so nothing the board cannot take
is sent, however late the computer wakes. When the board says what it has read
(``answer``: MrlComm's started event of each move) and the player passes on what it
sends (``heard``), a command also stays in flight until its answer has come: the account
then holds whatever the link's delays (a board simulated on a loaded machine reads late).

A command that is due and waits for room is superseded by a newer one of its ``key`` (a
move of the same servo) that is due too: after a stall, each servo is sent its newest
target once, not every overdue one. The clock time is an argument: tests run it on a
virtual clock.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Callable, Hashable
from dataclasses import dataclass
from itertools import islice

from ..boards.base import Controller
from ..clock import Clock, Sleep

LISTEN = 0.002  #: s; how often a sender waiting for its board's answers looks again
#: s; the longest the end of a play waits for a board to say it read all it was sent
#: (a board silent that long has stopped, and says so first: MrlComm's ``SILENT``)
CONFIRM = 3.0


@dataclass
class _Sent:
    """A command in flight: when the board is done with it (by the account), its size,
    and the answer still awaited (None: none, or it came)."""

    done: float
    size: int
    answer: Hashable | None


class Timed:
    """A link with no filler: each command written whole when it is due (the wire is
    idle between them), in the order given, within what the board can take
    (``controller``'s figures; None: all that is due, at once). ``answered``: the
    board's answers are passed to ``heard``, and awaited."""

    def __init__(self, port, tau: float, horizon: float = 0.0,
                 controller: Controller | None = None, answered: bool = False):
        self.port, self.tau, self.horizon = port, tau, horizon
        self.buffer: int | None = getattr(controller, "receive_buffer", None)
        self._kind = controller
        self._answers = controller.answers() if controller is not None and answered else None
        #: (due, command, key, answer awaited), in order
        self._queue: deque[tuple[float, bytes, Hashable | None, Hashable | None]] = deque()
        self._sent: deque[_Sent] = deque()
        self.flying = 0  #: bytes in flight (written, the board not done with them)
        self._free = -math.inf  # when the wire has sent everything written
        self._done = -math.inf  # when the board is done with the last command written
        self._now = -math.inf  # the last pump's time
        self.late = 0.0  #: s; the most a command was written after it was due
        self.most = 0  #: the most bytes it has had in flight
        self.superseded = 0  #: commands a newer one of their key made needless
        self.missed = 0  #: answers given up on (``_retire``)

    def pending(self) -> bool:
        """Are commands still to be written?"""
        return bool(self._queue)

    def add(self, t: float, command: bytes) -> None:
        """``command`` is due at clock time ``t`` (not before the one before it)."""
        if self._queue and self._queue[-1][0] > t:
            t = self._queue[-1][0]
        kind = self._kind
        key = kind.key(command) if kind is not None else None
        answer = kind.answer(command) if self._answers is not None else None
        self._queue.append((t, command, key, answer))

    def shift(self, dt: float) -> None:
        """Every command is due ``dt`` s later."""
        self._queue = deque((t + dt, *rest) for t, *rest in self._queue)

    def pump(self, now: float) -> None:
        """Write what is due by ``now`` and the board has room for, in one write."""
        self._now = now
        self._retire(now)
        n = self._coalesce(self._due(now))
        out = bytearray()
        start = max(now, self._free)
        while n and self._fits(len(self._queue[0][1])):
            t, command, _, answer = self._queue.popleft()
            n -= 1
            self.late = max(self.late, now - t)
            out += command
            cost = self._kind.cost(command) if self._kind is not None else 0.0
            self._done = max(start + len(out) * self.tau, self._done) + cost
            self._sent.append(_Sent(self._done, len(command), answer))
            self.flying += len(command)
        if out:
            self.port.write(bytes(out))
            self._free = start + len(out) * self.tau
            self.most = max(self.most, self.flying)

    def heard(self, data: bytes) -> None:
        """What the board sent: each answer says it has read its command and all before."""
        for said in self._answers(data) if self._answers is not None else ():
            for k, sent in enumerate(self._sent):
                if sent.answer is not None and sent.answer == said:
                    for before in islice(self._sent, k + 1):
                        before.answer = None
                    break

    def awaiting(self) -> int:
        """Commands written whose answer is awaited still."""
        return sum(sent.answer is not None for sent in self._sent)

    def unanswered(self) -> int:
        """Commands written whose answer has not come (awaited still, or given up on)."""
        return self.missed + self.awaiting()

    def busy(self, now: float) -> bool:
        """Is the wire still sending what was written?"""
        return self._free > now

    def next_wake(self, now: float) -> float:
        """When the next command is due, or the board has room for it (inf: none)."""
        if not self._queue:
            return math.inf
        due, command = self._queue[0][:2]
        if due > now or self._fits(len(command)):
            return due
        room, wake = self.buffer - self.flying, now
        for sent in self._sent:
            wake = max(wake, sent.done, now + LISTEN if sent.answer is not None else now)
            room += sent.size
            if room >= len(command):
                break
        return wake

    def discard(self) -> None:
        """Nothing more is written but what was due at the last ``pump`` and waits for
        room (one command a key at most): what the board is taken to hold (the drive
        loop's account) counts it sent."""
        while self._queue and self._queue[-1][0] > self._now:
            self._queue.pop()

    def _fits(self, size: int) -> bool:
        return self.buffer is None or not self._sent or self.flying + size <= self.buffer

    def _retire(self, now: float) -> None:
        """The commands the board is done with by ``now`` (and has answered). A board
        that has not answered for CONFIRM s past the account's time is not waited for
        again: the account alone paces what follows (the player says so in the end)."""
        if self._sent and self._sent[0].answer is not None and \
                now > self._sent[0].done + CONFIRM:
            self.missed += self.awaiting()
            for sent in self._sent:
                sent.answer = None
            self._answers = None
        while self._sent and self._sent[0].done <= now and self._sent[0].answer is None:
            self.flying -= self._sent.popleft().size

    def _due(self, now: float) -> int:
        n = 0
        while n < len(self._queue) and self._queue[n][0] <= now:
            n += 1
        return n

    def _coalesce(self, n: int) -> int:
        """Of the first ``n`` commands, drop each that a later one of its key makes
        needless (with no command of no key between them): how many are left."""
        keep, seen = [], set()
        for item in reversed(list(islice(self._queue, n))):
            key = item[2]
            if key is None:
                seen.clear()
            elif key in seen:
                self.superseded += 1
                continue
            else:
                seen.add(key)
            keep.append(item)
        for _ in range(n):
            self._queue.popleft()
        self._queue.extendleft(keep)  # (reversed twice: in order)
        return len(keep)


def awaited(sender: Timed, listen: Callable[[], object], now: Clock, sleep: Sleep,
            timeout: float = CONFIRM) -> int:
    """Listen (``listen``: what passes the board's answers on to ``sender``) until the
    board has answered every command ``sender`` wrote, or for ``timeout`` s: how many
    answers have not come."""
    deadline = now() + timeout
    while sender.awaiting() and now() < deadline:
        sleep(LISTEN)
        listen()
    return sender.unanswered()
