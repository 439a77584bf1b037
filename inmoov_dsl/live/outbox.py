"""What the drive loop sends, and what the boards hold (an edge: it writes to ports).

Each link's bytes go out as a continuous run timed by the wire (``wire.pace``),
written LIVE_HORIZON ahead; a take-over or a stop drops what is queued and not yet on
the wire. The ``Mirror`` reads each byte when it is due to arrive, so it holds what the
boards hold.
"""

from __future__ import annotations

from collections.abc import Sequence

from ..boards import controller
from ..compiling.compiled import Stream
from ..hardware import Profile
from ..protocol import PAIR_BYTES
from ..wire.pace import LIVE_HORIZON, pacer
from ..wire.player import SPIN, Link


class Mirror:
    """What each board holds, from the bytes sent to it (the board's own rules: its
    kind's ``core``)."""

    def __init__(self, profile: Profile, boards: Sequence[int]):
        by_id = {b.id: b for b in profile.boards}
        self.cores = [controller(profile, by_id[board]).core() for board in boards]
        where = {}
        for k, core in enumerate(self.cores):
            for j, servo in enumerate(core.servos):
                where[servo.id] = (k, j)
        self._where = [where[s.id] for s in profile.servos]
        self._by_id = {s.id: where[s.id] for s in profile.servos}
        self._order = {s.id: i for i, s in enumerate(profile.servos)}

    def set(self, pose: list[int]) -> None:
        """The boards hold ``pose`` (the profile's servo order)."""
        for (k, j), v in zip(self._where, pose, strict=True):
            self.cores[k].values[j] = v

    def feed(self, k: int, byte: int) -> None:
        """Board ``k`` reads ``byte``."""
        self.cores[k].feed(byte)

    def put(self, servo_id: int, value: int) -> bool:
        """Servo ``servo_id`` holds ``value`` (a pair heard on a stream); False if the
        profile has no such servo."""
        if servo_id not in self._by_id:
            return False
        k, j = self._by_id[servo_id]
        self.cores[k].values[j] = value
        return True

    def value(self, servo_id: int) -> int:
        """What servo ``servo_id`` holds."""
        k, j = self._by_id[servo_id]
        return self.cores[k].values[j]

    def held(self, then: dict[int, int] | None = None) -> list[int]:
        """What the boards hold, in the profile's servo order (``then``: once these
        servo IDs hold these values too)."""
        held = [self.cores[k].values[j] for k, j in self._where]
        for servo, value in (then or {}).items():
            if servo in self._order:
                held[self._order[servo]] = value
        return held


class Outbox:
    """The links' runs, and the bytes on their way that the Mirror has yet to read."""

    def __init__(self, links: Sequence[Link], profile: Profile):
        self.links = list(links)
        self.mirror = Mirror(profile, [link.board for link in links])
        by_id = {b.id: b for b in profile.boards}
        self.kinds = [link.controller or controller(profile, by_id[link.board])
                      for link in links]
        self.pacers = [pacer(link.port, kind, LIVE_HORIZON)
                       for link, kind in zip(self.links, self.kinds, strict=True)]
        #: (clock time, link, byte, the servo ID of a pair's value byte or None), in
        #: time order: not yet arrived, the Mirror reads them when due
        self.events: list[tuple[float, int, int, int | None]] = []
        #: each link's servos that a pair has been sent to: a stop sends them again
        self._touched: list[set[int]] = [set() for _ in self.links]

    def sending(self) -> bool:
        """Are bytes still to be written or to arrive?"""
        return bool(self.events) or any(p.pending() for p in self.pacers)

    def wake(self, t: float) -> float:
        """When a link needs topping up (a run's first byte: a moment before it is
        due) or the next byte arrives; ``inf`` if nothing is on its way."""
        wakes = [p.next_wake(t) - (0.0 if p.busy(t) else SPIN) for p in self.pacers]
        return min(wakes + [self.events[0][0] if self.events else float("inf")])

    def add(self, origin: float, streams: Sequence[Stream]) -> None:
        """Send ``streams`` (their times from clock time ``origin``) after what is on
        its way."""
        by_board = {link.board: k for k, link in enumerate(self.links)}
        events = []
        for stream in streams:
            k, times, data = by_board[stream.board], stream.times.tolist(), stream.data
            rig = self.kinds[k].ours  # its pairs are read ahead (``held``)
            for first, stop in self.kinds[k].commands(data):
                self.pacers[k].add(origin + times[first], data[first:stop])
                for i in range(first, stop):
                    pair = rig and stop - first == PAIR_BYTES and i > first
                    events.append((origin + times[i], k, data[i],
                                   data[first] if pair else None))
        self.events = sorted(self.events + events, key=lambda e: (e[0], e[1]))

    def relax(self, t: float) -> None:
        """Every board stops driving its servos, at once (its kind's ``relax``)."""
        for k, out in enumerate(self.pacers):
            data = self.kinds[k].relax()
            out.add(t, data)
            out.pump(t)
            for byte in data:
                self.mirror.feed(k, byte)

    def reach(self) -> float:
        """How far from the clock a byte's arrival is uncertain (s): a run is written
        up to its horizon ahead, placed on its grid, and may run late."""
        return max((p.horizon + p.tau for p in self.pacers), default=0.0)

    def held(self, t: float) -> list[int]:
        """What the boards hold once the bytes that may already be written by ``t``
        have arrived (a stop or a take-over now makes it so: ``discard``)."""
        values = {}
        for due, _, byte, servo in self.events:
            if due > t + self.reach():
                break
            if servo is not None:
                values[servo] = byte
        return self.mirror.held(values)

    def discard(self, t: float, resync: bool = True) -> None:
        """Nothing more of what was sent goes out: the runs stop and the ports drop what
        they hold. The values due within ``reach`` of ``t`` may or may not arrive, and a
        board that reads late (one in a simulator on a busy machine) may lose even older
        ones to the drop, so with ``resync`` each board is sent CANCEL and the value of
        every servo it has been sent (a value sent twice changes nothing; at most a pair
        a servo): it then holds what ``held`` said, as the Mirror does, however often
        stops come. A kind with no filler (a Maestro, a PCA9685) is written whole
        commands when they are due and its port drops nothing: what is due by ``t`` is
        written now, the rest never, and the board holds what the Mirror does."""
        for k, out in enumerate(self.pacers):
            if self.kinds[k].fill is None:
                out.pump(t)
        self._mirror(t)
        reach = t + self.reach()
        for due, k, byte, servo in self.events:  # a rig's bytes that may yet arrive
            if due <= reach and self.kinds[k].fill is not None:
                self.mirror.feed(k, byte)
                if servo is not None:
                    self._touched[k].add(servo)
        again = [{servo: self.mirror.value(servo) for servo in touched}
                 for touched in self._touched]
        self.events = []
        for k, out in enumerate(self.pacers):
            out.discard()
            if resync and self.kinds[k].fill is not None:
                out.add(t, self.kinds[k].set_values(again[k]))
                out.pump(t)

    def send(self, t: float) -> None:
        """Top the links up, and mirror what has arrived by ``t``."""
        for out in self.pacers:
            out.pump(t)
        self._mirror(t)

    def _mirror(self, t: float) -> None:
        """The Mirror reads what is due by ``t``; the servos its pairs set are
        remembered (a stop sends their values again)."""
        events = self.events
        n = 0
        while n < len(events) and events[n][0] <= t:
            _, k, byte, servo = events[n]
            self.mirror.feed(k, byte)
            if servo is not None:
                self._touched[k].add(servo)
            n += 1
        del events[:n]
