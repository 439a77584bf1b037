"""The rig: our firmware and the original project's, on an Arduino. Its byte protocol
(``protocol.py``, docs/protocol.md): the rules a board reads it by (``core``), a plan
as its timed bytes (``encode``), and the board as the rest of the package drives it
(``RigController``)."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ... import protocol
from ...decode import Replies
from .. import arduino
from ..arduino import Bootloader
from ..base import Controller, PlanLike, PoseReader
from . import encode as _encode
from .core import BoardCore


def commands(data: bytes) -> list[tuple[int, int]]:
    """(first, end) index of each command of ``data``: a signal (a byte above
    MAX_VALUE, the stream's CANCEL) alone, a servo ID with the value after it."""
    out = []
    i = 0
    while i < len(data):
        stop = i + 1 if data[i] > protocol.MAX_VALUE else min(i + protocol.PAIR_BYTES,
                                                              len(data))
        out.append((i, stop))
        i = stop
    return out


class DumpReader:
    """The reply to DUMP, read with the protocol's reader."""

    def __init__(self, board: int):
        self.replies = Replies(board)

    def feed(self, data: bytes) -> dict[int, int] | None:
        """The pose once the reply is whole."""
        found = self.replies.feed(data)
        return None if found is None else found[1]


class RigController(Controller):
    """A board running our firmware or the original: (servo ID, value) pairs in whole
    command degrees, CANCEL between commands, DUMP for the pose, RELAX."""

    kind = "rig"
    fill = protocol.Signal.CANCEL
    ours = True
    address = "servo ID"
    pose_reply = "DUMP reply"

    def commands(self, data: bytes) -> list[tuple[int, int]]:
        """The rig's commands (``commands``)."""
        return commands(data)

    def addresses(self) -> set[int]:
        """Its servos' IDs."""
        return {s.id for s in self.servos}

    def addressed(self, data: bytes) -> set[int]:
        """The servo IDs the pairs of ``data`` command."""
        return {sid for sid, _ in protocol.pairs(data)}

    def moves(self, data: bytes) -> list[tuple[int, int]]:
        """The stream's (servo ID, value) pairs."""
        return protocol.pairs(data)

    def encode(self, plan: PlanLike) -> tuple[np.ndarray, bytes]:
        """The plan as pairs, one per servo per 20 ms frame at most (``encode``)."""
        return _encode.encode(plan, self.board)

    def core(self) -> BoardCore:
        """The board's rules (``core.BoardCore``)."""
        return BoardCore.from_profile(self.profile, self.board)

    def set_values(self, values: Mapping[int, int]) -> bytes:
        """CANCEL, then a pair for each servo."""
        return protocol.frame(sorted(values.items()))

    def cancel(self) -> bytes:
        """CANCEL: a half-read pair is dropped."""
        return protocol.CANCEL_PENDING

    def relax(self) -> bytes:
        """CANCEL RELAX CANCEL (``protocol.RELAX_BOARD``)."""
        return protocol.RELAX_BOARD

    def ask_pose(self) -> bytes:
        """CANCEL DUMP."""
        return protocol.ASK_POSE

    def pose_reader(self) -> PoseReader:
        """The DUMP reply's reader for this board's ID."""
        return DumpReader(self.board.id)

    def bootloader(self) -> Bootloader:
        """Its Arduino's (``arduino`` in its ``[[board]]``)."""
        return arduino.bootloader(self.board.options)

    def probe(self) -> bytes:
        """CANCEL: a ready board answers WAIT."""
        return protocol.CANCEL_PENDING

    def ready(self, answer: bytes) -> bool:
        """A WAIT came."""
        return protocol.Signal.WAIT in answer

    def answered_late(self) -> str:
        """No WAIT, a DUMP reply."""
        return "sent no WAIT, but answered DUMP"

    def stop_sent(self) -> str:
        """CANCEL (``cancel``)."""
        return "CANCEL sent"

    def stop_held(self) -> str:
        """The board holds every servo where the last pair left it."""
        return "the hand holds its pose"
