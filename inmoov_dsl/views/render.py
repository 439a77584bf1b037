"""The robot's model drawn in 3-D with Pillow (pure but for Pillow): every part of a
profile's model (``kinematics.Chain``: urdf_parts' boxes, cylinders and spheres) placed
for a pose, seen from the front and a little from its right and above, shaded by a
light, the far faces drawn first; what ``gestc preview`` and ``gestsim --view`` show of
a robot with arms, a head or a torso.

A picture is a palette image ("P"): a few colours in SHADES shades each, so a GIF needs
no quantizing, frame after frame. The projection is orthographic and fitted once
(``fit``) to every pose of a motion, so the robot does not jump between frames.
"""

from __future__ import annotations

from collections.abc import Collection, Sequence
from typing import TYPE_CHECKING

import numpy as np

from ..hardware import Profile
from ..model.kinematics import Chain
from ..model.urdf_parts import COLOURS, Shape
from .preview import pillow

if TYPE_CHECKING:
    import PIL.Image

SHADES = 24  #: shades of each colour
HOT = "hot"  #: a part in contact
WHITE, INK, FLOOR, RED = 0, 1, 2, 3  #: palette indices of the plain colours
_PLAIN = ((255, 255, 255), (40, 40, 40), (214, 218, 222), (200, 30, 30))
_COLOURS = {**{k: v[:3] for k, v in COLOURS.items()}, HOT: (0.95, 0.25, 0.2)}
_FIRST = 8  #: the first shaded colour's index
VIEW = (1.0, -0.55, 0.4)  #: where the camera looks from: the robot's front, its right, above
LIGHT = (0.6, 0.3, 1.0)  #: where the light comes from (the camera's frame: right, up, towards)
SIDES = 12  #: faces around a cylinder


def palette() -> list[int]:
    """The pictures' palette: the plain colours, then each colour's shades, dark to
    light (a flat list of RGB bytes)."""
    out = [c for rgb in _PLAIN for c in rgb] + [0] * 3 * (_FIRST - len(_PLAIN))
    for rgb in _COLOURS.values():
        for k in range(SHADES):
            light = 0.3 + 0.75 * k / (SHADES - 1)
            out += [min(255, round(255 * c * light)) for c in rgb]
    return out + [0] * (768 - len(out))


def _box(size: Sequence[float]) -> tuple[np.ndarray, list[list[int]]]:
    x, y, z = (s / 2 for s in size)
    corners = np.array([[i * x, j * y, k * z] for i in (-1, 1) for j in (-1, 1)
                        for k in (-1, 1)])
    faces = [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4],
             [1, 5, 7, 3]]
    return corners, faces


def _cylinder(radius: float, length: float) -> tuple[np.ndarray, list[list[int]]]:
    a = np.linspace(0, 2 * np.pi, SIDES, endpoint=False)
    ring = np.stack([radius * np.cos(a), radius * np.sin(a)], axis=1)
    points = np.concatenate([np.c_[ring, np.full(SIDES, -length / 2)],
                             np.c_[ring, np.full(SIDES, length / 2)]])
    sides = [[k, (k + 1) % SIDES, SIDES + (k + 1) % SIDES, SIDES + k] for k in range(SIDES)]
    return points, [*sides, list(range(SIDES))[::-1], list(range(SIDES, 2 * SIDES))]


