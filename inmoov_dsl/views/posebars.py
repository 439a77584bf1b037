"""A pose as text: a line per servo with its value and a bar, as ``gestsim`` draws the
virtual board and ``gestplay`` says what the virtual hand holds after a gesture (pure)."""

from __future__ import annotations

from collections.abc import Iterable

from ..protocol import MAX_VALUE

BAR = 30  #: characters of a full bar (a value of MAX_VALUE)


def bar_lines(pose: Iterable[tuple[str, int]]) -> list[str]:
    """``  name  value  ####``: one line per (servo name, value)."""
    return [f"  {name:<10} {value:>3}  {'#' * (value * BAR // MAX_VALUE)}".rstrip()
            for name, value in pose]
