"""The robot's model in a viser scene on 127.0.0.1 (an edge; viser is the ``web`` extra):
what the pages of ``gestsim --web`` (webview.py) and ``gestc preview --live``
(livepage.py) share: viser found or told how to get, its server started quietly on this
computer, the profile's URDF model (``urdf.model``, through yourdfpy) on a floor with the
camera on the part of the body that matters, posed by servo values (``joints.positions``).
"""

from __future__ import annotations

import contextlib
import io
from collections.abc import Collection, Sequence
from typing import Any

from ..errors import Diagnostic, GestError
from ..hardware import Profile
from ..model import joints
from . import gate
from .gate import HOST

INSTALL = "pip install 'inmoov-dsl[web]'"


def need_viser(command: str = "gestsim --web") -> tuple[Any, Any, Any]:
    """viser, yourdfpy and viser's URDF helper; a GestError saying how to get them if
    they are not installed (``command``: what needs them, as the message says it)."""
    try:
        import viser
        import yourdfpy
        from viser.extras import ViserUrdf
    except ImportError as exc:
        missing = (exc.name or "viser").partition(".")[0]
        raise GestError(Diagnostic(
            "error", f"{command} needs viser and yourdfpy ({missing} is not installed)",
            hint=INSTALL)) from None
    return viser, yourdfpy, ViserUrdf


def start_server(viser: Any, port: int) -> Any:
    """viser's server on HOST:``port`` (0: any free one; a busy one: the next free),
    printing nothing (a command's standard output is its own), its "share" button
    hidden (sharing goes through viser's servers, on the internet), and no request
    answered that another web site sends (``gate``)."""
    gate.install()
    with contextlib.redirect_stdout(io.StringIO()):
        server = viser.ViserServer(host=HOST, port=port, verbose=False)
    gate.quiet(server)
    server.gui.configure_theme(show_share_button=False)
    return server


def stop_server(server: Any) -> None:
    """Stop ``server`` quietly (its pages then show they are disconnected)."""
    with contextlib.redirect_stdout(io.StringIO()):
        server.stop()


class Robot:
    """The profile's model in ``server``'s scene, at rest on a floor, the camera on the
    links the servos of ``servos`` (names; all the profile's when None) turn."""

    def __init__(self, server: Any, profile: Profile, servos: Collection[str] | None = None,
                 command: str = "gestsim --web"):
        viser, yourdfpy, viser_urdf = need_viser(command)
        from ..model.urdf import model  # an error if a servo's joint is not in the model

        self.profile = profile
        self.urdf = yourdfpy.URDF.load(io.StringIO(model(profile)))
        self.actuated: list[str] = list(self.urdf.actuated_joint_names)  # servos' joints
        self._names = joints.names(profile)
        self.handle = viser_urdf(server, self.urdf, root_node_name="/robot")
        self.values: list[float] | None = None  #: the pose it is in
        self._sent: dict[int, float] = {}  #: id(joint frame) -> the angle it was sent
        self._so3 = viser.transforms.SO3
        self.pose([s.rest for s in profile.servos])
        names = profile.names if servos is None else servos
        self._furnish(server, {self.urdf.joint_map[profile.servos[profile.index(n)].joint]
                               .child for n in names})

    def _furnish(self, server: Any, links: set[str]) -> None:
        """A floor under the model; the camera on ``links`` and what hangs from them."""
        import numpy as np

        robot = self.urdf
        low, high = np.asarray(robot.scene.bounds, dtype=float)
        size = float(np.linalg.norm(high - low))
        self.floor = server.scene.add_grid(
            "/floor", width=2 * size, height=2 * size, cell_size=size / 20,
            position=((low[0] + high[0]) / 2, (low[1] + high[1]) / 2, low[2]))
        low, high = _bounds(robot, links)
        centre, radius = (low + high) / 2, float(np.linalg.norm(high - low)) / 2
        view = np.asarray(_viewpoint(robot.base_link, centre))
        fov = np.radians(40)
        position = centre + view / np.linalg.norm(view) * radius / np.sin(fov / 2) * 1.15
        for camera in [server.initial_camera, *(c.camera for c in
                                                 server.get_clients().values())]:
            camera.fov = fov
            camera.look_at = centre
            camera.position = position

    def configuration(self, values: Sequence[float]) -> Any:
        """The model's actuated joints' positions (radians, its order) for the values
        of the profile's servos (profile order); a joint no servo turns stays at 0."""
        import numpy as np

        at = dict(zip(self._names, joints.positions(self.profile, values), strict=True))
        return np.array([at.get(name, 0.0) for name in self.actuated])

    def remove(self) -> None:
        """Take the model and its floor out of the scene."""
        self.handle.remove()
        self.floor.remove()

    def pose(self, values: Sequence[float]) -> None:
        """Move the model to the servos' ``values`` (profile order), unless it is there
        (nothing is sent): only the joints that turn, each from its own angle (viser's
        ``update_cfg`` places every joint through the whole model: 8 ms for the InMoov,
        a frame's budget while playing, against a few hundred microseconds)."""
        if list(values) == self.values:
            return
        first, self.values = self.values is None, list(values)
        configuration = self.configuration(values)
        frames = getattr(self.handle, "_joint_frames", None)
        joints = getattr(self.handle, "_joint_map_values", None)
        if first or frames is None or joints is None or len(frames) != len(joints):
            self.handle.update_cfg(configuration)  # the first: every joint, fixed ones too
            return
        at = dict(zip(self.actuated, configuration.tolist(), strict=True))
        for joint, frame in zip(joints, frames, strict=True):
            angle = _angle(joint, at)
            if angle is None or self._sent.get(id(frame)) == angle:
                continue
            self._sent[id(frame)] = angle
            place = _joint_transform(joint, angle)
            frame.wxyz = self._so3.from_matrix(place[:3, :3]).wxyz
            frame.position = place[:3, 3] * self.handle._scale


