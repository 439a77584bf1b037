"""The robot's self-collision check (model/collide.py): the rest pose is clear, an arm
driven into the chest is found, parts joined by a joint are never reported, the allowed
pairs kept beside each profile are the ones the generator makes, and the URDF's collision
geometry, read by another library, agrees."""

from __future__ import annotations

import io
import sys
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from inmoov_dsl.errors import GestError
from inmoov_dsl.model import joints
from inmoov_dsl.model.allowed import Allowed, allowed_pairs, digest, dumps, joined, load, path_for
from inmoov_dsl.model.collide import Checker, Contact
from inmoov_dsl.model.kinematics import Chain
from inmoov_dsl.model.urdf import model
from inmoov_dsl.profiles.profile import builtin_profiles, load_profile

pytest.importorskip("fcl", reason="the [collide] extra brings python-fcl")

PROFILES = builtin_profiles()  # every one has a model (gestc urdf)
ARM = ("r_bicep", "r_rotate", "r_shoulder", "r_omoplate")

# Found by sampling random right-arm poses (seed 5) and kept: the arm raised forward past
# the horizontal (r_shoulder 135, rest 30) while the omoplate lifts it sideways (151): in
# the plane the omoplate tilted, the upper arm swings in over the top of the chest.
INTO_CHEST = {"r_bicep": 96, "r_rotate": 32, "r_shoulder": 135, "r_omoplate": 151}


@pytest.fixture(scope="module")
def inmoov() -> Checker:
    return Checker(load_profile("inmoov"))


def random_poses(profile, count, seed, servos=None):
    """``count`` poses, each named servo (all by default) anywhere in its range."""
    rng = np.random.default_rng(seed)
    chosen = [s for s in profile.servos if servos is None or s.name in servos]
    for _ in range(count):
        yield {s.name: float(rng.uniform(s.lo, s.hi)) for s in chosen}


@pytest.mark.parametrize("name", PROFILES)
def test_the_rest_pose_is_never_a_contact(name):
    checker = Checker(load_profile(name))
    assert checker.pairs  # something is checked: the hands against the forearm at least
    assert checker.contacts({}) == []


def test_the_upper_arm_driven_into_the_chest_is_found(inmoov):
    (contact,) = inmoov.contacts(INTO_CHEST)
    assert (contact.a, contact.b) == ("chest", "r_upper_arm")
    assert 5 < contact.depth_mm < 40  # into it, by less than the upper arm's width (80)
    clear = dict(INTO_CHEST, r_shoulder=90)  # raised forward to the horizontal only
    assert inmoov.contacts(clear) == []


def test_a_near_miss_is_a_contact_within_the_clearance_only():
    profile = load_profile("inmoov")
    loose, tight = Checker(profile), Checker(profile, clearance_mm=0.0)
    assert loose.clearance_mm == 10.0  # the allowed pairs' file's
    misses = 0
    for pose in random_poses(profile, 300, 7, ARM):
        near = {(c.a, c.b) for c in loose.contacts(pose) if c.distance_mm > 0}
        misses += len(near)
        assert all(c.distance_mm < 0 for c in tight.contacts(pose))
        assert not near & {(c.a, c.b) for c in tight.contacts(pose)}
    assert misses > 10  # the arm passes close to the body often
    assert Contact("a", "b", 3.0).depth_mm == 0 and Contact("a", "b", -2.5).depth_mm == 2.5


@pytest.mark.parametrize("name", ["inmoov", "rhand"])
def test_pairs_joined_by_a_joint_are_never_checked_nor_reported(name):
    profile = load_profile(name)
    checker = Checker(profile)
    chain = Chain(profile)
    adjacent = {(chain.links[i], chain.links[j]) for (i, j), why in joined(chain).items()
                if why == "adjacent"}
    assert ("r_shoulder_link", "r_upper_arm") in adjacent or name != "inmoov"
    assert ("right_forearm", "right_palm") in adjacent
    assert not adjacent & set(checker.pairs)
    for pose in random_poses(profile, 300, 11):
        for c in checker.contacts(pose):
            assert (c.a, c.b) not in adjacent and (c.b, c.a) not in adjacent


@pytest.fixture(scope="module")
def generated():
    """The allowed pairs the generator makes, once per model (the three InMoov profiles
    share one, the right hands another)."""
    made: dict[str, Allowed] = {}

    def make(profile):
        key = digest(profile)
        if key not in made:
            made[key] = allowed_pairs(profile)
        return made[key]
    return make


