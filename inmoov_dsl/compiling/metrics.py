"""How well a stream follows its plan: coverage, lag, tracking error, link use.

Measured from the bytes (read as a board reads them: ``decode.Reader`` with the
``BOARD`` policy) against the plan, not from the encoder's bookkeeping, so the figures
hold whatever the scheduler did.

- A servo *needs* frame f when, at the frame's start, its rounded plan differs from
  the value the board holds; it is *covered* when a fresh value arrives within the
  frame. (The board cannot be told a change before it happens: a change in the last
  slot of a frame can only reach the board in the next one, so need is judged where
  the board can first learn of it.)
- Lag: degrees between the plan and the value the board holds, at each frame's end.
- Tracking error: each value sent against the plan at the moment it arrived.
"""

from __future__ import annotations

import math
from collections.abc import Collection, Sequence
from dataclasses import dataclass

import numpy as np

from .. import protocol
from ..boards import Controller, controller
from ..boards.rig.encode import frame_ends, round_values
from ..decode import BOARD, Pair, Reader
from ..hardware import Board, Profile
from .compiled import Compiled, Stream
from .plan import Plan


@dataclass(frozen=True)
class LinkReport:
    """How one board's stream serves its plan."""

    board: int
    baud: int
    servos: int
    bytes: int
    values: int  #: servo values the board acts on; 0: the gesture leaves the board idle
    naive_bytes: int  #: every servo every frame for the whole gesture, plus CANCEL
    end: float  #: s; the last byte has arrived
    utilisation: float  #: share of the link's time in use, over the gesture (or the
    #: stream, if it ends later)
    peak_utilisation: float  #: in the busiest servo frame
    needed: int  #: servo-frames that needed a fresh value
    covered: int
    worst_lag: float  #: degrees behind the plan at a frame's end
    worst_lag_servo: str
    worst_lag_time: float
    max_error: float  #: degrees between a value sent and the plan at its arrival

    @property
    def coverage(self) -> float:
        """The share of the servo-frames needing a fresh value that got one."""
        return 1.0 if self.needed == 0 else self.covered / self.needed

    @property
    def idle(self) -> bool:
        """Does the gesture move none of the board's servos (its stream is signals only,
        the CANCEL every stream starts with)?"""
        return self.values == 0


def writes(stream: Stream, ids: Collection[int]) -> list[tuple[float, int, int]]:
    """(arrival time, servo ID, value) of every servo write a rig board with servos
    ``ids`` makes from the stream's bytes; a byte has arrived one byte-time after it was
    sent."""
    tau = stream.byte_time
    reader = Reader(BOARD)
    out = []
    for t, b in zip(stream.times.tolist(), stream.data, strict=True):
        for event in reader.feed(b):
            if isinstance(event, Pair) and event.id in ids:
                out.append((t + tau, event.id, event.value))
    return out


def targets(stream: Stream, kind: Controller) -> list[tuple[float, int, int]]:
    """(arrival time, servo ID, width in the board's unit) of every servo command of
    another kind's stream (a command has arrived a byte-time after its last byte)."""
    times = stream.times.tolist()
    return [(times[stop - 1] + kind.tau, sid, unit)
            for first, stop in kind.commands(stream.data)
            for sid, unit in kind.moves(stream.data[first:stop])]


def _board_ids(profile: Profile, board: Board) -> frozenset[int]:
    """The servo IDs ``board`` drives."""
    return frozenset(profile.servos[profile.index(name)].id for name in board.servos)


def sent_values(plan: Plan, compiled: Compiled) -> dict[int, tuple[np.ndarray, np.ndarray]]:
    """Servo index -> (arrival times, values) of every pair the boards act on."""
    return values_sent(plan.profile, compiled.streams)


def values_sent(profile: Profile, streams: tuple[Stream, ...]
                ) -> dict[int, tuple[np.ndarray, np.ndarray]]:
    """Servo index -> (arrival times, values) of every value ``streams`` set, each
    board read by its kind (another kind's widths as the whole values nearest them)."""
    index = {s.id: i for i, s in enumerate(profile.servos)}
    boards = {b.id: b for b in profile.boards}
    out: dict[int, tuple[list[float], list[int]]] = {}
    for stream in streams:
        board = boards[stream.board]
        if stream.kind == "rig":
            found = writes(stream, _board_ids(profile, board))
        else:
            kind = controller(profile, board)
            j = {s.id: k for k, s in enumerate(kind.servos)}
            found = [(t, sid, kind.widths[j[sid]].value(unit * kind.unit_us))
                     for t, sid, unit in targets(stream, kind)]
        for t, sid, value in found:
            times, values = out.setdefault(index[sid], ([], []))
            times.append(t)
            values.append(value)
    return {i: (np.asarray(t), np.asarray(v)) for i, (t, v) in out.items()}


