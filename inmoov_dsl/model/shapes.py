"""The model's parts as a collision library's objects: how far apart two of them are,
through python-fcl (in the default install wherever PyPI has its wheel).

Why FCL (python-fcl) and not coal/pinocchio: FCL's primitives are the URDF's own (box,
cylinder, sphere: no mesh is made of them), it gives the distance between two shapes and
the depth of their overlap, and it is one small wheel on PyPI with numpy as its only
dependency; coal is FCL's fork behind pinocchio, a larger install for the same answers.

Nothing here computes a distance between shapes itself: FCL does. Each part's bounding
sphere (a centre and a radius, numpy) only skips the pairs that are clearly far apart
before FCL is asked, so a pose costs FCL calls for the few pairs near each other.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..errors import Diagnostic, GestError
from .kinematics import Chain
from .urdf_parts import Shape

#: how to get it where the default install had no wheel for it (Linux on ARM)
INSTALL = ("pip install python-fcl (on Linux ARM it builds from source: "
           "apt-get install libfcl-dev first)")


def need_fcl() -> Any:
    """The ``fcl`` module (python-fcl); a GestError saying how to get it if it is not
    installed."""
    try:
        import fcl
    except ImportError:
        raise GestError(Diagnostic(
            "error", "checking the robot's parts against each other needs python-fcl, "
            "which is not installed", hint=INSTALL)) from None
    return fcl


def geometry(fcl: Any, shape: Shape) -> Any:
    """The FCL shape of a part's: a box, a cylinder along z or a sphere, centred."""
    if shape.kind == "box":
        return fcl.Box(*shape.size)
    if shape.kind == "cylinder":
        return fcl.Cylinder(*shape.size)
    return fcl.Sphere(shape.size[0])


def bounding_radius(shape: Shape) -> float:
    """The radius of the sphere about the shape's centre that holds all of it."""
    if shape.kind == "box":
        return math.hypot(*shape.size) / 2
    if shape.kind == "cylinder":
        return math.hypot(shape.size[0], shape.size[1] / 2)
    return shape.size[0]


class Bodies:
    """The parts of a chain that have a shape, as FCL objects: ``links`` (their index in
    the chain, in its order) and ``names``; ``gaps`` tells how far pairs of them are."""

    def __init__(self, chain: Chain):
        self._fcl = fcl = need_fcl()
        self.links = [i for i, s in enumerate(chain.shapes) if s is not None]
        self.names = [chain.links[i] for i in self.links]
        shapes = [chain.shapes[i] for i in self.links]
        self._objects = [fcl.CollisionObject(geometry(fcl, s)) for s in shapes]
        self._offset = np.array([s.xyz for s in shapes], dtype=float).reshape(-1, 3)
        self.radius = np.array([bounding_radius(s) for s in shapes])  #: m, about centres
        self._reach = self.radius[:, None] + self.radius[None, :]  #: bounding spheres touch
        self._distance = fcl.DistanceRequest()
        self._collision = fcl.CollisionRequest(num_max_contacts=8, enable_contact=True)

    def near(self, transforms: np.ndarray, a: np.ndarray, b: np.ndarray,
             within_mm: float) -> np.ndarray:
        """Which pairs (``a[k]``, ``b[k]``: body indices) may be closer than
        ``within_mm``: their bounding spheres are (a mask)."""
        centre = self.centres(transforms)
        square = np.einsum("ij,ij->i", centre, centre)
        apart = square[:, None] + square[None, :] - 2 * (centre @ centre.T)  # squared
        pairs = a * len(centre) + b
        reach = self._reach.take(pairs) + within_mm / 1000
        return apart.take(pairs) < reach * reach

    def centres(self, transforms: np.ndarray) -> np.ndarray:
        """Each body's shape's centre in the base's frame (m), for every link's place."""
        return self.centres_of(transforms[..., self.links, :, :])

    def centres_of(self, places: np.ndarray) -> np.ndarray:
        """The centres (m) for the bodies' own places: (..., bodies, 4, 4) in, (...,
        bodies, 3) out."""
        return (np.einsum("...nij,nj->...ni", places[..., :3, :3], self._offset)
                + places[..., :3, 3])

    def reach(self, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        """How near (m) the centres of each pair may be before their bounding spheres
        touch."""
        return self._reach[a, b]

    def gaps(self, transforms: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        """The distance in mm between each pair's shapes, FCL's; less than 0 where they
        overlap: minus the depth of the overlap."""
        places = transforms[self.links]
        return self.gaps_at(places, self.centres_of(places), a, b)

    def gaps_at(self, places: np.ndarray, centres: np.ndarray, a: np.ndarray,
                b: np.ndarray) -> np.ndarray:
        """``gaps`` for the bodies' own places and centres (one pose)."""
        placed = set()
        out = np.empty(len(a))
        for k, (i, j) in enumerate(zip(a.tolist(), b.tolist(), strict=True)):
            for n in (i, j):
                if n not in placed:
                    self._objects[n].setRotation(places[n, :3, :3])
                    self._objects[n].setTranslation(centres[n])
                    placed.add(n)
            out[k] = self._gap(self._objects[i], self._objects[j])
        return out

    def around(self, transforms: np.ndarray, point: np.ndarray) -> list[tuple[int, float]]:
        """The bodies ``point`` (the base's frame, m) is inside of, with FCL's depth of
        it (mm), deepest first; none when it is outside every one."""
        fcl = self._fcl
        probe = fcl.CollisionObject(fcl.Sphere(1e-4))
        probe.setTranslation(point)
        places = transforms[self.links]
        centres = self.centres_of(places)
        near = np.linalg.norm(centres - point, axis=1) < self.radius + 1e-3
        found = []
        for n in np.flatnonzero(near).tolist():
            self._objects[n].setRotation(places[n, :3, :3])
            self._objects[n].setTranslation(centres[n])
            if (gap := self._gap(self._objects[n], probe)) <= 0:
                found.append((n, -gap))
        return sorted(found, key=lambda found: -found[1])

    def _gap(self, one: Any, other: Any) -> float:
        fcl = self._fcl
        distance = fcl.distance(one, other, self._distance, fcl.DistanceResult())
        if distance > 0:
            return distance * 1000
        result = fcl.CollisionResult()  # they touch: how deep, FCL's contacts say
        fcl.collide(one, other, self._collision, result)
        depth = max((c.penetration_depth for c in result.contacts), default=0.0)
        return -depth * 1000
