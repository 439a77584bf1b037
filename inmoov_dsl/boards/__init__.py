"""The kinds of board a profile's ``[[board]]`` may name (``kind``), one folder each:
``rig`` (our firmware and the original), ``maestro`` (Pololu Maestro), ``pca9685``
(a PCA9685 on an I2C bus). ``controller`` gives a board's ``Controller``
(``base.py``), which is all the rest of the package knows of a kind; ``pulses.py`` is
the one mapping from a value to a pulse width that every kind keeps."""

from __future__ import annotations

from ..profiles.data import Board, Profile
from .base import Controller


def _kinds() -> dict[str, type[Controller]]:
    from .maestro import MaestroController
    from .pca9685 import PcaController
    from .rig import RigController

    return {k.kind: k for k in (RigController, MaestroController, PcaController)}


def controller(profile: Profile, board: Board) -> Controller:
    """``board`` of ``profile`` as its kind drives it."""
    return _kinds()[board.kind](profile, board)


def by_id(profile: Profile) -> dict[int, Controller]:
    """Each board of ``profile`` by its ID, as its kind drives it."""
    return {b.id: controller(profile, b) for b in profile.boards}
