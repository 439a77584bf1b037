"""The robot's URDF model (gestc urdf): it agrees with its profile, ROS's own parser
accepts it, and its joints move the parts a person expects."""

from __future__ import annotations

import math
import subprocess
import xml.etree.ElementTree as ET

import numpy as np
import pytest
from toolchain import need

from inmoov_dsl.cli import gestc
from inmoov_dsl.errors import GestError
from inmoov_dsl.model import joints
from inmoov_dsl.model.urdf import model
from inmoov_dsl.profiles.profile import builtin_profiles, load_profile, parse_profile
from inmoov_dsl.resources import profiles_dir

PROFILES = builtin_profiles()


def parsed(name):
    return ET.fromstring(model(load_profile(name)).split("\n", 2)[2])


@pytest.mark.parametrize("name", PROFILES)
def test_every_servo_turns_its_joint_within_its_range(name):
    profile = load_profile(name)
    robot = parsed(name)
    by_name = {j.get("name"): j for j in robot.iter("joint")}
    assert profile.servos  # each is looked up in by_name: the robot has joints too
    for servo in profile.servos:
        joint = by_name[servo.joint]
        assert joint.get("type") == "revolute"
        assert joint.find("mimic") is None
        limit = joint.find("limit")
        low, high = joints.limits(servo)
        assert float(limit.get("lower")) == pytest.approx(low, abs=1e-6)
        assert float(limit.get("upper")) == pytest.approx(high, abs=1e-6)
        assert float(limit.get("velocity")) == pytest.approx(
            servo.max_velocity * joints.scale(servo), rel=1e-5)
    turned = {s.joint for s in profile.servos}
    for joint in robot.iter("joint"):  # the rest follow a servo's joint, or stay put
        mimic = joint.find("mimic")
        if mimic is not None:
            assert mimic.get("joint") in turned
        elif joint.get("name") not in turned:
            assert joint.get("type") == "fixed", joint.get("name")


@pytest.mark.parametrize("name", PROFILES)
def test_ross_own_parser_accepts_the_model(name, tmp_path):
    need("check_urdf", packages="liburdfdom-tools")
    path = tmp_path / f"{name}.urdf"
    assert gestc.main(["urdf", "--profile", name, "-o", str(path)]) == 0
    done = subprocess.run(["check_urdf", str(path)], capture_output=True, text=True,
                          timeout=60)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "Successfully Parsed XML" in done.stdout
    root = {"rhand": "right_forearm", "lhand": "left_forearm"}.get(name.split("-")[0], "base_link")
    assert f"root Link: {root}" in done.stdout


def test_gestc_urdf_prints_the_model(capsys):
    assert gestc.main(["urdf"]) == 0
    out = capsys.readouterr().out
    assert out.startswith('<?xml version="1.0"?>')
    assert '<robot name="rhand">' in out and 'name="right_palm_to_index"' in out


def test_a_joint_the_model_lacks_is_a_clear_error(capsys):
    text = (profiles_dir() / "rhand.toml").read_text().replace(
        'joint = "right_palm_to_index"', 'joint = "right_palm_to_indx"')
    with pytest.raises(GestError) as caught:
        model(parse_profile(text, "mine.toml"))
    message = caught.value.diagnostics[0].format()
    assert message.startswith("mine.toml:48:1: error: ")  # at its joint key
    assert "servo 'index' turns joint 'right_palm_to_indx', which the InMoov model " \
        "does not have" in message
    assert "right_palm_to_index" in message  # did you mean


def kinematics(name, tmp_path):
    yourdfpy = pytest.importorskip("yourdfpy", reason="the [web] extra brings yourdfpy")
    path = tmp_path / f"{name}.urdf"
    path.write_text(model(load_profile(name)))
    return yourdfpy.URDF.load(str(path), load_meshes=False)


def posed(robot, profile, values):
    """Where each link is when the servos hold ``values`` (by servo name)."""
    held = [values.get(s.name, s.rest) for s in profile.servos]
    robot.update_cfg(dict(zip(joints.names(profile), joints.positions(profile, held),
                              strict=True)))
    where = {link: robot.get_transform(link)[:3, 3].copy() for link in robot.link_map}
    return where.__getitem__


def test_a_curled_finger_folds_towards_the_palm(tmp_path):
    profile = load_profile("rhand")
    robot = kinematics("rhand", tmp_path)
    straight = posed(robot, profile, {})("right_index_3")
    curled = posed(robot, profile, {"index": 180})("right_index_3")
    palm = posed(robot, profile, {})("right_palm")
    assert straight[2] - palm[2] > 0.15  # upright: the fingertip above the palm
    assert curled[1] < palm[1] - 0.02  # folded onto the palm's side (-y)
    assert curled[2] < straight[2] - 0.08
    half = posed(robot, profile, {"index": 90})("right_index_3")
    assert curled[2] < half[2] < straight[2]  # all the way, through the middle
    # the other fingers did not move
    assert posed(robot, profile, {"index": 180})("right_pinky_3") == pytest.approx(
        posed(robot, profile, {})("right_pinky_3"))


def test_the_wrist_turns_the_whole_hand_about_the_forearm(tmp_path):
    profile = load_profile("rhand")
    robot = kinematics("rhand", tmp_path)
    rest = posed(robot, profile, {})
    before = rest("right_thumb_3"), rest("right_palm")
    turned = posed(robot, profile, {"wrist": 180})
    after = turned("right_thumb_3"), turned("right_palm")
    assert after[1] == pytest.approx(before[1])  # the palm turns in place
    angle = math.atan2(after[0][1], after[0][0]) - math.atan2(before[0][1], before[0][0])
    assert abs(math.degrees(angle)) == pytest.approx(35, abs=1)  # calibration 125..160


def test_the_left_hand_is_the_right_hands_mirror_image(tmp_path):
    right, left = load_profile("rhand"), load_profile("lhand")
    r_robot, l_robot = kinematics("rhand", tmp_path), kinematics("lhand", tmp_path)
    pose = {"thumb": 120, "index": 60, "ring": 180, "wrist": 90}
    at_r, at_l = posed(r_robot, right, pose), posed(l_robot, left, pose)
    for link in ("palm", "thumb_3", "index_3", "ring_3", "pinky_3"):
        r, ll = at_r(f"right_{link}"), at_l(f"left_{link}")
        assert ll == pytest.approx(r * np.array([-1, 1, 1]), abs=1e-9), link


def test_the_robot_has_both_hands_at_its_sides_and_its_head_on_top(tmp_path):
    profile = load_profile("inmoov")
    robot = kinematics("inmoov", tmp_path)
    at = posed(robot, profile, {})
    assert at("right_palm")[1] < -0.15 < 0.15 < at("left_palm")[1]
    assert at("right_palm")[2] < at("chest")[2] < at("head")[2]
    # at rest the hands hang down; each hand curls as the hand profile's does
    assert at("right_index_3")[2] < at("right_palm")[2]
    raised = posed(robot, profile, {"r_shoulder": 120})  # raise the arm forward by 90
    assert raised("right_palm")[0] > at("right_palm")[0] + 0.3
    assert raised("left_palm") == pytest.approx(at("left_palm"))
    turned = posed(robot, profile, {"rothead": 150})  # look to the robot's left
    assert turned("right_eye")[1] > at("right_eye")[1]
