"""Places (``right hand to cup``, ``look at cup``): solved at compile time into servo
values, checked where the hand ends by a URDF library we did not write (yourdfpy, on
``gestc urdf``'s model, posed by ``gestc export --joint-states``), refused at their place
in the file when out of reach or into the body."""

from __future__ import annotations

import csv
import os
import subprocess
import sys

import numpy as np
import pytest

from inmoov_dsl import compile_source
from inmoov_dsl.cli import gestc
from inmoov_dsl.errors import GestError
from inmoov_dsl.model import joints
from inmoov_dsl.model.collide import checker_for
from inmoov_dsl.profiles.profile import load_profile

yourdfpy = pytest.importorskip("yourdfpy", reason="the [web] extra brings yourdfpy")
ARM = ("r_omoplate", "r_shoulder", "r_rotate", "r_bicep")


@pytest.fixture(scope="module")
def robot(tmp_path_factory):
    """The whole robot's URDF, as ``gestc urdf`` writes it, read by yourdfpy."""
    path = tmp_path_factory.mktemp("urdf") / "inmoov.urdf"
    assert gestc.main(["urdf", "--profile", "inmoov", "-o", str(path)]) == 0
    return yourdfpy.URDF.load(str(path), load_meshes=False)


def end_pose(robot, tmp_path, text: str, gesture: str) -> None:
    """Pose ``robot`` as the gesture ends, from ``gestc export --joint-states``."""
    source, out = tmp_path / "g.gest", tmp_path / "g.csv"
    source.write_text("robot inmoov\n" + text)
    assert gestc.main(["export", str(source), "-g", gesture, "--joint-states",
                       str(out)]) == 0
    rows = list(csv.DictReader(out.open()))
    robot.update_cfg({k: float(v) for k, v in rows[-1].items() if k != "time"})


def where(robot, link: str) -> np.ndarray:
    return robot.get_transform(link)[:3, 3] * 1000


def test_the_model_has_the_frames_the_language_names(robot):
    for link in ("right_hand_point", "left_hand_point", "gaze"):
        assert link in robot.link_map
    # REP 103 at rest: the right hand hangs at the robot's right (-y), below its shoulder
    robot.update_cfg({})
    right, left = where(robot, "right_hand_point"), where(robot, "left_hand_point")
    assert right[1] < -150 and left[1] > 150 and abs(right[0] - left[0]) < 1
    gaze = robot.get_transform("gaze")
    assert gaze[2, 3] > 0.6 and gaze[:3, 0] @ np.array([1, 0, 0]) > 0.99  # forward


def seeded_places(robot, count: int, seed: int) -> list[np.ndarray]:
    """Places the right hand reaches clear of the body: where random arm poses put it
    (found by yourdfpy, not by the solver's kinematics)."""
    profile = load_profile("inmoov")
    checker = checker_for(profile)
    rng = np.random.default_rng(seed)
    servos = [profile.servos[profile.index(n)] for n in ARM]
    found = []
    while len(found) < count:
        pose = {s.name: int(rng.integers(s.lo, s.hi + 1)) for s in servos}
        if checker.contacts(pose):
            continue
        values = [pose.get(s.name, s.rest) for s in profile.servos]
        robot.update_cfg(dict(zip(joints.names(profile), joints.positions(profile, values),
                                  strict=True)))
        found.append(np.round(where(robot, "right_hand_point")))
    return found


def test_reachable_places_put_the_hand_within_5_mm(robot, tmp_path):
    places = seeded_places(robot, 6, seed=50)
    text = "".join(f"g{k}: right hand to ({x:.0f}, {y:.0f}, {z:.0f}) mm over 4s\n"
                   for k, (x, y, z) in enumerate(places))
    for k, place in enumerate(places):
        end_pose(robot, tmp_path, text, f"g{k}")
        miss = np.linalg.norm(where(robot, "right_hand_point") - place)
        assert miss <= 5.0, (place, miss)


def test_look_at_turns_the_gaze_within_2_degrees(robot, tmp_path):
    text = ("place face (1500, 300, 900) mm\n"
            "g: look at (1500, 0, 600) mm over 1s\n"
            "h: look at face over 1s\n")
    for gesture, goal in (("g", (1500, 0, 600)), ("h", (1500, 300, 900))):
        end_pose(robot, tmp_path, text, gesture)
        gaze = robot.get_transform("gaze")
        seen = np.asarray(goal) / 1000 - gaze[:3, 3]
        angle = np.degrees(np.arccos(seen @ gaze[:3, 0] / np.linalg.norm(seen)))
        assert angle <= 2.0, (gesture, angle)


def error_of(text: str) -> str:
    with pytest.raises(GestError) as info:
        compile_source("robot inmoov\n" + text, file="p.gest")
    return str(info.value)


