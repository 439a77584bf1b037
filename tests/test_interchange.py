"""gestc export and gestc import: Blender Servo Animation's JSON and header, Bottango's
curve commands and our CSV, out and back; the header read as BSA's Arduino library reads
it, Bottango's curves evaluated as its driver evaluates them."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from inmoov_dsl.boards.pulses import angle, pulse_us, widths
from inmoov_dsl.cli.gestc import main as gestc
from inmoov_dsl.cli.target import load_target
from inmoov_dsl.compiling.compiler import compile_program
from inmoov_dsl.errors import GestError
from inmoov_dsl.interchange import bottango, bsa
from inmoov_dsl.interchange.frames import Frames
from inmoov_dsl.language.load import load

ADDON_KEYS = ["description", "fps", "frames", "seconds", "bones", "file", "scene",
              "positions"]  # json_export.py's dict, in its order
EXTS = {"bsa-json": ".json", "bsa-h": ".h", "bottango": ".txt", "csv": ".csv"}


def plan_of(target: str, profile: str | None = None):
    found = load_target(target, None, profile, [], "test")
    return compile_program(found.program, found.gesture, found.profile, None, False)[1]


def test_the_json_is_the_addons_with_the_widths_the_firmware_gives(tmp_path):
    """Field by field as the add-on's exporter writes them; frame 0 has every servo, each
    later frame only what changed; a position is the firmware's pulse for the planned
    whole value at that frame."""
    out = tmp_path / "peace.json"
    assert gestc(["export", "peace", "--format", "bsa-json", "-o", str(out)]) == 0
    data = json.loads(out.read_text())
    assert list(data) == ADDON_KEYS
    assert data["description"] == "Blender Servo Animation Positions"
    plan = plan_of("peace")
    assert data["fps"] == 50 and data["frames"] == len(data["positions"]) == 36
    assert data["seconds"] == round(36 / 50) and data["bones"] == 6
    servos = plan.profile.servos
    assert set(data["positions"][0]) == {str(s.pin) for s in servos}
    held: dict[str, int] = {}
    for k, frame in enumerate(data["positions"]):
        assert all(held.get(key) != v for key, v in frame.items())
        held.update(frame)
        for s, track in zip(servos, plan.tracks, strict=True):
            value = int(np.floor(track.position(k / 50) + 0.5))
            assert held[str(s.pin)] == pulse_us(angle(value, s.calibration, s.reversed))
    assert any(len(f) < 6 for f in data["positions"][1:])  # unchanged left out


def test_the_header_read_as_the_library_reads_it_plays_the_json(tmp_path):
    """FPS, FRAMES, LENGTH and the PROGMEM bytes, twelve a line; read byte by byte as BSA's
    ServoManager and Command read them, the same moves as the JSON's frames."""
    for fmt in ("bsa-json", "bsa-h"):
        assert gestc(["export", "wave", "--format", fmt, "-o",
                      str(tmp_path / f"wave{EXTS[fmt]}")]) == 0
    header = (tmp_path / "wave.h").read_text()
    data = json.loads((tmp_path / "wave.json").read_text())
    assert "const byte FPS = 50;" in header
    assert f"const int FRAMES = {data['frames']};" in header
    rows = header.split("ANIMATION_DATA[LENGTH] = {\n")[1].split("};")[0].splitlines()
    assert all(len(r.split(",")) - 1 == 12 for r in rows[:-1])
    raw = bytes(int(b, 16) for r in rows for b in r.split(",") if b.strip())
    assert f"const int LENGTH = {len(raw)};" in header
    played = bsa.play(raw)
    assert [{str(k): v for k, v in f.items()} for f in played] == data["positions"]


def test_the_library_misreads_a_marker_inside_a_command_so_none_is_written():
    """A '<' (0x3C) in a position starts the command again and a line feed ends the frame
    (BSA's Command.cpp, ServoManager::parseData): such a position is written one unit up,
    an ID of 10 or 60 refused."""
    bad = bytes([0x3C, 2, 0x05, 0x3C, 0x3E, 0x0A, 0x3C, 3, 0x05, 0x0A, 0x3E, 0x0A])
    assert bsa.play(bad) == [{}, {}, {}]  # nothing valid is moved
    rhand = plan_of("peace").profile
    servos = tuple(rhand.servos[:2])
    frames = Frames(rhand.boards[0], servos, 50.0, np.zeros(1), np.zeros((1, 2)))
    found = bsa.positions(frames, np.array([[1340, 1290]]), safe=True)  # 0x053C, 0x050A
    assert found == [{2: 1341, 3: 1291}]
    assert bsa.play(bsa.commands(found)) == found
    odd = Frames(rhand.boards[0], (servos[0].__class__(**{**servos[0].__dict__, "pin": 10}),),
                 50.0, np.zeros(1), np.zeros((1, 1)))
    with pytest.raises(GestError, match="reads servo ID 10 as a line feed"):
        bsa.positions(odd, np.array([[1500]]), safe=True)


