"""The keys of the bench tools, ``gestplay teach`` and ``gestplay calibrate``: one map,
so that a key does the same thing in both, and the help each tool shows, made from it.

Both tools draw the servos side by side on one line and a value that goes up and down:
left/right choose a servo along that line (as a mixer's channels), up/down move its
value by 1, page up/down (or shift+up/down) by 10. Enter keeps the pose (a keyframe, or
an end), u takes back the last one, s saves, q or Esc leaves. Key names are those
``cli.keys.key_reader`` gives. Pure.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass


@dataclass(frozen=True)
class Binding:
    """Keys that do one thing: ``action``, by the amount each key gives (a step, a
    direction, a servo's number), shown in the help as ``shown  does``."""

    action: str
    keys: tuple[tuple[str, float], ...]
    shown: str
    does: str


BINDINGS = (
    Binding("move", (("up", 1), ("down", -1)), "up/down", "move +1/-1"),
    Binding("move", (("pageup", 10), ("pagedown", -10), ("shift-up", 10),
                     ("shift-down", -10)), "page up/down", "move +10/-10"),
    Binding("next", (("left", -1), ("right", 1)), "left/right", "choose a servo"),
    Binding("pick", tuple((str(n), n) for n in range(1, 10)), "1..9", "choose servo 1..9"),
    Binding("keep", (("enter", 0), (" ", 0)), "Enter or space", "keep this pose"),
    Binding("undo", (("u", 0),), "u", "take back the last one"),
    Binding("time", (("+", 0.1), ("=", 0.1), ("-", -0.1), ("_", -0.1)), "+/-",
            "time to the next one +-0.1 s"),
    Binding("play", (("p", 0),), "p", "play back"),
    Binding("save", (("s", 0),), "s", "save"),
    Binding("quit", (("q", 0), ("esc", 0)), "q or Esc", "quit"),
)
ACTIONS = {key: (b.action, amount) for b in BINDINGS for key, amount in b.keys}


def action(key: str) -> tuple[str, float] | None:
    """What ``key`` does in every bench tool: (action, amount), or None."""
    return ACTIONS.get(key)


def help_text(actions: Iterable[str], words: Mapping[str, str] | None = None) -> str:
    """The help for a tool that does ``actions``: its bindings in the map's order, two
    to a line in columns; ``words`` says what an action means in that tool (``keep``:
    "keep the pose as a keyframe")."""
    wanted, words = set(actions), words or {}
    entries = [f"{b.shown}  {words.get(b.action, b.does)}" for b in BINDINGS
               if b.action in wanted]
    width = max((len(e) for e in entries[::2]), default=0) + 4
    pairs = [entries[i:i + 2] for i in range(0, len(entries), 2)]
    return "\n".join(f"{p[0]:<{width}}{p[1]}" if len(p) == 2 else p[0] for p in pairs)
