"""A plan as the rig protocol's timed bytes for one board.

The stream opens with CANCEL, then ``(servo ID, value)`` pairs. Time is cut into
20 ms servo frames, ``(f * 20 ms, (f + 1) * 20 ms]``; a servo takes one value per
frame, so each servo gets at most one pair per frame, and only when the rounded
plan moved. Pairs are packed at the end of their frame so the board holds the
freshest value when the frame closes; each value is the plan at the pair's slot,
rounded to a whole degree.

Every byte sits on the link's byte grid, a whole number of byte-times after the
stream's CANCEL: a pair arrives at the last grid point at or before its slot (less than
a byte-time early). A player that fills the gaps with CANCEL (``wire.pace``) sends a
continuous stream in which every byte's time is fixed by its place: the UART's clock
keeps the schedule, not the operating system's.

When a board's servos all fit in a frame (6 servos need 6 of the 9 pair slots at
9600 baud), each servo has its own slot and the schedule is computed with numpy.
When they do not, every frame's slots go to the servos furthest behind their plan.
"""

from __future__ import annotations

import math

import numpy as np

from ... import protocol
from ..base import PlanLike


def frame_ends(count: int) -> np.ndarray:
    """End of servo frames 0..count-1; frame f is (f * 20 ms, (f + 1) * 20 ms]."""
    return (np.arange(count) + 1) * protocol.SERVO_FRAME


def grid_points(times: np.ndarray, tau: float) -> np.ndarray:
    """The last byte-time grid point at or before each of ``times`` (a whole number of
    byte-times ``tau`` after the stream's start), as that number."""
    return np.floor(np.asarray(times) / tau + 1e-9).astype(np.int64)


def round_values(x: np.ndarray) -> np.ndarray:
    """Positions (planned or recorded) as servo values: rounded half up to whole degrees
    (numpy's round is half to even), within 0..MAX_VALUE."""
    return np.clip(np.floor(np.asarray(x) + 0.5), 0, protocol.MAX_VALUE).astype(np.int64)


def encode(plan: PlanLike, board) -> tuple[np.ndarray, bytes]:
    """``board``'s servos of ``plan``: each byte's time and the bytes."""
    profile = plan.profile
    frames = int(plan.duration / protocol.SERVO_FRAME) + 2  # the last frame is past the end
    ends = frame_ends(frames)
    servos = [profile.index(name) for name in board.servos]
    slots = protocol.pairs_per_frame(board.baud)
    pair_time = protocol.PAIR_BYTES * protocol.byte_time(board.baud)
    if len(servos) <= slots:
        events = _fixed_slots(plan, servos, ends, pair_time)
    else:
        events = _furthest_behind(plan, servos, ends, pair_time, slots)
    return _serialise(board.baud, events)


def _fixed_slots(plan: PlanLike, servos: list[int], ends: np.ndarray, pair_time: float):
    """Servo j of n arrives (n-1-j) pair times before each frame's end."""
    arrivals, ids, values = [], [], []
    n = len(servos)
    for j, i in enumerate(servos):
        track = plan.tracks[i]
        if len(track.breaks) == 1 and track.coefs[0, 0] == plan.start[i]:
            continue  # it never moves: nothing to send
        at = ends - (n - 1 - j) * pair_time
        q = round_values(track.position(at))
        previous = np.concatenate(([plan.start[i]], q[:-1]))
        changed = q != previous
        arrivals.append(at[changed])
        values.append(q[changed])
        ids.append(np.full(int(changed.sum()), plan.profile.servos[i].id))
    if not arrivals:
        return np.empty(0), np.empty(0, dtype=np.int64), np.empty(0, dtype=np.int64)
    return np.concatenate(arrivals), np.concatenate(ids), np.concatenate(values)


def _furthest_behind(plan: PlanLike, servos: list[int], ends: np.ndarray, pair_time: float,
                     slots: int):
    """A link too slow for every servo every frame: slots go to the largest lag first."""
    tracks = [plan.tracks[i] for i in servos]
    ids = [plan.profile.servos[i].id for i in servos]
    held = [float(plan.start[i]) for i in servos]
    out_a: list[float] = []
    out_id: list[int] = []
    out_v: list[int] = []
    chunk = max(1, 2_000_000 // (slots * len(servos)))
    for first in range(0, len(ends), chunk):
        block = ends[first:first + chunk]
        at_end = np.stack([t.position(block) for t in tracks], axis=1).tolist()
        # the rounded plan at every slot of every frame of the block: [slot][frame][servo]
        at_slot = [
            round_values(np.stack([t.position(block - m * pair_time) for t in tracks],
                                  axis=1)).tolist()
            for m in range(slots)
        ]
        for f, row in enumerate(at_end):
            behind = [(abs(x - h), j) for j, (x, h) in enumerate(zip(row, held, strict=True))
                      if math.floor(x + 0.5) != h]
            if not behind:
                continue
            behind.sort(reverse=True)
            # packed at the frame's end, the servo furthest behind first
            slot = min(len(behind), slots) - 1
            for _, j in behind:
                if slot < 0:
                    break
                value = at_slot[slot][f][j]
                if value == held[j]:
                    continue
                out_a.append(float(block[f] - slot * pair_time))
                out_id.append(ids[j])
                out_v.append(value)
                held[j] = value
                slot -= 1
    return np.asarray(out_a, dtype=float), np.asarray(out_id), np.asarray(out_v)


def _serialise(baud: int, events) -> tuple[np.ndarray, bytes]:
    """The stream of ``events`` (arrival times, servo IDs, values): ``protocol.frame``'s
    bytes, each pair's ID sent two byte-times and its value one before it arrives, the
    arrival moved to the last point of the byte grid at or before it (less than a
    byte-time early; the value is the plan's at the slot's own time)."""
    arrivals, ids, values = events
    order = np.argsort(arrivals, kind="stable")
    arrivals, ids, values = arrivals[order], ids[order], values[order]
    tau = protocol.byte_time(baud)
    arrived = grid_points(arrivals, tau)
    sent = np.stack([arrived - 2, arrived - 1], axis=1).ravel()
    times = np.concatenate(([0], sent)) * tau  # CANCEL at 0
    data = protocol.frame(zip(ids.tolist(), values.tolist(), strict=True))
    return times, data
