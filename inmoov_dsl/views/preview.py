"""A schematic of the hand (``gestc preview``, ``gestsim --view``); needs Pillow (the
``plot`` extra).

The back of a right hand: the palm, four fingers that fold down over it as they curl,
the thumb swinging across it, and the wrist's rotation on a dial below. Each frame is
one 20 ms servo frame, drawn from the values the board holds at its end (decoded from
the compiled stream), so the animation runs at the stream's own timing.
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

import numpy as np

from ..compiling.compiled import Compiled
from ..compiling.metrics import held_at, sent_values
from ..compiling.plan import Plan
from ..errors import Diagnostic, GestError
from ..hardware import Profile
from ..protocol import MAX_VALUE, SERVO_FRAME

if TYPE_CHECKING:  # Pillow is optional: imported when a picture is drawn
    import PIL.Image

FINGERS = ("index", "middle", "ring", "pinky")
HAND = ("wrist", "thumb", *FINGERS)
WIDTH, HEIGHT = 240, 300
SKIN, EDGE, FOLDED, INK = (240, 200, 170), (120, 80, 60), (205, 160, 130), (40, 40, 40)
#: finger: x of its knuckle, lengths of its three bones (px)
_GEOMETRY = {"index": (86, (38, 24, 18)), "middle": (112, (42, 27, 19)),
             "ring": (138, (39, 25, 18)), "pinky": (162, (30, 19, 15))}
_PALM = (72, 130, 176, 225)  # left, top, right, bottom


def pillow():
    """Pillow's Image, ImageDraw and ImageFont; a GestError saying how to get it."""
    try:
        from PIL import Image, ImageDraw, ImageFont
    except ImportError:
        raise GestError(Diagnostic("error", "the preview needs Pillow, which is not "
                                   "installed", hint="pip install 'inmoov-dsl[plot]'")) from None
    return Image, ImageDraw, ImageFont


def hand_servos(profile: Profile) -> dict[str, int]:
    """Hand part -> index of the profile's servo that moves it (by name, or through a
    group of one servo, as the whole robot names its right hand)."""
    found = {}
    for part in HAND:
        members = (part,) if part in profile.names else profile.groups.get(part, ())
        if len(members) == 1:
            found[part] = profile.index(members[0])
    if not set(FINGERS) & set(found):
        raise GestError(Diagnostic(
            "error", f"profile '{profile.name}' has no hand to draw",
            hint="the preview draws servos named wrist, thumb, index, middle, ring, pinky"))
    return found


