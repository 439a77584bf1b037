"""The robot as geometry: joint positions from servo values (``joints``), the URDF
(``urdf``, ``urdf_parts``), every link placed (``kinematics``), joint states over time
(``export``), the self-collision check (``collide``, on ``shapes`` and ``allowed``;
what the tools do with a contact, and how it is worded: ``guard``), and places as servo
values (``reach``: a hand's by inverse kinematics, ``ik``; the gaze's, ``gaze``). What
people look at is in ``views``.

Importing this package gives the compiler its solver of places (``compiling.reaching``),
which imports ``reach`` only when a place is solved: every front end imports it."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING

from ..compiling import reaching

if TYPE_CHECKING:
    from ..compiling.plan import Plan
    from ..compiling.reaching import Aim
    from ..errors import Diagnostic, SourceMap
    from ..hardware import Profile


def collisions(plan: Plan, sources: SourceMap, strict: bool,
               step: Callable[[], None] | None = None) -> tuple[Diagnostic, ...]:
    """The self-collision check of a plan as the compiler runs it (``guard.check_plan``,
    for ``compiler.plan_checks``; ``step`` as its), imported only when a plan is
    checked: a command that compiles nothing pays nothing for it."""
    from .guard import check_plan

    return check_plan(plan, sources, strict, step)


def solve_place(profile: Profile, aim: Aim, pose: Sequence[int], sources: SourceMap
                ) -> dict[int, int]:
    """``reach.solve``, for ``compiling.reaching``: imported when a place is solved."""
    from .reach import solve

    return solve(profile, aim, pose, sources)


def place_note() -> str | None:
    """``reach.note``, for ``compiling.reaching``."""
    from .reach import note

    return note()


reaching.provide(solve_place, place_note)
