"""Joint states of a compiled gesture for a ROS model (``gestc export``): pure.

The original project drove a URDF model of the hand in rviz from the serial stream.
Here each row is one moment (every servo frame by default) and each column a joint of
our model (``gestc urdf``), named as in the original (``right_arm_to_wrist``,
``right_palm_to_thumb``, ...): the value the board holds then, decoded from the stream,
as the joint's position in radians (joints.py: 0 at rest, the servo's real angle).
"""

from __future__ import annotations

import math

import numpy as np

from ..compiling.compiled import Compiled
from ..compiling.metrics import held_at, sent_values
from ..compiling.plan import Plan
from ..protocol import SERVO_FRAME
from . import joints


def joint_states(plan: Plan, compiled: Compiled, period: float = SERVO_FRAME
                 ) -> tuple[list[str], np.ndarray]:
    """(column names, rows): ``time`` then one column per servo, a row every ``period``
    seconds from 0 to the end of the gesture, positions in radians."""
    steps = int(math.ceil(compiled.duration / period - 1e-9))
    times = np.arange(steps + 1) * period
    held = held_at(plan.start, sent_values(plan, compiled), times)
    columns = [joints.position(s, held[:, i]) for i, s in enumerate(plan.profile.servos)]
    return ["time", *joints.names(plan.profile)], np.column_stack([times, *columns])


def to_csv(names: list[str], rows: np.ndarray) -> str:
    """The rows of ``joint_states`` as CSV: a header, times to 1 ms, radians to 1e-6."""
    lines = [",".join(names)]
    lines += [",".join([f"{row[0]:.3f}", *(f"{x:.6f}" for x in row[1:])]) for row in rows]
    return "\n".join(lines) + "\n"