def draw_hand(pose: Mapping[str, int], title: str = "",
              image: PIL.Image.Image | None = None) -> PIL.Image.Image:
    """The hand in ``pose`` (part -> value 0..180; missing parts straight)."""
    Image, ImageDraw, ImageFont = pillow()  # noqa: N806 (modules)
    img = image or Image.new("RGB", (WIDTH, HEIGHT), "white")
    d = ImageDraw.Draw(img)
    font = ImageFont.load_default(size=12)
    left, top, right, bottom = _PALM
    # the forearm and the wrist dial
    d.rectangle((left + 16, bottom, right - 16, HEIGHT - 18), fill=SKIN, outline=EDGE)
    _dial(d, pose.get("wrist", 0), ((left + right) // 2, bottom + 38), font)
    d.rounded_rectangle(_PALM, radius=14, fill=SKIN, outline=EDGE, width=2)
    for finger in FINGERS:
        _finger(d, finger, pose.get(finger, 0), font)
    _thumb(d, pose.get("thumb", 0), font)
    if title:
        d.text((8, 6), title, fill=INK, font=font)
    return img


def _finger(d, finger: str, value: int, font) -> None:
    """Seen from the back, a finger curling toward the palm looks shorter, then folds
    down over the palm: each joint bends up to 80 degrees."""
    x, bones = _GEOMETRY[finger]
    y = float(_PALM[1])
    bend = math.radians(80) * value / MAX_VALUE
    angle = 0.0
    points = [(x, y)]
    for length in bones:
        angle += bend
        y -= length * math.cos(angle)
        points.append((x, y))
    for (x0, y0), (x1, y1) in zip(points, points[1:], strict=False):
        colour = FOLDED if y1 > y0 else SKIN  # going down: folded over the palm
        d.line((x0, y0, x1, y1), fill=EDGE, width=17)
        d.line((x0, y0, x1, y1), fill=colour, width=13)
    for px, py in points[1:-1]:
        d.ellipse((px - 3, py - 3, px + 3, py + 3), outline=EDGE)
    tip = points[-1][1]
    d.text((x, min(tip, _PALM[1]) - 22), str(value), fill=INK, font=font, anchor="mm")


def _thumb(d, value: int, font) -> None:
    """The thumb swings from pointing out (0) to lying across the palm (180)."""
    base = (_PALM[0] - 2, _PALM[3] - 34)
    direction = math.radians(-145 + 135 * value / MAX_VALUE)  # up-left -> right
    length = 58 - 18 * value / MAX_VALUE
    mid = (base[0] + 0.55 * length * math.cos(direction),
           base[1] + 0.55 * length * math.sin(direction))
    tip = (base[0] + length * math.cos(direction), base[1] + length * math.sin(direction))
    colour = FOLDED if value > 90 else SKIN
    d.ellipse((base[0] - 11, base[1] - 11, base[0] + 11, base[1] + 11), fill=SKIN,
              outline=EDGE, width=2)
    for a, b in ((base, mid), (mid, tip)):
        d.line((*a, *b), fill=EDGE, width=19)
        d.line((*a, *b), fill=colour, width=15)
    d.ellipse((mid[0] - 3, mid[1] - 3, mid[0] + 3, mid[1] + 3), outline=EDGE)
    d.text((tip[0] - 8, tip[1] - 14), str(value), fill=INK, font=font, anchor="mm")


def _dial(d, value: int, centre: tuple[int, int], font) -> None:
    """The wrist's rotation: a needle over a half circle, 0 left, 180 right."""
    cx, cy = centre
    r = 22
    d.pieslice((cx - r, cy - r, cx + r, cy + r), 180, 360, fill="white", outline=EDGE)
    a = math.radians(180 + value)
    d.line((cx, cy, cx + r * math.cos(a), cy + r * math.sin(a)), fill=INK, width=3)
    d.text((cx, cy + 12), f"wrist {value}", fill=INK, font=font, anchor="mm")


def poses(plan: Plan, compiled: Compiled, period: float = SERVO_FRAME
          ) -> tuple[np.ndarray, list[dict[str, int]]]:
    """The hand's pose at the end of every servo frame, from the stream: (times, poses)."""
    parts = hand_servos(plan.profile)
    count = int(math.ceil(compiled.duration / period - 1e-9)) + 1
    times = np.arange(count) * period
    held = held_at(plan.start, sent_values(plan, compiled), times)
    return times, [{part: int(row[i]) for part, i in parts.items()} for row in held]


def animation(plan: Plan, compiled: Compiled) -> tuple[list[PIL.Image.Image], list[int]]:
    """The frames of the preview and each one's duration in ms; a frame repeats only
    as long as the pose holds, so the timing is the stream's, frame for frame."""
    times, frames = poses(plan, compiled)
    images, durations = [], []
    previous: dict[str, int] | None = None
    for t, pose in zip(times, frames, strict=True):
        if pose == previous:
            durations[-1] += round(SERVO_FRAME * 1000)
            continue
        images.append(draw_hand(pose, f"{compiled.gesture}  {t:5.2f} s"))
        durations.append(round(SERVO_FRAME * 1000))
        previous = pose
    return images, durations


def write_gif(plan: Plan, compiled: Compiled, path: str | os.PathLike) -> tuple[int, int]:
    """Write the animation; returns (frames, total ms)."""
    images, durations = animation(plan, compiled)
    images[0].save(path, save_all=True, append_images=images[1:], duration=durations,
                   loop=0, optimize=False)
    return len(images), sum(durations)


def to_terminal(image: PIL.Image.Image, columns: int = 60) -> list[str]:
    """``image`` as terminal lines: two pixels per character cell (upper half block,
    24-bit colour)."""
    w, h = image.size
    rows = max(2, round(columns * h / w / 2) * 2)
    small = np.asarray(image.convert("RGB").resize((columns, rows)))
    lines = []
    for y in range(0, rows, 2):
        cells = []
        for top, bottom in zip(small[y], small[y + 1], strict=True):
            cells.append(f"\x1b[38;2;{top[0]};{top[1]};{top[2]}m"
                         f"\x1b[48;2;{bottom[0]};{bottom[1]};{bottom[2]}m\u2580")
        lines.append("".join(cells) + "\x1b[0m")
    return lines


def pose_of(profile: Profile, values: Sequence[int], servo_ids: Sequence[int]
            ) -> dict[str, int]:
    """The hand's pose from a board's values (servo ID order ``servo_ids``)."""
    by_id = dict(zip(servo_ids, values, strict=True))
    return {part: by_id[profile.servos[i].id] for part, i in hand_servos(profile).items()
            if profile.servos[i].id in by_id}