class Renderer:
    """Pictures of a profile's model, ``size`` pixels (width, height)."""

    def __init__(self, profile: Profile, size: tuple[int, int] = (400, 460)):
        self.chain = Chain(profile)
        self.size = size
        view = np.asarray(VIEW, dtype=float)
        self.towards = view / np.linalg.norm(view)  #: from the robot to the camera
        right = np.cross((0.0, 0.0, 1.0), self.towards)
        self.right = right / np.linalg.norm(right)
        self.up = np.cross(self.towards, self.right)
        light = np.asarray(LIGHT) @ np.stack([self.right, self.up, self.towards])
        self.light = light / np.linalg.norm(light)
        self._mesh = _Mesh(self.chain.shapes)
        self.scale, self.offset = 1.0, np.zeros(2)
        self._empty: PIL.Image.Image | None = None  #: the background, once drawn
        self._font: tuple | None = None  #: the title's and the caption's
        self.floor = np.zeros((4, 3))  #: its corners
        self.fit([self.chain.values({})])

    def _world(self, values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Every link's place for ``values``; every corner's place in the base frame."""
        places = self.chain.transforms(np.asarray(values, dtype=float))
        at = places[self._mesh.point_link]
        return places, np.einsum("nij,nj->ni", at[:, :3, :3], self._mesh.points) + \
            at[:, :3, 3]

    def fit(self, poses: Sequence[Sequence[float]] | np.ndarray) -> None:
        """Fit the picture to every pose of ``poses`` (servo values, profile order):
        the scale and the place that keep each of them whole in it, the floor under
        the lowest."""
        poses = np.asarray(poses, dtype=float).reshape(-1, len(self.chain.values({})))
        picked = np.unique(np.linspace(0, len(poses) - 1, min(len(poses), 100)).round())
        points = np.concatenate([self._corners(values) for values in poses[picked.astype(int)]])
        low, high = points.min(axis=0), points.max(axis=0)
        centre, half = (low + high) / 2, max(high[:2] - low[:2]) / 2 + 0.08
        self.floor = np.array([[centre[0] + i * half, centre[1] + j * half, low[2] - 0.03]
                               for i, j in ((-1, -1), (1, -1), (1, 1), (-1, 1))])
        flat = self._plane(np.concatenate([points, self.floor]))
        lo, hi = flat.min(axis=0), flat.max(axis=0)
        width, height = self.size
        room = np.array([width - 20, height - 76], dtype=float)  # the title, the caption
        self.scale = float(min(room / np.maximum(hi - lo, 1e-6)))
        self.offset = np.array([width / 2, 26 + room[1] / 2]) - self.scale * (lo + hi) / 2
        self._empty = None

    def holds(self, values: Sequence[float]) -> bool:
        """Whether the pose ``values`` is whole in the picture as it is fitted."""
        x, y = (self._plane(self._corners(values)) * self.scale + self.offset).T
        width, height = self.size
        return bool(x.min() >= 0 and x.max() <= width and y.min() >= 22
                    and y.max() <= height - 44)

    def _corners(self, values: Sequence[float]) -> np.ndarray:
        """Every corner of the model in the pose ``values``, and each sphere's centre
        and top."""
        places, world = self._world(np.asarray(values, dtype=float))
        balls = [self._ball(places, i, s) for i, s in self._mesh.balls]
        tops = [b + (0, 0, s.size[0]) for b, (_, s) in zip(balls, self._mesh.balls, strict=True)]
        return np.concatenate([world, np.reshape(balls + tops, (-1, 3))])

    @staticmethod
    def _ball(places: np.ndarray, link: int, shape: Shape) -> np.ndarray:
        return places[link][:3, 3] + places[link][:3, :3] @ np.asarray(shape.xyz)

    def _plane(self, points: np.ndarray) -> np.ndarray:
        """Points of the base frame on the picture's plane (x right, y down; unscaled)."""
        return np.stack([points @ self.right, -(points @ self.up)], axis=-1)

    def pixel(self, values: Sequence[float], link: str) -> tuple[float, float]:
        """Where the origin of ``link`` is drawn in the pose ``values`` (profile order)."""
        places = self.chain.transforms(np.asarray(values, dtype=float))
        return self._pixels(places[self.chain.links.index(link)][None, :3, 3])[0]

    def _pixels(self, points: np.ndarray) -> list[tuple[float, float]]:
        return [tuple(p) for p in (self._plane(points) * self.scale + self.offset).tolist()]

    def draw(self, values: Sequence[float], hot: Collection[int] = (), title: str = "",
             caption: str = "") -> PIL.Image.Image:
        """The model in the pose ``values`` (servo values, profile order), the links
        ``hot`` (indices into ``chain.links``) in the contact's colour, ``title`` at the
        top and ``caption`` (in red) at the bottom."""
        _, draw_mod, font_mod = pillow()
        img = self._background().copy()
        d = draw_mod.Draw(img)
        places, world = self._world(values)
        pixels = self._pixels(world)
        faces, depths, fills = self._faces(places, world, hot)
        balls = [(self._ball(places, i, shape), shape, i) for i, shape in self._mesh.balls]
        depths = np.concatenate([depths, [c @ self.towards + s.size[0] for c, s, _ in balls]])
        for k in np.argsort(depths, kind="stable").tolist():  # far first
            if k < len(faces):
                fill = int(fills[k])
                face = faces[k]
                d.polygon([pixels[c] for c in self._mesh.faces[face]], fill,
                          fill - 6 if self._mesh.edged[face] else fill)
                continue
            centre, shape, link = balls[k - len(faces)]
            (x, y), r = self._pixels(centre[None])[0], shape.size[0] * self.scale
            fill = _shade(HOT if link in hot else shape.colour, SHADES - 5)
            d.ellipse((x - r, y - r, x + r, y + r), fill=fill, outline=fill - 8)
            d.ellipse((x - 0.6 * r, y - 0.7 * r, x - 0.1 * r, y - 0.2 * r), fill=fill + 3)
        if self._font is None:
            self._font = font_mod.load_default(size=13), font_mod.load_default(size=12)
        if title:
            d.text((8, 6), title, fill=INK, font=self._font[0])
        if caption:
            _caption(d, caption, self._font[1], self.size)
        return img

    def _faces(self, places: np.ndarray, world: np.ndarray, hot: Collection[int]
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The faces turned to the camera: (which, their depths, their palette
        indices: their colour shaded by the light)."""
        mesh = self._mesh
        normals = np.einsum("nij,nj->ni", places[mesh.face_link, :3, :3], mesh.normals)
        facing = np.flatnonzero(normals @ self.towards > 1e-6)
        depth = np.add.reduceat((world @ self.towards)[mesh.flat], mesh.starts) / mesh.counts
        light = np.clip(normals[facing] @ self.light, 0.0, 1.0)
        shade = np.round((0.3 + 0.7 * light) * (SHADES - 1)).astype(int)
        colour = mesh.colour_index[facing]
        if hot:
            colour = np.where(np.isin(mesh.face_link[facing], list(hot)),
                              list(_COLOURS).index(HOT), colour)
        return facing, depth[facing], _FIRST + colour * SHADES + np.clip(shade, 0, SHADES - 1)

    def _background(self) -> PIL.Image.Image:
        """The picture before the robot: white, the floor's grid under it (drawn once
        per fit)."""
        if self._empty is None:
            image_mod, draw_mod, _ = pillow()
            self._empty = image_mod.new("P", self.size, WHITE)
            self._empty.putpalette(palette())
            d = draw_mod.Draw(self._empty)
            a, b, c, e = self.floor
            for k in np.linspace(0, 1, 11):  # ten by ten
                d.line(self._pixels(np.array([a + (b - a) * k, e + (c - e) * k])), FLOOR)
                d.line(self._pixels(np.array([a + (e - a) * k, b + (c - b) * k])), FLOOR)
        return self._empty


def _shade(colour: str, k: int) -> int:
    """The palette index of ``colour``'s shade ``k`` (0: the darkest)."""
    return _FIRST + list(_COLOURS).index(colour) * SHADES + max(0, min(SHADES - 1, k))


class _Mesh:
    """Every face of every part of a model, in its link's frame: ``faces`` (indices into
    ``points``), each one's ``normals``, ``colours``, ``face_link`` and whether its edge
    is drawn (``edged``: a box's, a cylinder's ends); the spheres (``balls``: link,
    shape), drawn as discs."""

    def __init__(self, shapes: Sequence[Shape | None]):
        points, links, self.faces, normals, face_link = [], [], [], [], []
        self.colours: list[str] = []
        self.edged: list[bool] = []
        self.balls: list[tuple[int, Shape]] = []
        count = 0
        for i, shape in enumerate(shapes):
            if shape is not None and shape.kind == "sphere":
                self.balls.append((i, shape))
            if shape is None or shape.kind == "sphere":
                continue
            box = shape.kind == "box"
            corners, polygons = _box(shape.size) if box else _cylinder(*shape.size)
            corners = corners + np.asarray(shape.xyz)
            for polygon in polygons:
                self.faces.append([count + k for k in polygon])
                a, b, c = corners[polygon[:3]]
                normal = np.cross(b - a, c - b)
                normals.append(normal / np.linalg.norm(normal))
                face_link.append(i)
                self.colours.append(shape.colour)
                self.edged.append(box or len(polygon) > 4)
            points.append(corners)
            links += [i] * len(corners)
            count += len(corners)
        self.points = np.concatenate(points) if points else np.zeros((0, 3))
        self.point_link = np.asarray(links, dtype=int)
        self.normals = np.asarray(normals, dtype=float).reshape(-1, 3)
        self.face_link = np.asarray(face_link, dtype=int)
        self.colour_index = np.asarray([list(_COLOURS).index(c) for c in self.colours],
                                       dtype=int)
        self.flat = np.asarray([k for f in self.faces for k in f], dtype=int)
        sizes = [len(f) for f in self.faces]
        self.starts = np.cumsum([0, *sizes[:-1]]).astype(int)
        self.counts = np.asarray(sizes, dtype=float)


def _caption(d, text: str, font, size: tuple[int, int]) -> None:
    """``text`` in red at the bottom of the picture, wrapped to its width."""
    width, height = size
    lines, line = [], ""
    for word in text.split():
        wider = f"{line} {word}".strip()
        if line and d.textlength(wider, font=font) > width - 16:
            lines.append(line)
            line = word
        else:
            line = wider
    lines.append(line)
    for k, line in enumerate(lines[-3:]):
        d.text((8, height - 8 - 16 * (len(lines[-3:]) - k)), line, fill=RED, font=font)
