"""Encode a plan into timed streams, one per board (stage 4), each by its board's kind
(``boards/``: the rig's pairs, a Maestro's targets, a PCA9685's registers)."""

from __future__ import annotations

from ..boards import controller
from .compiled import Stream
from .plan import Plan


def encode(plan: Plan) -> tuple[Stream, ...]:
    """One timed stream per board of the plan's profile."""
    streams = []
    for board in plan.profile.boards:
        times, data = controller(plan.profile, board).encode(plan)
        streams.append(Stream(board.id, board.baud, times, data, board.kind))
    return tuple(streams)
