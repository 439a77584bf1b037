"""The places of a plan in the 3-D page (``gestc preview --live``, the editor's page): a
sphere at each place a step solved, the hand's path as a line over the whole gesture,
and the gaze as a ray from between the eyes while the robot is posed (docs/reach.md).
Positions come from the model's kinematics (``model.kinematics``), in the frame the
robot is drawn in (its base at the scene's origin)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from ..compiling.reaching import FRAMES
from ..model.kinematics import Chain

HAND = (230, 120, 40)  #: a hand's place and path
GAZE = (40, 140, 230)  #: the gaze's place and ray
RAY = 1.5  #: m, the gaze's ray
EVERY = 0.05  #: s between the points of a hand's path


class PlaceMarks:
    """What a page shows of one plan's places (``show``), and the gaze at a pose
    (``pose``)."""

    def __init__(self, server: Any):
        self.server = server
        self.handles: list[Any] = []
        self.ray: Any = None
        self._chain: Chain | None = None
        self._gaze: int | None = None

    def show(self, plan: Any) -> None:
        """Mark ``plan``'s places (None: no plan, nothing marked)."""
        self.clear()
        aims = {} if plan is None else {aim.pos: aim for step in plan.steps
                                        for aim, _ in step.solved}
        if not aims:
            return
        self._chain = Chain(plan.profile)
        scene = self.server.scene
        for k, aim in enumerate(aims.values()):
            colour = GAZE if aim.what == "look" else HAND
            self.handles.append(scene.add_icosphere(f"/places/p{k}", radius=0.015,
                                                    color=colour, position=aim.xyz))
            if aim.place:
                self.handles.append(scene.add_label(f"/places/name{k}", aim.place,
                                                  position=aim.xyz))
        hands = sorted({aim.what for aim in aims.values() if aim.what != "look"})
        times = np.arange(0.0, plan.duration + EVERY, EVERY)
        rows = np.stack([track.position(times) for track in plan.tracks], axis=1)
        world = self._chain.transforms(rows)
        for what in hands:
            path = world[:, self._chain.links.index(FRAMES[what]), :3, 3]
            segments = np.stack([path[:-1], path[1:]], axis=1)
            self.handles.append(scene.add_line_segments(f"/places/{what}_path", segments,
                                                        HAND, thickness=0.004))
        if any(aim.what == "look" for aim in aims.values()):
            self._gaze = self._chain.links.index(FRAMES["look"])

    def pose(self, values: Sequence[float]) -> None:
        """The gaze's ray at the pose ``values`` (when the plan looks at a place)."""
        if self._chain is None or self._gaze is None:
            return
        frame = self._chain.transforms(np.asarray(values, dtype=float))[self._gaze]
        start = frame[:3, 3]
        segment = np.stack([start, start + frame[:3, 0] * RAY])[None]
        if self.ray is None:
            self.ray = self.server.scene.add_line_segments("/places/gaze", segment, GAZE,
                                                           thickness=0.003)
        else:
            self.ray.points = segment

    def clear(self) -> None:
        """Take every mark off the page."""
        for handle in [*self.handles, *([self.ray] if self.ray is not None else [])]:
            handle.remove()
        self.handles, self.ray, self._chain, self._gaze = [], None, None, None
