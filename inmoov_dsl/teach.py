"""Teaching a gesture by posing the hand (``gestplay teach``): the session's state, pure.

Keys come in, and each one changes the pose, the servo chosen, the keyframes or the
time to the next keyframe; the caller sends the servo values to the board and draws
the line this module describes. The keyframes become a gesture in the canonical layout.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from .profile import Profile
from .protocol import MAX_VALUE
from .record import Keyframe, to_gest

STEPS = {"up": 1, "down": -1, "pageup": 10, "pagedown": -10}
MIN_OVER, MAX_OVER, OVER_STEP = 0.1, 10.0, 0.1  #: s
HELP = """\
left/right or 1..9 choose a servo   up/down +-1   page up/down +-10
Enter or space  keep this pose as a keyframe      u  undo the last one
+/-  time to the next keyframe +-0.1 s            p  play the keyframes back
s  save                                           q  quit"""


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
        count = len(self.profile.servos)
        asked, self.asking = self.asking, False
        if key in STEPS:
            value = max(0, min(MAX_VALUE, self.pose[self.selected] + STEPS[key]))
            servo = self.profile.servos[self.selected]
            value = max(servo.lo, min(servo.hi, value))
            if value == self.pose[self.selected]:
                return None
            self.pose[self.selected] = value
            return "send"
        if key in ("left", "right"):
            self.selected = (self.selected + (1 if key == "right" else -1)) % count
        elif key.isdigit() and 1 <= int(key) <= count:
            self.selected = int(key) - 1
        elif key in ("enter", " "):
            self.keys.append((0.0 if not self.keys else self.over, tuple(self.pose)))
            self.saved = False
        elif key == "u" and self.keys:
            self.keys.pop()
            self.saved = False
        elif key in ("+", "="):
            self.over = min(MAX_OVER, round(self.over + OVER_STEP, 3))
        elif key in ("-", "_"):
            self.over = max(MIN_OVER, round(self.over - OVER_STEP, 3))
        elif key == "p" and len(self.keys) > 1:
            return "play"
        elif key == "s" and self.keys:
            return "save"
        elif key in ("q", "esc"):
            if self.saved or not self.keys or asked:
                return "quit"
            self.asking = True
        return None

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
