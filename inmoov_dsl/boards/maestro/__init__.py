"""Pololu Maestro (Micro 6, Mini 12/18/24) on its USB Command Port: a plan as targets
in quarter-microseconds (``commands.py``), one update per 20 ms servo frame while a
servo moves, the virtual Maestro (``device.py``)."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ..base import Controller, PlanLike, PoseReader
from ..frames import per_frame
from . import commands as c
from .device import MaestroCore


def echoes(question: bytes, answer: bytes) -> bool:
    """Is ``answer`` the start of ``question`` sent back (a port that echoes)?"""
    return bool(answer) and question.startswith(bytes(answer))


class _Positions:
    """The answers to Get Position, one channel after another."""

    def __init__(self, controller: MaestroController):
        self.controller, self.data = controller, bytearray()

    def feed(self, data: bytes) -> dict[int, int] | None:
        """The pose once every channel has answered (a channel sending no pulses: the
        servo's rest, since where it is cannot be known); never from a port that
        echoes the questions (a loopback: a Maestro's answers are 2 bytes each, and no
        six of them spell the questions)."""
        self.data += data
        servos = self.controller.servos
        n = 2 * len(servos)
        if len(self.data) < n or echoes(self.controller.ask_pose(), self.data[:n]):
            return None
        pose = {}
        for j, s in enumerate(servos):
            q = self.data[2 * j] | self.data[2 * j + 1] << 8
            pose[s.id] = self.controller.widths[j].value(q / c.QUARTERS) if q else s.rest
        return pose


class MaestroController(Controller):
    """A Maestro: Set Target per servo (Set Multiple Targets on a Mini, for channels
    next to each other), the Pololu protocol when the profile gives a device number."""

    kind = "maestro"
    pose_reply = "answer to Get Position"
    unheard = "is the Maestro powered, and this its Command Port (the first of its two), " \
        "in serial mode USB Dual Port?"
    unit_us = 1 / c.QUARTERS

    @property
    def model(self) -> str:
        """``micro6``, ``mini12``, ``mini18`` or ``mini24``."""
        return ("micro6", "mini12", "mini18", "mini24")[self.board.option("model", 1)]

    @property
    def device(self) -> int | None:
        """The device number of the Pololu protocol (None: the compact protocol)."""
        d = self.board.option("device", -1)
        return None if d < 0 else d

    def commands(self, data: bytes) -> list[tuple[int, int]]:
        """Its commands, by Pololu's table."""
        return c.commands(data)

    def addressed(self, data: bytes) -> set[int]:
        """The channels its targets set."""
        return c.channels(data)

    def unanswered(self) -> str:
        """The Command Port, and the serial mode that lets it answer."""
        return "give the Maestro's Command Port (the first of its two ports), set its " \
               "serial mode to USB Dual Port in Maestro Control Center " \
               "(docs/controllers.md), or list the ports: gestplay ports"

    def moves(self, data: bytes) -> list[tuple[int, int]]:
        """(servo ID, quarter-us) of each target set for a servo of the board."""
        ids = {s.pin: s.id for s in self.servos}
        return [(ids[ch], q) for ch, q in c.targets(data) if ch in ids]

    def units(self, index: int, values) -> np.ndarray:
        """Quarter-microseconds."""
        return self.quarters(index, values)

    def quarters(self, index: int, values) -> np.ndarray:
        """Servo ``index``'s ``values`` (kept in its range) as targets."""
        us = self.widths[index].us(self.limit(np.asarray(values, dtype=float), index))
        return np.round(us * c.QUARTERS).astype(np.int64)

    def targets(self, changed: Mapping[int, int]) -> bytes:
        """Channel -> quarters as commands: runs of channels next to each other in one
        Set Multiple Targets on a Mini, else a Set Target each."""
        if self.model == "micro6":
            return b"".join(c.set_target(ch, q, self.device) for ch, q in
                            sorted(changed.items()))
        out, run = bytearray(), []
        for ch in sorted(changed):
            if run and ch != run[-1] + 1:
                out += self._run(run, changed)
                run = []
            run.append(ch)
        return bytes(out + (self._run(run, changed) if run else b""))

    def _run(self, channels: list[int], changed: Mapping[int, int]) -> bytes:
        if len(channels) == 1:
            return c.set_target(channels[0], changed[channels[0]], self.device)
        return c.set_targets(channels[0], [changed[ch] for ch in channels], self.device)

    def encode(self, plan: PlanLike) -> tuple[np.ndarray, bytes]:
        """Every 20 ms frame, the targets that changed (``frames.per_frame``): in
        quarter-us, not rounded to degrees."""
        return per_frame(self, plan, self.targets)

    def core(self) -> MaestroCore:
        """The virtual Maestro, its servos at rest."""
        return MaestroCore(self.board.id, self.servos, self.widths, self.model,
                           self.device if self.device is not None else c.DEFAULT_DEVICE)

    def set_values(self, values: Mapping[int, int]) -> bytes:
        """Targets for the servos' values."""
        by_id = {s.id: j for j, s in enumerate(self.servos)}
        return self.targets({self.servos[by_id[sid]].pin: int(self.quarters(by_id[sid],
                                                                            [v])[0])
                             for sid, v in values.items() if sid in by_id})

    def relax(self) -> bytes:
        """Target 0 on each of its channels: no pulses."""
        return self.targets({s.pin: 0 for s in self.servos})

    def ask_pose(self) -> bytes:
        """Get Position for each channel."""
        return b"".join(c.command(c.GET_POSITION, [s.pin], self.device)
                        for s in self.servos)

    def pose_reader(self) -> PoseReader:
        """Reads the positions back as values."""
        return _Positions(self)

    def probe(self) -> bytes:
        """Get Errors: any Maestro answers it at once."""
        return c.command(c.GET_ERRORS, [], self.device)

    def ready(self, answer: bytes) -> bool:
        """Its two bytes came, and they are a Maestro's error register (nine bits: a
        port that echoes the question, ``0xA1`` or ``0xAA`` and a device number, sets
        others)."""
        return len(answer) >= 2 and not (answer[0] | answer[1] << 8) & ~c.ERROR_BITS

    def answered_late(self) -> str:
        """It sends no WAIT: no Get Errors answer, Get Position answered."""
        return "did not answer Get Errors, but answered Get Position"

    def greeting(self, answer: bytes) -> str | None:
        """Its errors, in words, when it reports any."""
        if len(answer) < 2 or not (errors := answer[0] | answer[1] << 8):
            return None
        return f"the Maestro on board {self.board.id} reported {c.describe(errors)} " \
               f"(cleared now)"

    def setup(self, answer: bytes = b"", pose: Mapping[int, int] | None = None) -> bytes:
        """Speed and acceleration 0 on its channels: the plan is the motion."""
        return b"".join(c.command(code, [s.pin, 0, 0], self.device) for s in self.servos
                        for code in (c.SET_SPEED, c.SET_ACCELERATION))