@pytest.mark.parametrize("name", ["wave", "demo"])
def test_bottangos_curves_as_its_driver_evaluates_them_follow_the_plan(tmp_path, name):
    """Each curve found as the driver finds a moment (bisection to 1 ms), its Y as the
    driver maps it to a width: within a command degree of the plan, every 5 ms."""
    out = tmp_path / f"{name}.txt"
    assert gestc(["export", name, "--format", "bottango", "-o", str(out)]) == 0
    setups, curves = bottango.read(out.read_text(), str(out))
    plan = plan_of(name)
    ms = list(range(0, int(plan.duration * 1000) + 1, 5))
    worst = 0.0
    for servo, track in zip(plan.profile.servos, plan.tracks, strict=True):
        us = bottango.evaluate(setups[servo.pin], curves.get(servo.pin, []), ms)
        w = widths(servo)
        degrees = np.interp(us, w.exact, np.arange(181)) if w.exact[0] < w.exact[-1] \
            else np.interp(us, w.exact[::-1], np.arange(181)[::-1])
        worst = max(worst, float(np.max(np.abs(degrees - track.position(np.array(ms) / 1000)))))
    assert worst <= 1.0, worst


@pytest.mark.parametrize("fmt", list(EXTS))
def test_out_and_back_is_the_gesture_it_was(tmp_path, fmt):
    """Exported, imported through the recorder: the gesture's plan within 2 command
    degrees of the one exported, every 5 ms."""
    for name in ("peace", "wave"):
        out = tmp_path / f"{name}{EXTS[fmt]}"
        assert gestc(["export", name, "--format", fmt, "-o", str(out)]) == 0
        back = tmp_path / f"{name}-back.gest"
        assert gestc(["import", str(out), "-p", "rhand", "-o", str(back),
                      "--name", name]) == 0
        a = plan_of(name)
        b = compile_program(load(str(back)), name, "rhand", None, False)[1]
        t = np.arange(0, max(a.duration, b.duration), 0.005)
        worst = max(float(np.max(np.abs(x.position(t) - y.position(t))))
                    for x, y in zip(a.tracks, b.tracks, strict=True))
        assert worst <= 2.0, (name, fmt, worst, back.read_text())


@pytest.mark.parametrize("text, said", [
    ("hello", "which animation is it?"),
    ('{"fps": 0, "positions": []}', "its fps is 0"),
    ('{"fps": 30, "positions": [{"9": 1500}]}', "servo ID 9 is no servo of board 181"),
    ('{"fps": 30, "positions": [{"2": 300}]}', "PCA9685 ticks"),
    ("sC,2,0,100,0,33,0,8192,-33,0\n", "pin 2 has curves but no 'rSVPin,2"),
    ("time,indx\n0,0\n", "did you mean 'index'"),
])
def test_what_is_not_an_animation_is_an_error_and_nothing_is_written(tmp_path, text, said):
    """Exit 1, the file named and what is wrong, no .gest written, no traceback."""
    name = "anim.csv" if text.startswith("time") else \
        "anim.json" if text.startswith("{") else "anim.txt"
    src, out = tmp_path / name, tmp_path / "out.gest"
    src.write_text(text)
    done = subprocess.run([sys.executable, "-m", "inmoov_dsl.cli.gestc", "import", str(src),
                           "-o", str(out)], capture_output=True, text=True, timeout=120)
    assert done.returncode == 1, done.stderr
    assert said in done.stderr and "Traceback" not in done.stderr
    assert str(src.name) in done.stderr and not out.exists()


def test_the_old_joint_states_flag_still_works_and_says_the_new_one(tmp_path, capsys):
    out = tmp_path / "j.csv"
    assert gestc(["export", "peace", "--joint-states", str(out)]) == 0
    assert "--format joint-states" in capsys.readouterr().err
    assert out.read_text().startswith("time,")


def test_a_robot_of_two_boards_gets_a_file_a_board_and_both_come_back_as_one(tmp_path):
    """Exported a file a board (named by the board), imported together: one gesture
    moving both arms and the head (its default name made from the file's)."""
    (tmp_path / "lift.gest").write_text("robot inmoov\nlift: r_bicep 40, l_bicep 40, neck 100 "
                                         "over 0.6s\n")
    out = tmp_path / "lift.json"
    assert gestc(["export", str(tmp_path / "lift.gest"), "--format", "bsa-json", "-o",
                  str(out)]) == 0
    written = sorted(p.name for p in Path(tmp_path).glob("*.json"))
    assert written == ["lift-left.json", "lift-right.json"], written
    back = tmp_path / "lift-back.gest"
    assert gestc(["import", str(tmp_path / "lift-right.json"), str(tmp_path / "lift-left.json"),
                  "-p", "inmoov", "-o", str(back)]) == 0
    plan = compile_program(load(str(back)), "lift_back", "inmoov", None, False)[1]
    moved = {plan.profile.servos[i].name for step in plan.steps for i in step.servos
             if step.servos}
    assert {"r_bicep", "l_bicep", "neck"} <= moved, moved
    final = dict(zip((s.name for s in plan.profile.servos), plan.final, strict=True))
    # (a width two whole values share is read as the one whose exact width is nearest)
    assert all(abs(final[n] - v) <= 1 for n, v in
               (("r_bicep", 40), ("l_bicep", 40), ("neck", 100))), final