def _angle(joint: Any, at: dict[str, float]) -> float | None:
    """A yourdfpy joint's position (rad, m) when the actuated joints are ``at``: its
    own, or the one it follows (mimic); None for a joint that never moves."""
    if joint.type not in ("revolute", "continuous", "prismatic"):
        return None
    if joint.mimic is not None:
        return at[joint.mimic.joint] * joint.mimic.multiplier + joint.mimic.offset
    return at.get(joint.name, 0.0)


def _joint_transform(joint: Any, angle: float) -> Any:
    """The child link's place in its parent's frame, the joint at ``angle`` (as yourdfpy
    computes it)."""
    import numpy as np
    from trimesh import transformations

    origin = np.eye(4) if joint.origin is None else joint.origin
    if joint.type == "prismatic":
        return origin @ transformations.translation_matrix(angle * np.asarray(joint.axis))
    return origin @ transformations.rotation_matrix(angle, joint.axis)


def robot_for(server: Any, current: Robot | None, profile: Profile, command: str
              ) -> tuple[Robot | None, str]:
    """The model of ``profile`` in ``server``'s scene: ``current`` if it is that
    profile's, else a new one (``current`` taken out); None, and why, for a profile whose
    servos the model does not have."""
    if current is not None and (current.profile.name, current.profile.sha256) == \
            (profile.name, profile.sha256):
        return current, ""
    if current is not None:
        current.remove()
    try:
        return Robot(server, profile, command=command), ""
    except GestError as exc:
        return None, "; ".join(d.message for d in exc.diagnostics)


def _bounds(robot: Any, links: set[str]) -> Any:
    """The lowest and highest corner of the shapes of ``links`` and every link under
    them, in the model's frame, as it stands."""
    import numpy as np
    import trimesh

    graph, corners = robot.scene.graph, []
    for node in graph.nodes_geometry:
        up = node
        while up != graph.base_frame and up not in links:
            up = graph.transforms.parents[up]
        if up in links:
            transform, name = graph[node]
            shape = robot.scene.geometry[name]
            corners.append(trimesh.transform_points(shape.bounding_box.vertices, transform))
    points = np.concatenate(corners) if corners else np.asarray(robot.scene.bounds)
    return points.min(axis=0), points.max(axis=0)


def _viewpoint(root: str, centre: Any) -> tuple[float, float, float]:
    """Where the camera looks from (a direction) at what is around ``centre``, by
    urdf_parts' frames: a hand alone stands on its forearm with its palm towards -y, a
    right thumb on +x (a left one on -x); the robot faces +x with its left on +y, its
    hands hang at its sides with their palms towards it, so a part on one side is seen
    from the front, a little from the middle."""
    if root.endswith("_forearm"):
        return (-0.5 if root.startswith("left") else 0.5), -1.0, 0.45
    return 1.0, 0.4 if centre[1] < -0.05 else -0.4, 0.3
