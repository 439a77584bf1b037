"""The robot as geometry: joint positions from servo values (``joints``), the URDF
(``urdf``, ``urdf_parts``), every link placed (``kinematics``), joint states over time
(``export``), and the self-collision check (``collide``, on ``shapes`` and ``allowed``;
what the tools do with a contact, and how it is worded: ``guard``). What people look at
is in ``views``."""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from ..compiling.plan import Plan
    from ..errors import Diagnostic, SourceMap


def collisions(plan: Plan, sources: SourceMap, strict: bool,
               step: Callable[[], None] | None = None) -> tuple[Diagnostic, ...]:
    """The self-collision check of a plan as the compiler runs it (``guard.check_plan``,
    for ``compiler.plan_checks``; ``step`` as its), imported only when a plan is
    checked: a command that compiles nothing pays nothing for it."""
    from .guard import check_plan

    return check_plan(plan, sources, strict, step)
