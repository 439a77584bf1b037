"""The conformance vectors, read once for the Python tests (the firmware's host tests
read the same files): board.json, bytes into a servo board and what it does."""

import json
from pathlib import Path

from inmoov_dsl.boards.rig.core import BoardCore, BoardServo

BOARD = json.loads((Path(__file__).parent / "board.json").read_text())


def board_servos() -> list[BoardServo]:
    """The vectors' board's servos."""
    return [BoardServo(s["id"], tuple(s["calibration"]), s["reversed"], s["default"])
            for s in BOARD["servos"]]


def vector_board() -> BoardCore:
    """A fresh core of the vectors' board."""
    return BoardCore(BOARD["board"], board_servos())
