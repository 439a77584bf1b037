"""A joint trajectory as steps planned through the profile's limits (pure, no ROS).

A trajectory (ROS's ``JointTrajectory``, or any other) names some of the model's
joints and gives points: a position in radians for each of them, and the time from
the start at which to be there. Each point becomes one move of the named servos,
``over`` the time since the point before (the first: since the request came), so the
hand passes through every point at rest, each move jerk-limited by the planner and
stretched, with a warning, when the limits need more time. Nothing is sent raw.
Velocities and accelerations of the points are not used. Anything the hand cannot do
(a joint it does not have, a position outside its range, times that do not increase,
NaN) is a GestError that says which point and which joint.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import NoReturn

from ..compiling.actions import Action, Steps
from ..errors import Diagnostic, GestError, did_you_mean
from ..hardware import Profile
from ..model import joints

#: one point of a trajectory: the joints' positions (radians, in the order of the
#: names), and its time from the start (s)
Point = tuple[Sequence[float], float]


def steps(profile: Profile, names: Sequence[str], points: Sequence[Point],
          name: str = "trajectory") -> Steps:
    """The steps that move the joints ``names`` through ``points``."""
    index = _servos(profile, names)
    if not points:
        _fail("a trajectory with no points", "give at least one point")
    actions = []
    before = 0.0
    for k, (positions, t) in enumerate(points, 1):
        t = float(t)
        if not math.isfinite(t) or t < 0:
            _fail(f"point {k}: time_from_start {t:g} s is not a time from the start",
                  "times are seconds from the start of the trajectory, 0 or more")
        if k > 1 and t <= before:
            _fail(f"point {k}: time_from_start {t:g} s is not after point {k - 1}'s "
                  f"({before:g} s)", "the points' times must increase")
        if len(positions) != len(names):
            _fail(f"point {k} has {len(positions)} positions for {len(names)} joints",
                  "give one position per joint name")
        targets = tuple((i, _value(profile, i, names[j], float(x), k))
                        for j, (i, x) in enumerate(zip(index, positions, strict=True)))
        actions.append(Action(targets, over=(t - before) or None, where=f"{name} point {k}"))
        before = t
    return Steps(tuple(actions), f"{name} ({len(points)} point{'s' * (len(points) > 1)}, "
                 f"{before:g} s)")


def _servos(profile: Profile, names: Sequence[str]) -> list[int]:
    """The index of each named joint's servo in the profile."""
    if not names:
        _fail("a trajectory with no joint names", "name the joints it moves")
    known = joints.names(profile)
    index = []
    for name in names:
        if name not in known:
            hint = did_you_mean(name, known) or f"its joints: {', '.join(known)}"
            _fail(f"profile '{profile.name}' has no joint '{name}'", hint)
        if name in names[:len(index)]:
            _fail(f"joint '{name}' is named twice", "name each joint once")
        index.append(known.index(name))
    return index


def _value(profile: Profile, i: int, joint: str, radians: float, k: int) -> int:
    """The servo value for ``radians``, rounded; out of the servo's range is an error."""
    servo = profile.servos[i]
    if not math.isfinite(radians):
        _fail(f"point {k}: joint '{joint}' at {radians} rad", "positions are finite numbers")
    value = joints.value(servo, radians)
    whole = math.floor(value + 0.5)
    if not servo.lo <= whole <= servo.hi:
        low, high = joints.limits(servo)
        _fail(f"point {k}: joint '{joint}' at {radians:.3f} rad is outside its range "
              f"{low:.3f}..{high:.3f} rad", f"{servo.name} {servo.lo}..{servo.hi} in "
              f"command degrees; position 0 is its rest, {servo.name} {servo.rest}")
    return whole


def _fail(message: str, hint: str) -> NoReturn:
    raise GestError(Diagnostic("error", message, hint=hint))
