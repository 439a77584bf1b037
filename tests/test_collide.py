"""The robot's self-collision check (model/collide.py): the rest pose is clear, an arm
driven into the chest is found, parts joined by a joint are never reported, the allowed
pairs kept beside each profile are the ones the generator makes, and the URDF's collision
geometry, read by another library, agrees."""

from __future__ import annotations

import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

from inmoov_dsl.errors import GestError
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
    assert loose.clearance_mm == 10.0  # the profile's (by default)
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
    assert "pip install python-fcl" in message


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
    pytest.importorskip("yourdfpy", reason="the [web] extra brings yourdfpy")
    from trimesh_reference import Reference

    reference, checked, seen = Reference(inmoov.profile), set(inmoov.pairs), 0
    for pose in random_poses(inmoov.profile, 300, 13):
        values = inmoov.chain.values(pose)
        theirs = reference.overlapping(values, checked)
        gaps = {(c.a, c.b): c.distance_mm for c in inmoov.contacts_of(values)}
        ours = {pair for pair, gap in gaps.items() if gap < -1.0}
        unsure = {pair for pair, gap in gaps.items() if -1.0 <= gap < 1.0}
        assert ours <= theirs, pose
        assert theirs - ours <= unsure, pose
        seen += len(ours)
    assert seen > 50  # the poses did put parts into each other (about 500 of them)


def test_a_motion_swept_at_once_finds_what_each_of_its_poses_finds(inmoov):
    """The sweep measures a pair again only once its parts may have moved far enough:
    along a motion through random whole-robot poses, it finds at every pose exactly the
    contacts (and distances) that checking that pose alone finds."""
    profile = inmoov.profile
    keys = np.array([inmoov.chain.values(p) for p in random_poses(profile, 9, 17)])
    t = np.linspace(0, len(keys) - 1, 400)  # 50 poses from one key pose to the next
    values = np.stack([np.interp(t, np.arange(len(keys)), keys[:, i])
                       for i in range(keys.shape[1])], axis=1)
    swept = {(row, c.a, c.b): c.distance_mm for row, found in inmoov.sweep(values)
             for c in found}
    alone = {(row, c.a, c.b): c.distance_mm for row in range(len(values))
             for c in inmoov.contacts_of(values[row])}
    assert len(alone) > 100  # the motion does put parts into each other
    assert swept == alone


def test_the_clearance_is_the_profile_s(inmoov):
    from inmoov_dsl.profiles.profile import parse_profile

    text = Path(load_profile("inmoov").path).read_text(encoding="utf-8")
    near = {"r_bicep": 96, "r_rotate": 32, "r_shoulder": 123, "r_omoplate": 151}
    gaps = [c.distance_mm for c in inmoov.contacts(near)]
    assert gaps and all(0 < g < 10 for g in gaps)  # near, not in: within 10 mm
    touching = parse_profile(text + "\n[collision]\nclearance_mm = 0\n", "inmoov.toml")
    assert touching.clearance_mm == 0.0
    assert Checker(touching, inmoov.allowed).contacts(near) == []  # 0: overlaps only
    for bad, said in (("clearance_mm = -1", "must be a number of millimetres in 0..100"),
                      ("clearance = 5", "unknown key 'clearance'"),
                      ("clearance_mm = true", "must be a number")):
        with pytest.raises(GestError) as caught:
            parse_profile(text + f"\n[collision]\n{bad}\n", "inmoov.toml")
        assert said in caught.value.first.message, caught.value.first.message


def test_without_python_fcl_players_say_so_once_and_check_nothing(monkeypatch):
    from inmoov_dsl.model import collide, guard

    monkeypatch.setitem(sys.modules, "fcl", None)
    monkeypatch.setattr(collide, "_CHECKERS", {})
    robot, hand = load_profile("inmoov"), load_profile("rhand")
    assert guard.Guard(hand).missing is None  # a hand alone: nothing to check anyway
    keeper = guard.Guard(robot)
    assert "python-fcl is not installed" in keeper.missing.message
    assert keeper.missing.hint.startswith("pip install python-fcl")
    from inmoov_dsl.compiling.compiler import compile_source

    with pytest.raises(GestError) as caught:  # --strict: not checked is an error
        from inmoov_dsl.compiling.compiler import plan_checks

        with plan_checks(guard.check_plan):
            compile_source("robot inmoov\nx: r_shoulder 135 over 3s", strict=True)
    assert "needs python-fcl" in caught.value.first.message


def test_a_pose_taught_into_the_chest_is_refused_and_allowed_with_a_warning():
    from inmoov_dsl.model.guard import Guard

    profile = load_profile("inmoov")
    pose = [INTO_CHEST.get(s.name, s.rest) for s in profile.servos]
    with pytest.raises(GestError) as caught:
        Guard(profile).pose(pose, [profile.index("r_shoulder")])
    (said,) = caught.value.diagnostics
    assert said.message.startswith("the right upper arm enters the chest by ")
    assert said.message.endswith("(r_shoulder 135)") and "--allow-contact" in said.hint
    (warned,) = Guard(profile, allow_contact=True).pose(pose, [profile.index("r_shoulder")])
    assert warned.severity == "warning"
