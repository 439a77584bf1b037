"""What a ``[[board]]`` of a kind says in a profile, as data its room declares
(``TABLE`` in ``boards/<kind>/table.py``): the keys the kind reads, its default baud,
what its servos' places are (pins or channels) and which it has. ``profiles`` reads a
board's table through it; nothing here reads TOML."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

Options = tuple[tuple[str, int], ...]  #: what a kind knows of a board: option -> value


@dataclass(frozen=True)
class Choice:
    """A key whose value is one of ``choices``, kept as its place among them."""

    key: str
    choices: tuple[str, ...]
    default: str


@dataclass(frozen=True)
class Whole:
    """A key whose value is a whole number in ``low..high`` (``named``: that range in
    other words), kept under ``option`` (the key's name when empty); no ``default``: the
    key is optional and, when left out, not kept."""

    key: str
    low: int
    high: int
    default: int | None = None
    named: str | None = None
    option: str = ""


@dataclass(frozen=True)
class Place:
    """What is wrong with a servo's place: the message, as it goes on after ``servo
    'NAME'``, and a hint."""

    message: str
    hint: str | None = None


#: what is wrong with a servo at ``pin`` (None: none given) of the board whose id and
#: options are given, or None
PlaceRule = Callable[[int, Options, "int | None"], "Place | None"]


@dataclass(frozen=True)
class KindTable:
    """One kind's part of a profile."""

    kind: str  #: its ``kind = "..."``
    baud: int  #: the baud its link is timed at when the board gives none
    keys: tuple[Choice | Whole, ...]  #: what its ``[[board]]`` may say of it
    noun: str  #: what a servo's place is called on it: "pin" or "channel"
    place: PlaceRule

    @property
    def names(self) -> tuple[str, ...]:
        """The keys its ``[[board]]`` may hold besides every board's."""
        return tuple(key.key for key in self.keys)


def channels(kind: str, count: Callable[[Options], int]
             ) -> PlaceRule:
    """The place rule of a kind whose servos take channels ``0..count(options) - 1``,
    each given as ``pin``."""
    def place(board: int, options: Options, pin: int | None) -> Place | None:
        """What is wrong with a servo on channel ``pin``, or None."""
        most = count(options)
        if pin is not None and 0 <= pin < most:
            return None
        return Place(f": board {board} ({kind}) has channels 0..{most - 1}: give the servo's "
                     f"channel as 'pin', got {pin!r}")
    return place
