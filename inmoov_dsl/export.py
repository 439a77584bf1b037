"""Joint states of a compiled gesture for a ROS model (``gestc export``): pure.

The original project drove a URDF model of the hand in rviz from the serial stream; its
joints are named ``right_arm_to_wrist``, ``right_palm_to_thumb``, ... ``_to_pinky``.
Here each row is one moment (every servo frame by default) and each column a joint:
the value the board holds then, decoded from the stream, in radians (a command value
of 0..180 degrees is 0..pi: 0 straight, pi curled).
"""

from __future__ import annotations

import math

import numpy as np

from .compiled import Compiled
from .metrics import held_at, sent_values
from .plan import Plan
from .protocol import SERVO_FRAME

#: the original model's joint of each hand servo (the right hand's)
JOINTS = {
    "wrist": "right_arm_to_wrist",
    "thumb": "right_palm_to_thumb",
    "index": "right_palm_to_index",
    "middle": "right_palm_to_medius",
    "ring": "right_palm_to_ring",
    "pinky": "right_palm_to_pinky",
}


def joint_name(servo: str) -> str:
    """The model's name of a servo: the right hand's joints (``thumb`` or ``r_thumb``),
    any other servo by its own name."""
    return JOINTS.get(servo, JOINTS.get(servo.removeprefix("r_"), servo))


def joint_states(plan: Plan, compiled: Compiled, period: float = SERVO_FRAME
                 ) -> tuple[list[str], np.ndarray]:
    """(column names, rows): ``time`` then one column per servo, a row every ``period``
    seconds from 0 to the end of the gesture, positions in radians."""
    steps = int(math.ceil(compiled.duration / period - 1e-9))
    times = np.arange(steps + 1) * period
    held = held_at(plan, sent_values(plan, compiled), times)
    names = ["time", *(joint_name(s.name) for s in plan.profile.servos)]
    return names, np.column_stack([times, np.radians(held)])


def to_csv(names: list[str], rows: np.ndarray) -> str:
    """The rows of ``joint_states`` as CSV: a header, times to 1 ms, radians to 1e-6."""
    lines = [",".join(names)]
    lines += [",".join([f"{row[0]:.3f}", *(f"{x:.6f}" for x in row[1:])]) for row in rows]
    return "\n".join(lines) + "\n"