def test_a_place_out_of_reach_is_an_error_at_it_with_the_miss_and_the_nearest():
    message = error_of("far: right hand to (2000, 0, 0) mm over 2s\n")
    assert message.startswith("p.gest:2:6: error: 'right hand to (2000, 0, 0) mm' is out "
                              "of reach: the right hand's point comes no closer than ")
    assert "hint: the nearest place it reaches is (" in message


def test_a_place_inside_the_body_names_the_parts():
    message = error_of("chest: right hand to (0, -50, 400) mm over 2s\n")
    assert message.startswith("p.gest:2:8: error: 'right hand to (0, -50, 400) mm' is "
                              "inside the chest (by ")


def test_a_value_for_a_servo_the_place_solves_is_an_error_at_the_value():
    message = error_of("place cup (350, -200, 300) mm\n"
                       "g: right hand to cup, r_thumb 180, r_bicep 90 over 2s\n")
    assert message.startswith("p.gest:3:44: error: 'r_bicep' is solved by 'right hand to "
                              "cup' in this step")


def test_a_hand_alone_has_no_arm_to_move():
    with pytest.raises(GestError) as info:
        compile_source("g: right hand to (300, 0, 300) mm over 1s\n", profile="rhand",
                       file="p.gest")
    assert "profile 'rhand' has no right arm to turn" in str(info.value)


def test_a_place_needs_its_unit_and_a_name_must_be_a_place():
    message = error_of("g: right hand to (300, 0, 300) over 1s\n"
                       "h: right hand to peace over 1s\n"
                       "peace: r_thumb 90\n")
    assert "p.gest:2:18: error: the place (300, 0, 300) needs a unit" in message
    assert "hint: write (300, 0, 300) mm or (300, 0, 300) m" in message


def test_the_same_file_gives_the_same_bytes_and_a_profile_place_is_used(tmp_path):
    profile = tmp_path / "inmoov.toml"
    with open(load_profile("inmoov").path) as given:
        profile.write_text(given.read() + "\n[place.desk]\nmm = [350, -200, 300]\n")
    source = f'robot "{profile}"\ng: right hand to desk, look at (1500, 400, 600) mm over 2s\n'
    first, again = (compile_source(source, file=str(tmp_path / "p.gest")) for _ in range(2))
    assert [bytes(s.data) for s in first.streams] == [bytes(s.data) for s in again.streams]
    moved = {n for n, a, b in zip(first.servos, first.start, first.final, strict=True)
             if a != b}
    assert set(ARM) <= moved and {"rothead", "neck"} <= moved


def test_a_gesture_played_on_the_left_mirrors_its_places(robot, tmp_path):
    text = ("place cup (350, -200, 300) mm\n"
            "reach: right hand to cup over 2s\n"
            "other: left reach\n")
    end_pose(robot, tmp_path, text, "other")
    assert np.linalg.norm(where(robot, "left_hand_point") - (350, 200, 300)) <= 5.0


def solved_values(text: str) -> dict[str, int]:
    """What ``gestc`` solves ``text`` (one step from rest) to: the servos it moves."""
    compiled = compile_source("robot inmoov\ng: " + text + "\n")
    return {n: v for n, a, v in zip(compiled.servos, compiled.start, compiled.final,
                                    strict=True) if a != v}


def test_the_repl_takes_a_place_and_solves_it_from_where_the_hand_is():
    typed = ("right hand to (350, -200, 300) mm over 2s\nwhere\n"
             "right hand to (2000, 0, 0) mm\nquit\n")
    done = subprocess.run([sys.executable, "-m", "inmoov_dsl.cli.gestplay", "repl",
                           "--profile", "inmoov", "--port", "sim://?boot=0"], input=typed,
                          capture_output=True, text=True, timeout=120)
    pose = dict(item.rsplit(" ", 1) for item in done.stdout.splitlines()[0].split("  "))
    assert {n: int(pose[n]) for n in ARM} == solved_values(
        "right hand to (350, -200, 300) mm over 2s")
    assert "<stdin>:3:1: error: 'right hand to (2000, 0, 0) mm' is out of reach" in done.stderr
    assert "Traceback" not in done.stderr


def test_the_service_plays_a_text_with_a_place_and_refuses_one_out_of_reach():
    from test_service import serving, until

    text = "g: right hand to (350, -200, 300) mm over 2s"
    with serving("--profile", "inmoov") as service, service.events() as ws:
        status, answer, _ = service.call("POST", "/api/play", {"text": text})
        assert status == 202, answer
        until(ws, "done", answer["id"], timeout=60)
        status, pose, _ = service.call("GET", "/api/pose")
        assert {n: pose["servos"][n]["value"] for n in ARM} == solved_values(text[3:])
        status, problem, _ = service.call(
            "POST", "/api/play", {"text": "g: right hand to (2000, 0, 0) mm over 1s"})
        assert status == 422 and "is out of reach" in problem["text"]


