"""``gestc preview``'s GIF of any profile: a hand alone drawn as preview.py draws it, a
robot with arms, a head or a torso as its model in 3-D (render.py), every part of it;
a frame per 20 ms servo frame of the stream, a pose that holds one longer frame, so the
GIF lasts as long as the gesture. A contact (``guard.marks``) is told at the bottom from
when it begins, for as long as it lasts (a second at least), its parts in red while
they touch.
"""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..compiling.compiled import Compiled
from ..compiling.metrics import held_at, sent_values
from ..compiling.plan import Plan
from ..errors import GestError
from ..hardware import Profile
from ..protocol import SERVO_FRAME
from . import preview
from .render import Renderer

if TYPE_CHECKING:
    import PIL.Image

TOLD = 1.0  #: s a contact's words stay at least, so that they can be read


def whole_robot(profile: Profile) -> bool:
    """Whether the profile's model is more than a hand on its forearm (arms, head,
    torso): drawn in 3-D; a hand alone keeps the hand's drawing."""
    from ..model.urdf import body

    try:
        return not body(profile)[0].link.endswith("_forearm")
    except GestError:  # a joint the model lacks: the hand's drawing, if it has a hand
        return False


def held(plan: Plan, compiled: Compiled, period: float = SERVO_FRAME
         ) -> tuple[np.ndarray, np.ndarray]:
    """(times, values): what every servo's board holds at the end of each servo frame,
    from the stream (rows of values in the profile's order)."""
    count = int(math.ceil(compiled.duration / period - 1e-9)) + 1
    times = np.arange(count) * period
    return times, held_at(plan.start, sent_values(plan, compiled), times)


@dataclass(frozen=True)
class Marked:
    """What a frame shows of the contacts: the links touching (indices into the model's
    ``Chain.links``) and the words of each contact told then."""

    hot: frozenset[int] = frozenset()
    words: tuple[str, ...] = ()


def marked(plan: Plan, times: np.ndarray, rows: np.ndarray) -> list[Marked]:
    """Each frame's contacts: the words of ``guard.marks`` from when each begins, while
    its two parts touch in the frames' poses (``rows`` at ``times``) and for TOLD
    seconds at least; the touching links. Nothing without python-fcl."""
    from ..model.collide import checker_for, first_contacts
    from ..model.guard import marks

    told = marks(plan)
    checker = checker_for(plan.profile) if told else None
    out = [Marked() for _ in times]
    if checker is None or not told:
        return out
    touches = first_contacts(checker, plan)  # marks' own, in its order (kept)
    pairs = {(checker.part(t.contact.a), checker.part(t.contact.b)): k
             for k, t in enumerate(touches)}
    index = {name: i for i, name in enumerate(checker.chain.links)}
    hot: list[set[int]] = [set() for _ in times]
    words: list[set[int]] = [set() for _ in times]
    for row, contacts in checker.sweep(np.asarray(rows, dtype=float), still=False):
        for c in contacts:
            k = pairs.get((checker.part(c.a), checker.part(c.b)))
            if k is not None and times[row] >= told[k][0] - SERVO_FRAME:
                hot[row] |= {index[c.a], index[c.b]}
                words[row].add(k)
    for k, (at, _) in enumerate(told):
        for row in np.flatnonzero((times >= at - 1e-9) & (times < at + TOLD)).tolist():
            words[row].add(k)
    return [Marked(frozenset(h), tuple(told[k][1] for k in sorted(w)))
            for h, w in zip(hot, words, strict=True)]


def animation(plan: Plan, compiled: Compiled, renderer: Renderer | None = None
              ) -> tuple[list[PIL.Image.Image], list[int]]:
    """The robot's frames and each one's duration in ms: one per servo frame, a frame
    held as long as the pose and its marks hold (the stream's timing, frame for
    frame)."""
    times, rows = held(plan, compiled)
    renderer = renderer or Renderer(plan.profile)
    renderer.fit(rows)
    images: list[PIL.Image.Image] = []
    durations: list[int] = []
    previous = None
    step = round(SERVO_FRAME * 1000)
    for t, values, mark in zip(times, rows, marked(plan, times, rows), strict=True):
        now = (tuple(values.tolist()), mark)
        if now == previous:
            durations[-1] += step
            continue
        images.append(renderer.draw(values, mark.hot, f"{compiled.gesture}  {t:5.2f} s",
                                    "; ".join(mark.words)))
        durations.append(step)
        previous = now
    return images, durations


def write_gif(plan: Plan, compiled: Compiled, path: str | os.PathLike) -> tuple[int, int]:
    """Write the preview of ``plan`` (the hand's drawing for a hand alone, the model for
    a robot); returns (frames, total ms)."""
    if not whole_robot(plan.profile):
        return preview.write_gif(plan, compiled, path)
    images, durations = animation(plan, compiled)
    save(images, durations, path)
    return len(images), sum(durations)


def save(images: Sequence[PIL.Image.Image], durations: Sequence[int],
         path: str | os.PathLike) -> None:
    """The frames as a GIF that loops."""
    images[0].save(path, save_all=True, append_images=list(images[1:]),
                   duration=list(durations), loop=0, optimize=False)