@pytest.mark.parametrize("name", PROFILES)
def test_the_allowed_pairs_kept_are_the_ones_the_generator_makes(name, generated):
    profile = load_profile(name)
    kept = load(path_for(profile))
    assert kept.model == digest(profile), "run the generator again (docs/collisions.md)"
    made = generated(profile)
    assert kept.pairs == made.pairs
    assert dumps(kept) == path_for(profile).read_text()  # as the generator writes it
    assert (kept.clearance_mm, kept.samples, kept.seed) == (
        made.clearance_mm, made.samples, made.seed)


def test_the_allowed_pairs_are_the_joined_ones_and_a_few_always_close():
    kept = load(path_for(load_profile("inmoov")))
    reasons = {}
    for pair, why in kept.pairs.items():
        reasons.setdefault(why, set()).add(pair)
    assert ("r_upper_arm", "right_forearm") in reasons["always"]  # about the elbow
    assert ("neck_link", "jaw_link") in reasons["always"]
    assert ("right_index_2", "right_thumb_3") in reasons["hand"]
    assert ("chest", "r_upper_arm") not in kept
    assert not any("left_" in a and "right_" in b for a, b in kept.pairs)  # hands apart


def test_without_python_fcl_the_check_says_how_to_get_it(monkeypatch):
    monkeypatch.setitem(sys.modules, "fcl", None)  # import fcl raises ImportError
    with pytest.raises(GestError) as caught:
        Checker(load_profile("rhand"))
    message = caught.value.diagnostics[0].format()
    assert "needs python-fcl, which is not installed" in message
    assert "pip install 'inmoov-dsl[collide]'" in message


@pytest.mark.parametrize("name", ["inmoov", "rhand"])
def test_every_shape_of_the_urdf_is_also_its_collision_geometry(name):
    robot = ET.fromstring(model(load_profile(name)).split("\n", 2)[2])
    links = list(robot.iter("link"))
    assert sum(link.find("visual") is not None for link in links) >= 17
    for link in links:
        visual, collision = link.find("visual"), link.find("collision")
        if visual is None:
            assert collision is None
            continue
        shape, same = (list(e.find("geometry")) for e in (visual, collision))
        assert [(x.tag, x.attrib) for x in same] == [(x.tag, x.attrib) for x in shape]
        assert collision.find("origin").attrib == visual.find("origin").attrib


@pytest.mark.filterwarnings("ignore:.*Scene.dump:DeprecationWarning")  # yourdfpy's, meshing
def test_another_library_reading_the_urdf_agrees(inmoov):
    """yourdfpy places the URDF's collision shapes (meshed by trimesh) and trimesh's
    collision manager says which overlap; away from touching (a polygon is not quite a
    cylinder) it agrees with the check on every checked pair, pose after pose."""
    yourdfpy = pytest.importorskip("yourdfpy", reason="the [web] extra brings yourdfpy")
    trimesh = pytest.importorskip("trimesh", reason="yourdfpy brings trimesh")
    profile = inmoov.profile
    robot = yourdfpy.URDF.load(io.StringIO(model(profile)), build_scene_graph=False,
                               build_collision_scene_graph=True, load_meshes=False,
                               load_collision_meshes=True)
    scene = robot.collision_scene
    link = {node: scene.graph.transforms.parents[node] for node in scene.graph.nodes_geometry}
    manager = trimesh.collision.CollisionManager()
    for node, name in link.items():
        manager.add_object(name, scene.geometry[scene.graph[node][1]])
    checked, seen = set(inmoov.pairs), 0
    for pose in random_poses(profile, 300, 13):
        values = inmoov.chain.values(pose)
        robot.update_cfg(dict(zip(joints.names(profile), joints.positions(profile, values),
                                  strict=True)))
        for node, name in link.items():
            manager.set_transform(name, scene.graph[node][0])
        _, overlapping = manager.in_collision_internal(return_names=True)
        theirs = {pair for pair in overlapping if pair in checked or pair[::-1] in checked}
        theirs = {pair if pair in checked else pair[::-1] for pair in theirs}
        gaps = {(c.a, c.b): c.distance_mm for c in inmoov.contacts_of(values)}
        ours = {pair for pair, gap in gaps.items() if gap < -1.0}
        unsure = {pair for pair, gap in gaps.items() if -1.0 <= gap < 1.0}
        assert ours <= theirs, pose
        assert theirs - ours <= unsure, pose
        seen += len(ours)
    assert seen > 50  # the poses did put parts into each other
