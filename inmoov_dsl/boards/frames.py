"""What the kinds finer than a degree share: a plan sampled once per 20 ms servo frame
into the board's own unit, a command for the servos whose width changed (ending as the
frame ends), and a stream cut into its commands by their lengths.

A servo the gesture names is held at its target when it ends, even one named at the
value the plan starts it from, which no width change would ever write: a channel of
these kinds may send no pulses until written to (a PCA9685 as it powers up, a
Maestro's channel off), and the servo would hang limp. Such a servo is written once,
in the first frame with room. (Our firmware needs no such rule: it drives every servo
from boot, and its next write, whichever servo it is for, ends a RELAX for all.)
"""

from __future__ import annotations

from collections.abc import Callable, Mapping

import numpy as np

from .. import protocol
from .base import Controller, PlanLike


def per_frame(kind: Controller, plan: PlanLike,
              command: Callable[[Mapping[int, int]], bytes], most: int | None = None
              ) -> tuple[np.ndarray, bytes]:
    """Every frame, ``command`` (channel -> width in ``kind``'s unit) for the servos of
    ``kind``'s board whose width changed: the frame's plan at its end (not rounded to
    degrees), the command's last byte sent a byte-time before the frame ends. With
    ``most``, that many servos a frame at most, those furthest from their width first
    (the others follow in the frames after). Each servo the plan names whose width
    never changes is written once all the same, in the first frame with room
    (``_unheld``)."""
    frames = int(plan.duration / protocol.SERVO_FRAME) + 2
    ends = (np.arange(frames) + 1) * protocol.SERVO_FRAME
    index = [plan.profile.index(s.name) for s in kind.servos]
    track = [kind.units(j, plan.tracks[i].position(ends)).tolist()
             for j, i in enumerate(index)]
    held = _unheld(plan, index, track,
                  [int(kind.units(j, [plan.start[i]])[0]) for j, i in enumerate(index)])
    times: list[float] = []
    data = bytearray()
    for f in range(frames):
        behind = sorted((j for j in range(len(index)) if track[j][f] != held[j]),
                        key=lambda j: _lag(track[j][f], held[j]))[:most]
        changed = {}
        for j in sorted(behind):
            changed[kind.servos[j].pin] = held[j] = track[j][f]
        if changed:
            cmd = command(changed)
            times += (ends[f] - (len(cmd) - np.arange(len(cmd))) * kind.tau).tolist()
            data += cmd
    return np.asarray(times, dtype=float), bytes(data)


def _unheld(plan: PlanLike, index: list[int], track: list[list[int]], held: list[int]
            ) -> list[int | None]:
    """``held`` (each servo's width as the plan starts), None for each servo the plan
    names whose width ``track`` (per frame) never leaves it: one the stream must write
    once all the same."""
    return [None if i in plan.named and all(w == held[j] for w in track[j]) else held[j]
            for j, i in enumerate(index)]


def _lag(width: int, held: int | None) -> float:
    """How far behind a servo at ``held`` is (a servo to hold, None: last, 0)."""
    return 0.0 if held is None else -abs(width - held)


def split(data: bytes, length: Callable[[bytes, int], int]) -> list[tuple[int, int]]:
    """(first, end) index of each command of ``data``, ``length(data, i)`` bytes each."""
    out, i = [], 0
    while i < len(data):
        n = length(data, i)
        out.append((i, i + n))
        i += n
    return out
