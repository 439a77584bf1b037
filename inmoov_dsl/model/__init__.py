"""The robot as a model: joint positions from servo values (``joints``), the URDF
(``urdf``, ``urdf_parts``), the 3-D view in a browser (``webview``, on ``scene``), the
live preview page (``livepage``, on ``timeline``, ``livedraw``, ``liveclock``,
``livepanel``, ``lookout``), the drawn hand (``preview``), plots (``plot``), joint-state
export (``export``), a pose as bars (``posebars``), and the self-collision check
(``collide``, on ``kinematics``, ``shapes`` and ``allowed``; what the tools do with a
contact: ``guard``)."""

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