def held_at(start: Sequence[int], sent: dict, times: np.ndarray) -> np.ndarray:
    """The value each servo's board holds at each of ``times``: [time][servo], from
    the ``start`` values (profile order) and the values ``sent`` (``values_sent``)."""
    out = np.empty((len(times), len(start)), dtype=np.int64)
    for i, first in enumerate(start):
        at, values = sent.get(i, (np.empty(0), np.empty(0, dtype=np.int64)))
        series = np.concatenate(([first], values)).astype(np.int64)
        out[:, i] = series[np.searchsorted(at, times, side="right")]
    return out


def measure(plan: Plan, streams: tuple[Stream, ...]) -> tuple[LinkReport, ...]:
    """A report for each stream: how well it follows ``plan``."""
    return tuple(_measure_board(plan, s) for s in streams)


def _scales(stream: Stream, kind: Controller, j: int, track):
    """How servo ``j`` of the board is measured: its plan in the board's unit, its plan
    in degrees, the board's units as degrees. A rig's are its whole values; another
    kind's widths, and the plan's, are degrees of the servo's span
    (``Controller.degrees``)."""
    if stream.kind == "rig":
        return round_values, track.position, lambda v: v
    return (lambda x: kind.units(j, x),
            lambda t: kind.degrees(j, kind.units(j, track.position(t))),
            lambda v: kind.degrees(j, v))


def _measure_board(plan: Plan, stream: Stream) -> LinkReport:
    profile = plan.profile
    board = next(b for b in profile.boards if b.id == stream.board)
    kind = controller(profile, board)
    tau = kind.tau
    events = writes(stream, _board_ids(profile, board)) if stream.kind == "rig" else \
        targets(stream, kind)
    end = float(stream.times[-1] + tau) if len(stream.times) else 0.0
    frames = int(max(end, plan.duration) / protocol.SERVO_FRAME) + 2
    ends = frame_ends(frames)
    starts = ends - protocol.SERVO_FRAME

    by_id: dict[int, list[tuple[float, int]]] = {}
    for t, sid, v in events:
        by_id.setdefault(sid, []).append((t, v))

    needed = covered = 0
    worst = (0.0, "", 0.0)
    max_error = 0.0
    for j, name in enumerate(board.servos):
        i = profile.index(name)
        track = plan.tracks[i]
        unit, plain, degrees = _scales(stream, kind, j, track)
        got = by_id.get(profile.servos[i].id, [])
        at = np.asarray([t for t, _ in got], dtype=float)
        values = np.asarray([unit(np.asarray([plan.start[i]]))[0]] + [v for _, v in got],
                            dtype=float)
        held_start = values[np.searchsorted(at, starts, side="right")]
        held_end = values[np.searchsorted(at, ends, side="right")]
        need = unit(track.position(starts)) != held_start
        values, held_end = degrees(values), degrees(held_end)
        fresh = np.searchsorted(at, ends, side="right") > np.searchsorted(at, starts,
                                                                          side="right")
        needed += int(need.sum())
        covered += int((need & fresh).sum())
        lag = np.abs(plain(ends) - held_end)
        k = int(np.argmax(lag))
        if lag[k] > worst[0]:
            worst = (float(lag[k]), name, float(ends[k]))
        if len(at):
            max_error = max(max_error, float(np.abs(values[1:] - plain(at)).max()))

    busy = np.bincount(np.minimum((stream.times / protocol.SERVO_FRAME).astype(int),
                                  frames - 1), minlength=frames)
    gesture_frames = max(1, math.ceil(plan.duration / protocol.SERVO_FRAME))
    length = max(end, plan.duration)
    return LinkReport(
        board=stream.board, baud=stream.baud, servos=len(board.servos),
        bytes=len(stream.data), values=len(events),
        naive_bytes=1 + protocol.PAIR_BYTES * len(board.servos) * gesture_frames,
        end=end,
        utilisation=len(stream.data) * tau / length if length > 0 else 0.0,
        peak_utilisation=float(busy.max() * tau / protocol.SERVO_FRAME),
        needed=needed, covered=covered,
        worst_lag=worst[0], worst_lag_servo=worst[1], worst_lag_time=worst[2],
        max_error=max_error,
    )
