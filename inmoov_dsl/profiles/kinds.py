"""A ``[[board]]``'s kind, read through the kind's table (``boards.TABLES``: the keys it
reads, its default baud and the places its servos take, each declared in the kind's own
folder), and the check that every servo has a place its board has. Nothing here names a
kind."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from ..boards import KINDS, TABLES
from ..boards.table import Choice, KindTable, Options
from ..errors import did_you_mean
from ..hardware import Board, Servo
from . import fields as check
from .fields import Check, Problem, shown


def kind(key: str, value: Any) -> str:
    """One of ``boards.KINDS``."""
    return KINDS[choice(KINDS)(key, value)]


def choice(choices: tuple[str, ...]) -> Check[int]:
    """One of ``choices``, as its place among them."""
    def check_choice(key: str, value: Any) -> int:
        """``value``'s place among the choices, if it is one."""
        if not isinstance(value, str) or value not in choices:
            raise Problem(f"'{key}' must be one of {', '.join(choices)}, got {shown(value)}",
                          did_you_mean(value, choices) if isinstance(value, str) else None)
        return choices.index(value)
    return check_choice


def keys(common: tuple[str, ...], named: Any) -> tuple[tuple[str, ...], dict[str, str]]:
    """The keys a ``[[board]]`` of the kind ``named`` takes: ``common`` (every board's)
    and its kind's (every kind's when ``named`` is none: that error alone); and a hint
    for each key only other kinds take."""
    table = TABLES.get(named) if isinstance(named, str) else None
    taken = (*common, *dict.fromkeys(k for t in ([table] if table else TABLES.values())
                                     for k in t.names))
    others: dict[str, list[str]] = {}
    for other in TABLES.values():
        for key in other.names:
            if key not in taken:
                others.setdefault(key, []).append(other.kind)
    return taken, {key: f"only a board of kind {' or '.join(of)} takes '{key}'; this one's "
                   f"kind is {named}" for key, of in others.items()}


def options(fields, table: KindTable) -> Options:
    """The keys of ``table``'s kind the board table ``fields`` holds, as options."""
    found = []
    for key in table.keys:
        if isinstance(key, Choice):
            found.append((key.key, fields.get(key.key, choice(key.choices), key.default,
                                              fallback=key.choices.index(key.default))))
            continue
        whole = check.whole(key.low, key.high, key.named)
        value = fields.get(key.key, whole if key.default is not None
                           else check.optional(whole), key.default)
        if value is not None:
            found.append((key.option or key.key, value))
    return tuple(found)


def pulse(key: str, value: Any) -> tuple[int, int]:
    """[width at 0, width at 180] in us, each 400..2600, not equal."""
    pair = check.pair(value)
    if pair is None or pair[0] == pair[1] or not all(400 <= p <= 2600 for p in pair):
        raise Problem(f"'{key}' must be [width at 0, width at 180] in microseconds, each "
                      f"400..2600 and not equal, got {shown(value)}",
                      "leave it out to use the calibration's widths (the firmware's)")
    return pair


def check_places(report, boards: Sequence[Board], servos: Sequence[Servo]) -> None:
    """Each servo on a place (a pin, a channel) its board has, one a place, as its
    board's kind says (a board whose kind is unknown is that error alone)."""
    for board in boards:
        table = TABLES.get(board.kind)
        if table is None:
            continue
        taken: dict[int, str] = {}
        for s in (s for s in servos if s.board == board.id):
            at = ("servo", s.name, "pin") if s.pin is not None else ("servo", s.name)
            problem = table.place(board.id, board.options, s.pin)
            if problem is not None:
                report.error(at, f"servo '{s.name}'{problem.message}", hint=problem.hint)
            elif s.pin is not None and s.pin in taken:
                report.error(at, f"servo '{s.name}': {table.noun} {s.pin} of board {board.id} "
                             f"is servo '{taken[s.pin]}''s already")
            elif s.pin is not None:
                taken[s.pin] = s.name