def test_without_the_toolbox_places_are_solved_slowly_and_said_once(monkeypatch, robot,
                                                                     tmp_path):
    from inmoov_dsl.model import ik

    monkeypatch.setattr(ik, "toolbox", lambda: None)
    monkeypatch.setattr(ik, "installed", lambda: False)
    text = ("robot inmoov\na: right hand to (400, -250, 350) mm over 2s\n"
            "b: left hand to (400, 250, 350) mm, right hand to (400, -250, 350) mm over 2s\n")
    path = tmp_path / "slow.gest"
    path.write_text(text)
    from inmoov_dsl.compiling.compiler import compile_program
    from inmoov_dsl.language.load import load

    _, plan = compile_program(load(str(path)), "b")
    said = [w for w in plan.warnings if "Robotics Toolbox" in w.message]
    assert len(said) == 1 and said[0].pos.line == 3  # once, at the first hand's place
    assert "pip install 'inmoov-dsl[reach]'" in said[0].message
    with pytest.raises(GestError, match="solved without the Robotics Toolbox"):
        compile_program(load(str(path)), "a", strict=True)
    values = dict(zip(plan.profile.names, plan.final, strict=True))
    robot.update_cfg(dict(zip(joints.names(plan.profile),
                              joints.positions(plan.profile, plan.final), strict=True)))
    assert np.linalg.norm(where(robot, "right_hand_point") - (400, -250, 350)) <= 5.0
    assert values["l_bicep"] == values["r_bicep"]  # the mirror image, solved the same way


def test_the_work_a_text_may_ask_of_the_solver_is_bounded(monkeypatch):
    from inmoov_dsl.compiling import reaching

    monkeypatch.setattr(reaching, "MAX_SOLVES", 3)
    steps = "".join(f"    right hand to ({400 + k}, -250, 350) mm over 0.5s\n" for k in range(5))
    message = error_of("g:\n" + steps)
    assert "p.gest:6:5: error: this gesture asks for more than 3 places to be solved" \
        in message
    again = "g:\n    repeat 50:\n        right hand to (400, -250, 350) mm over 0.5s\n" \
            "        right hand to (450, -250, 350) mm over 0.5s\n"
    compile_source("robot inmoov\n" + again)  # the same places from the same poses: 2 solves


def test_a_place_flows_staggers_and_runs_beside_another_part_as_values_do(robot):
    text = ("robot inmoov\nplace cup (350, -200, 300) mm\n"
            "flow:\n    right hand to cup over 1.5s through\n"
            "    right hand to (450, -250, 500) mm over 1.5s\n"
            "wave: right hand to cup, look at (1500, 400, 600) mm over 2s stagger 200ms\n"
            "both: flow & look_right\nlook_right: look at (1500, 400, 600) mm over 1s\n")
    flow, wave, both = (compile_source(text, gesture=g) for g in ("flow", "wave", "both"))
    profile = load_profile("inmoov")
    for compiled in (flow, both):  # through the cup without stopping, on to the next place
        robot.update_cfg(dict(zip(joints.names(profile),
                                  joints.positions(profile, compiled.final), strict=True)))
        assert np.linalg.norm(where(robot, "right_hand_point") - (450, -250, 500)) <= 5.0
    head = dict(zip(both.servos, both.final, strict=True))
    assert head["rothead"] != profile.servos[profile.index("rothead")].rest  # the other part
    assert wave.duration >= 2.0 and [s.asked for s in wave.steps] == [2.0]


def test_a_place_reached_only_into_the_body_names_the_moving_part_first():
    message = error_of("g: look at (350, -200, 300) mm over 2s\n")
    assert message.startswith("p.gest:2:4: error: 'look at (350, -200, 300) mm' puts the jaw "
                              "into the chest (by ")
    message = error_of("g: right hand to (342.321, 50.605, 379.044) mm over 2s\n")
    assert "mm' puts the right upper arm into the chest (by " in message  # within 5 mm of
    # the place only so: told as a contact, not as out of reach


def test_a_place_solved_once_is_kept_and_the_toolbox_not_imported_again(tmp_path):
    from inmoov_dsl.resources import CACHE_ENV

    source = tmp_path / "p.gest"
    source.write_text("robot inmoov\ng: right hand to (400, -250, 350) mm over 2s\n")
    run = ("import sys; from inmoov_dsl.cli import gestc; gestc.main(['show', sys.argv[1]]);"
           " print('toolbox', 'roboticstoolbox' in sys.modules)")
    env = {**os.environ, CACHE_ENV: str(tmp_path / "cache")}
    first, again = (subprocess.run([sys.executable, "-c", run, str(source)], env=env,
                                   capture_output=True, text=True, timeout=120)
                    for _ in range(2))
    assert first.stdout.endswith("toolbox True\n"), first.stderr
    assert again.stdout.endswith("toolbox False\n"), again.stderr  # seconds saved
    shown = [row for row in first.stdout.splitlines() if "right hand to" in row]
    assert shown and shown == [row for row in again.stdout.splitlines()
                               if "right hand to" in row]  # the same values
