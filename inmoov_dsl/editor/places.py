"""What each place of a file solved to, for an editor (pure, over an Analysis): a
hover and an inlay hint on ``right hand to cup`` with its servos' values, and the code
action that writes the item as those values."""

from __future__ import annotations

from dataclasses import dataclass

from .analysis import Analysis
from .lines import place


@dataclass(frozen=True)
class Solved:
    """A place's item (``line``, ``column`` to ``end``: 0-based, protocol), as written
    (``label``), and the values it solved to, each distinct set once (a place in a
    gesture called from two poses solves twice)."""

    line: int
    column: int
    end: int
    label: str
    values: tuple[str, ...]  #: ``r_omoplate 147, r_shoulder 66, ...``, one per solve

    @property
    def text(self) -> str:
        """The values, or how many ways the item solves."""
        if len(self.values) == 1:
            return self.values[0]
        return f"{len(self.values)} ways, from the poses before it: " + "; ".join(self.values)


def solved(found: Analysis) -> list[Solved]:
    """Every place of this file's text that its plans solved, in the file's order."""
    names = found.profile.names if found.profile is not None else ()
    seen: dict[tuple[int, int, int], tuple[str, dict[str, None]]] = {}
    for plan in found.plans.values():
        for step in plan.steps:
            for aim, values in step.solved:
                pos = aim.pos
                if pos is None or pos.file != found.path or not names:
                    continue
                line, column = place(found.text, pos.line, pos.column)
                written = ", ".join(f"{names[i]} {v}" for i, v in values)
                key = (line, column, column + pos.width)
                seen.setdefault(key, (aim.label, {}))[1][written] = None
    return [Solved(*key, label, tuple(values)) for key, (label, values) in sorted(seen.items())]


def at(found: Analysis, line: int, column: int) -> Solved | None:
    """The place's item under ``line``, ``column`` (0-based), if one was solved."""
    return next((s for s in solved(found) if s.line == line and s.column <= column <= s.end),
                None)
