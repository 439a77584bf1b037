"""What a gesture does once resolved (``resolve``): its Actions, and where an expansion
is (pure data)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from ..errors import Pos, SourceMap


@dataclass(frozen=True)
class Action:
    """What one step of a gesture does once resolved: a move (targets), or a hold
    (``hold`` > 0). (``syntax.Step`` is what was written, ``plan.PlannedStep`` what was
    planned, ``compiled.StepSummary`` what a compiled file reports.)"""

    targets: tuple[tuple[int, int], ...]  #: (servo index, value), in stagger order
    over: float | None = None  #: s; all servos arrive together at this time
    stagger: float = 0.0  #: s between the starts of consecutive targets
    hold: float = 0.0  #: s; a wait step
    pos: Pos | None = None
    over_pos: Pos | None = None
    where: str = ""  #: the call chain, e.g. "demo > peace"
    through: bool = False  #: its servos cross the keyframe moving when the next step goes on
    #: ``a & b``: steps that run at the same time on their own servos, each from the
    #: step's start (``targets`` is then empty); the step ends when the longest ends
    branches: tuple[tuple[Action, ...], ...] = ()
    #: ``say``: a ``speech.Speech``, the sound and the mouth moving with it (not imported
    #: here: a step's data stays below the planning that reads it)
    speech: Any = None
    #: the call of the gesture resolved that this step plays in (where it is written
    #: there; None: one of its own steps), and whether it is the first step of one play
    #: of that call (a call in a repeat plays again)
    call: Pos | None = None
    opens: bool = False
    #: ``right hand to cup``, ``look at cup``: ``reaching.Aim``s the solve turns into
    #: targets (then empty), and each one solved with its values ((servo, value), ...)
    aims: tuple[Any, ...] = ()
    solved: tuple[tuple[Any, tuple[tuple[int, int], ...]], ...] = ()

    def servos(self) -> set[int]:
        """The servos this step moves (in its branches too)."""
        found = {i for i, _ in self.targets} | ({self.speech.servo} if self.speech else set())
        found.update(i for aim in self.aims for i in aim.servos)
        for branch in self.branches:
            for action in branch:
                found |= action.servos()
        return found


@dataclass(frozen=True)
class Frame:
    """Where the expansion is: the gestures called (outermost first), the call chain as
    shown, and how deep calls and repeats nest here."""

    chain: tuple[str, ...]
    where: str
    depth: int = 0


@dataclass(frozen=True)
class Steps:
    """Steps already resolved for the profile (a trajectory's points), and their name."""

    actions: tuple[Action, ...]
    name: str = "steps"
    sources: SourceMap | None = None  #: the text the steps' diagnostics point into
