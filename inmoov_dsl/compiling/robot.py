"""The robot a program is written for: its files' ``robot`` lines, the profile a
command uses when none is given, and the check that a profile given plays them.

A file's robot line names a profile (``robot inmoov``) or a profile file beside it
(``robot "my_hand.toml"``). Without ``--profile`` (or its like), the root file's robot
is the profile, else the robot its imports agree on, else ``rhand``. A profile given
explicitly plays a file's gestures when it has every servo and group of the file's
robot (``rhand-maestro`` or ``inmoov`` play a ``robot rhand`` file; ``rhand`` does not
play a ``robot inmoov`` one): the resolver asks ``check`` for each gesture it expands.
"""

from __future__ import annotations

import os

from ..errors import GestError, Pos
from ..hardware import Profile
from ..language import syntax as ast
from ..language.program import Program
from ..profiles.profile import load_profile

DEFAULT = "rhand"  #: the profile of a program that names no robot
SHOWN = 6  #: missing names a message lists before "and N more"


def robot(program: Program) -> ast.Robot | None:
    """The robot line that chooses the program's profile: the root file's, else the one
    robot its imports name (several different ones choose none)."""
    own = program.robots.get(program.root)
    if own is not None:
        return own
    named = {(r.name, r.is_file): r for r in program.robots.values()}
    return next(iter(named.values())) if len(named) == 1 else None


def robot_profile(line: ast.Robot, program: Program) -> Profile:
    """The profile a robot line names; one that cannot be loaded is an error at it."""
    where = line.name
    if line.is_file and not os.path.isabs(where):
        where = os.path.join(os.path.dirname(line.pos.file), where)
    try:
        return load_profile(where)
    except GestError as exc:
        first = exc.first
        raise GestError(program.sources.error(first.message, line.pos, first.hint)) from None


def profile_for(program: Program, profile: str | Profile | None = None,
                default: str = DEFAULT) -> Profile:
    """The profile to compile ``program`` for: ``profile`` when given (a name, a path or
    a Profile), else the program's robot, else ``default`` (an editor's setting)."""
    if isinstance(profile, Profile):
        return profile
    if profile is not None:
        return load_profile(profile)
    line = robot(program)
    return robot_profile(line, program) if line is not None else load_profile(default)


def check(program: Program, profile: Profile, gesture: str, at: Pos | None = None) -> None:
    """A GestError unless ``profile`` plays ``gesture``: has every servo and group of the
    robot its file's robot line names; at ``at`` (a call) or at the robot line."""
    file = program.gestures[gesture].name.pos.file
    line = program.robots.get(file)
    if line is None:
        return
    wanted = robot_profile(line, program)
    if wanted is profile or wanted.sha256 == profile.sha256:
        return
    have = {*profile.names, *profile.groups}
    missing = [n for n in (*wanted.names, *wanted.groups) if n not in have]
    if not missing:
        return
    listed = ", ".join(missing[:SHOWN])
    if len(missing) > SHOWN:
        listed += f" and {len(missing) - SHOWN} more"
    what = "this file is" if at is None else \
        f"this gesture is from {os.path.basename(file)}, which is"
    raise GestError(program.sources.error(
        f"{what} for robot '{wanted.name}', and profile '{profile.name}' has no {listed}",
        at or line.pos,
        f"play it on '{wanted.name}', or on a profile with all of its servos and groups"))
