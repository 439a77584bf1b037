"""Teaching a gesture by posing the hand (``gestplay teach``): the session's state, pure.

Keys come in, and each one changes the pose, the servo chosen, the keyframes or the
time to the next keyframe; the caller sends the servo values to the board and draws
the line this module describes. The keyframes become a gesture in the canonical layout.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from ..hardware import Profile
from ..protocol import clamp
from . import keymap
from .record import Keyframe, to_gest

MIN_OVER, MAX_OVER = 0.1, 10.0  #: s
HELP = keymap.help_text(
    ("move", "next", "pick", "keep", "undo", "time", "play", "save", "quit"),
    {"keep": "keep the pose as a keyframe", "undo": "take back the last keyframe",
     "time": "time to the next keyframe +-0.1 s", "play": "play the keyframes back",
     "save": "save them to the file"})


@dataclass
class Teach:
    """Where the hand is, which servo the keys move, and the keyframes kept so far."""

    profile: Profile
    pose: list[int]
    selected: int = 0
    over: float = 0.5  #: s from the previous keyframe to the next one
    keys: list[tuple[float, tuple[int, ...]]] = field(default_factory=list)  #: (over, pose)
    saved: bool = True
    asking: bool = False  #: q was pressed with keyframes not saved: q again quits

    def press(self, key: str) -> str | None:
        """Apply a key; returns what the caller must do: 'send' (the chosen servo's new
        value), 'play', 'save', 'quit', or None (only redraw). Quitting with keyframes
        not saved asks first: q again quits, any other key carries on."""
        act, amount = keymap.action(key) or ("", 0)
        asked, self.asking = self.asking, False
        if act == "move":
            return self._move(int(amount))
        count = len(self.profile.servos)
        if act == "next":
            self.selected = (self.selected + int(amount)) % count
        elif act == "pick" and amount <= count:
            self.selected = int(amount) - 1
        elif act == "keep":
            self.keys.append((0.0 if not self.keys else self.over, tuple(self.pose)))
            self.saved = False
        elif act == "undo" and self.keys:
            self.keys.pop()
            self.saved = False
        elif act == "time":
            self.over = max(MIN_OVER, min(MAX_OVER, round(self.over + amount, 3)))
        elif act == "play" and len(self.keys) > 1:
            return "play"
        elif act == "save" and self.keys:
            return "save"
        elif act == "quit":
            if self.saved or not self.keys or asked:
                return "quit"
            self.asking = True
        return None

    def _move(self, step: int) -> str | None:
        """The chosen servo ``step`` further, within its range: 'send', or None when it
        is at its end already."""
        servo = self.profile.servos[self.selected]
        value = clamp(self.pose[self.selected] + step)
        value = max(servo.lo, min(servo.hi, value))
        if value == self.pose[self.selected]:
            return None
        self.pose[self.selected] = value
        return "send"

    def line(self) -> str:
        """The state in one line: every servo's value (the chosen one in brackets)."""
        if self.asking:
            return (f"{_keyframes(len(self.keys))} not saved: q again quits without them, "
                    f"s saves them, any other key goes on")
        values = "  ".join(f"[{s.name} {v}]" if i == self.selected else f"{s.name} {v}"
                           for i, (s, v) in enumerate(zip(self.profile.servos, self.pose,
                                                          strict=True)))
        return f"{values}  | {_keyframes(len(self.keys))}, next over {self.over:.1f} s"

    def gesture(self, name: str) -> str:
        """The keyframes as a gesture: the first pose, then each change ``over`` its time
        (written as a recording is, by record.to_gest)."""
        if not self.keys:
            raise ValueError("no keyframe")
        keyframes, at = [], 0.0
        for over, pose in self.keys:
            at += over
            keyframes.append(Keyframe(at, dict(enumerate(pose))))
        about = [f"{name}: taught with gestplay teach, {len(self.keys)} keyframes"]
        return to_gest(name, keyframes, self.profile, about)


def _keyframes(n: int) -> str:
    return f"{n} keyframe{'' if n == 1 else 's'}"
