"""Another library's word on the self-collision check (tests/test_collide.py and
benchmarks/collisions.py): yourdfpy places the URDF's collision shapes, meshed by
trimesh, and trimesh's collision manager (FCL through its own meshes) says which parts
overlap. Needs the web extra (yourdfpy, trimesh)."""

from __future__ import annotations

import io
from collections.abc import Iterable, Sequence

from inmoov_dsl.hardware import Profile
from inmoov_dsl.model import joints
from inmoov_dsl.model.urdf import model


class Reference:
    """The profile's model, its parts overlapping as trimesh finds them."""

    def __init__(self, profile: Profile):
        import trimesh
        import yourdfpy

        self.profile = profile
        self.robot = yourdfpy.URDF.load(io.StringIO(model(profile)), build_scene_graph=False,
                                        build_collision_scene_graph=True, load_meshes=False,
                                        load_collision_meshes=True)
        scene = self.robot.collision_scene
        self.scene = scene
        self.link = {n: scene.graph.transforms.parents[n] for n in scene.graph.nodes_geometry}
        self.manager = trimesh.collision.CollisionManager()
        for node, name in self.link.items():
            self.manager.add_object(name, scene.geometry[scene.graph[node][1]])

    def overlapping(self, values: Sequence[float], pairs: Iterable[tuple[str, str]]
                    ) -> set[tuple[str, str]]:
        """Which of ``pairs`` (links) overlap when the servos hold ``values`` (profile
        order), each named as in ``pairs``."""
        self.robot.update_cfg(dict(zip(joints.names(self.profile),
                                       joints.positions(self.profile, values), strict=True)))
        for node, name in self.link.items():
            self.manager.set_transform(name, self.scene.graph[node][0])
        _, found = self.manager.in_collision_internal(return_names=True)
        wanted = set(pairs)
        return {p if p in wanted else p[::-1] for p in found
                if p in wanted or p[::-1] in wanted}
