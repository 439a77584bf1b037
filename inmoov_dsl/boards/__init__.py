"""The kinds of board a profile's ``[[board]]`` may name (``kind``), one folder each:
``rig`` (our firmware and the original), ``maestro`` (Pololu Maestro), ``pca9685`` (a
PCA9685 on an I2C bus), ``mrlcomm`` (MyRobotLab's firmware). A kind's folder holds all
of it: what its ``[[board]]`` says in a profile (``table.py``: ``TABLES`` here), how a
plan becomes its commands, what it answers, its virtual twin. ``controller`` gives a
board's ``Controller`` (``base.py``), which is all the rest of the package knows of a
kind; ``pulses.py`` is the one mapping from a value to a pulse width every kind keeps;
``arduino.py`` the Arduinos ours and MrlComm run on."""

from __future__ import annotations

from ..hardware import Board, Profile
from .base import Controller
from .maestro.table import TABLE as MAESTRO
from .mrlcomm.table import TABLE as MRLCOMM
from .pca9685.table import TABLE as PCA9685
from .rig.table import TABLE as RIG
from .table import KindTable

#: every kind, by its name: a new kind is its folder and its line here
TABLES: dict[str, KindTable] = {t.kind: t for t in (RIG, MAESTRO, PCA9685, MRLCOMM)}
KINDS = tuple(TABLES)
DEFAULT_KIND = RIG.kind  #: a board that names no kind runs our firmware (or the original)


def _kinds() -> dict[str, type[Controller]]:
    from .maestro import MaestroController
    from .mrlcomm import MrlCommController
    from .pca9685 import PcaController
    from .rig import RigController

    return {k.kind: k for k in (RigController, MaestroController, PcaController,
                                MrlCommController)}


__all__ = ["DEFAULT_KIND", "KINDS", "TABLES", "Controller", "KindTable", "claimed", "controller",
           "fault"]


def controller(profile: Profile, board: Board) -> Controller:
    """``board`` of ``profile`` as its kind drives it."""
    return _kinds()[board.kind](profile, board)


def claimed(spec: str) -> tuple[str, str] | None:
    """The kind whose own port ``spec`` is (``Controller.claims``), and what it is; None:
    a port any kind may be on (a serial port, a URL)."""
    for kind, cls in _kinds().items():
        said = cls.claims(spec)
        if said is not None:
            return kind, said
    return None


def fault(kind: str, data: bytes) -> str | None:
    """What in ``data`` breaks the framing of ``kind`` (a Maestro's or a PCA9685's), or
    None (a rig's layout is ``protocol.frame_fault``)."""
    from .maestro import commands
    from .mrlcomm import messages
    from .pca9685 import transactions

    return {"maestro": commands.fault, "pca9685": transactions.fault,
            "mrlcomm": messages.fault}[kind](data)
