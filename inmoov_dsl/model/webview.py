"""The hand in 3-D in a browser, live: the page of ``gestsim --web`` (an edge: HTTP and
a websocket on 127.0.0.1, through viser, an optional extra).

viser serves its own client (a page built into its wheel: nothing is fetched from the
network) and draws the profile's URDF model (``urdf.model``) through yourdfpy. The board
loop hands over its values (``draw``, cheap: a copy when they changed); a thread of its
own turns them into joint positions (``joints.positions``) and moves the model, at most
FRAME apart, and sleeps while nothing changes.
"""

from __future__ import annotations

import contextlib
import io
import threading
from collections.abc import Sequence
from typing import Any

from ..errors import Diagnostic, GestError
from ..hardware import Board, Profile
from . import joints

INSTALL = "pip install 'inmoov-dsl[web]'"
FRAME = 1 / 30  #: s between two updates of the page, at most 30 a second
HOST = "127.0.0.1"  #: this computer only: the page is a view, not a service


def need_viser() -> tuple[Any, Any, Any]:
    """viser, yourdfpy and viser's URDF helper; a GestError saying how to get them if
    they are not installed."""
    try:
        import viser
        import yourdfpy
        from viser.extras import ViserUrdf
    except ImportError as exc:
        missing = (exc.name or "viser").partition(".")[0]
        raise GestError(Diagnostic(
            "error", f"gestsim --web needs viser and yourdfpy ({missing} is not installed)",
            hint=INSTALL)) from None
    return viser, yourdfpy, ViserUrdf


class WebView:
    """A page on ``http://127.0.0.1:PORT/`` where the profile's model takes the pose of
    one of its boards, live. ``port`` 0 takes any free one; a busy one, the next free."""

    def __init__(self, profile: Profile, board: Board, port: int):
        viser, yourdfpy, viser_urdf = need_viser()
        from .urdf import model  # an error if a servo's joint is not in the model

        robot = yourdfpy.URDF.load(io.StringIO(model(profile)))
        self.profile = profile
        self.slots = [profile.index(name) for name in board.servos]
        self.values = [s.rest for s in profile.servos]  #: the whole robot, profile order
        self.actuated: list[str] = list(robot.actuated_joint_names)  # every servo's joint
        with contextlib.redirect_stdout(io.StringIO()):  # stdout is the pty's path only
            self.server = viser.ViserServer(host=HOST, port=port, verbose=False)
        try:
            self._furnish(board, robot, viser_urdf)
        except BaseException:
            self.close()
            raise
        self.port: int = self.server.get_port()
        self.url = f"http://{HOST}:{self.port}/"
        self.shown: list[int] | None = None
        self._pending: list[int] | None = None
        self._lock = threading.Lock()
        self._whole = False  #: ``pose`` gave the whole robot's values
        self._wake, self._closing = threading.Event(), threading.Event()
        self._thread = threading.Thread(target=self._run, name="gestsim-web", daemon=True)
        self._thread.start()

    def _furnish(self, board: Board, robot: Any, viser_urdf: Any) -> None:
        """The scene: the model at rest on a floor, the camera on what the board moves."""
        import numpy as np

        server = self.server
        server.gui.configure_theme(show_share_button=False)  # sharing needs the internet
        server.gui.set_panel_label(f"gestsim: {self.profile.name}, board {board.id} "
                                   f"({board.name})")
        server.gui.main_panel.minimize()  # the hand has the page; the panel is a click away
        self.robot = viser_urdf(server, robot, root_node_name="/robot")
        self.robot.update_cfg(self.configuration(self.values))
        low, high = np.asarray(robot.scene.bounds, dtype=float)
        size = float(np.linalg.norm(high - low))
        server.scene.add_grid("/floor", width=2 * size, height=2 * size, cell_size=size / 20,
                              position=((low[0] + high[0]) / 2, (low[1] + high[1]) / 2, low[2]))
        low, high = _bounds(robot, {robot.joint_map[self.profile.servos[i].joint].child
                                    for i in self.slots})
        centre, radius = (low + high) / 2, float(np.linalg.norm(high - low)) / 2
        view = np.asarray(_viewpoint(robot.base_link, centre))
        camera = server.initial_camera
        camera.fov = np.radians(40)
        camera.look_at = centre
        camera.position = centre + view / np.linalg.norm(view) * radius / np.sin(
            camera.fov / 2) * 1.15

    def configuration(self, values: Sequence[float]) -> Any:
        """The model's actuated joints' positions (radians, its order) for the values
        of the profile's servos (profile order); a joint no servo turns stays at 0."""
        import numpy as np

        at = dict(zip(joints.names(self.profile), joints.positions(self.profile, values),
                      strict=True))
        return np.array([at.get(name, 0.0) for name in self.actuated])

    def draw(self, board: Any, now: float) -> None:
        """Called by the board loop on every turn: hand over the board's values if they
        changed (the page is moved by the view's own thread)."""
        values = board.core.values
        if values == self.shown:
            return
        self.shown = list(values)
        with self._lock:
            self._pending = self.shown
        self._wake.set()

    def pose(self, values: Sequence[int]) -> None:
        """Hand over the whole robot's values (profile order), if they changed: for a
        page that shows every board (``gestplay serve``)."""
        values = list(values)
        if values == self.shown:
            return
        self.shown = values
        with self._lock:
            self._pending = None
            self.values = list(values)
            self._whole = True
        self._wake.set()

    def _run(self) -> None:
        """Until closed: wait for new values, move the model, pause a frame."""
        while True:
            self._wake.wait()
            if self._closing.is_set():
                return
            self._wake.clear()
            with self._lock:
                board_values, self._pending = self._pending, None
                whole, self._whole = self._whole, False
                if board_values is not None:
                    for slot, value in zip(self.slots, board_values, strict=True):
                        self.values[slot] = value
                values = list(self.values)
            if board_values is not None or whole:
                self.robot.update_cfg(self.configuration(values))
            if self._closing.wait(FRAME):
                return

    def close(self) -> None:
        """Stop the thread and the server (the page then shows it is disconnected)."""
        if hasattr(self, "_closing"):
            self._closing.set()
            self._wake.set()
            self._thread.join(timeout=2)
        with contextlib.redirect_stdout(io.StringIO()):
            self.server.stop()


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
