"""gestc preview (the hand, animated), gestsim --view (the same, live), gestc export."""

import contextlib
import csv
import io
import math
import os
import subprocess
import sys
import threading
import time

import pytest
from PIL import Image

from inmoov_dsl import GestError, load_profile
from inmoov_dsl.cli import gestc
from inmoov_dsl.compiling.compiler import compile_program
from inmoov_dsl.language.library import scan_library
from inmoov_dsl.language.load import load
from inmoov_dsl.views.preview import draw_hand, hand_servos, poses

LIBRARY = scan_library()
POSIX = pytest.mark.skipif(not hasattr(os, "openpty"), reason="pseudo-terminals are POSIX")


def compiled(name, profile="rhand"):
    return compile_program(load(str(LIBRARY[name].path)), name, profile)


def test_the_preview_is_frame_accurate_to_the_stream(tmp_path, capsys):
    out = tmp_path / "peace.gif"
    assert gestc.main(["preview", "peace", "-o", str(out)]) == 0
    assert capsys.readouterr().err.startswith(f"wrote {out}: ")
    gif = Image.open(out)
    durations = []
    for k in range(gif.n_frames):
        gif.seek(k)
        durations.append(gif.info["duration"])
    c, plan = compiled("peace")
    # one frame per 20 ms servo frame, repeated frames merged: the same total time
    assert all(d % 20 == 0 for d in durations)
    assert sum(durations) == 20 * (math.ceil(c.duration / 0.02) + 1)
    times, frames = poses(plan, c)
    assert frames[0] == dict.fromkeys(("wrist", "thumb", "index", "middle", "ring",
                                       "pinky"), 0)
    assert frames[-1] == {"wrist": 0, "thumb": 180, "index": 0, "middle": 0, "ring": 180,
                          "pinky": 180}


def tip_is_drawn(image, finger_x, y=100):
    return image.getpixel((finger_x, y)) != (255, 255, 255)


def test_a_curled_finger_folds_down_and_a_straight_one_stands_up():
    straight = draw_hand({"index": 0, "ring": 0})
    curled = draw_hand({"index": 0, "ring": 180})
    assert tip_is_drawn(straight, 86) and tip_is_drawn(straight, 138)
    assert tip_is_drawn(curled, 86) and not tip_is_drawn(curled, 138)


def test_the_robot_hand_and_the_left_hand_are_drawn_too():
    assert hand_servos(load_profile("inmoov"))["index"] == load_profile("inmoov").index(
        "r_index")
    assert set(hand_servos(load_profile("lhand"))) == {"wrist", "thumb", "index", "middle",
                                                       "ring", "pinky"}
    from conftest import make_profile

    with pytest.raises(GestError, match="has no hand to draw"):
        hand_servos(make_profile({181: ["neck"]}))


def test_a_preview_must_be_a_gif(tmp_path, capsys):
    assert gestc.main(["preview", "peace", "-o", str(tmp_path / "p.png")]) == 1
    assert "write a .gif file, or into a directory" in capsys.readouterr().err


def test_export_writes_joint_states_in_radians(tmp_path, capsys):
    out = tmp_path / "peace.csv"
    assert gestc.main(["export", "peace", "--joint-states", str(out)]) == 0
    rows = list(csv.reader(io.StringIO(out.read_text())))
    assert rows[0] == ["time", "right_arm_to_wrist", "right_palm_to_thumb",
                       "right_palm_to_index", "right_palm_to_medius", "right_palm_to_ring",
                       "right_palm_to_pinky"]
    assert rows[1] == ["0.000"] + ["0.000000"] * 6
    # curled: each servo's real travel (thumb 50..160, ring 45..145, pinky 55..145)
    assert [float(x) for x in rows[-1]] == pytest.approx(
        [0.7, 0, math.radians(110), 0, 0, math.radians(100), math.radians(90)], abs=1e-6)
    assert len(rows) == 1 + 36  # 0.70 s at 50 rows a second, both ends
    times = [float(r[0]) for r in rows[1:]]
    assert times == pytest.approx([k * 0.02 for k in range(36)])


def test_export_names_the_robots_joints_like_the_model(capsys):
    assert gestc.main(["export", "peace", "--profile", "inmoov", "--joint-states", "-"]) == 0
    header, *rows = capsys.readouterr().out.splitlines()
    assert header.split(",")[1:8] == ["right_arm_to_wrist", "right_palm_to_thumb",
                                      "right_palm_to_index", "right_palm_to_medius",
                                      "right_palm_to_ring", "right_palm_to_pinky",
                                      "r_bicep"]  # the right Mega: hand, then arm
    assert "neck" in header.split(",")
    assert all(float(x) == 0 for x in rows[0].split(",")[1:])  # from rest: all at zero


@POSIX
def test_gestsim_view_draws_the_hand_live():
    master, slave = os.openpty()
    proc = subprocess.Popen([sys.executable, "-m", "inmoov_dsl.cli.gestsim", "--view",
                             "--boot", "0.1"], stdout=subprocess.PIPE, stderr=slave, text=True)
    os.close(slave)
    screen = bytearray()

    def watch():  # read the screen as it is drawn, or the view blocks on a full pty
        with contextlib.suppress(OSError):
            while chunk := os.read(master, 1 << 16):
                screen.extend(chunk)

    watcher = threading.Thread(target=watch, daemon=True)
    watcher.start()
    try:
        path = proc.stdout.readline().strip()
        player = subprocess.run([sys.executable, "-m", "inmoov_dsl.cli.gestplay", "peace",
                                 "--port", path], capture_output=True, timeout=30)
        assert player.returncode == 0, player.stderr
        assert b"warning" not in player.stderr  # the board answered while it drew
        time.sleep(0.3)
    finally:
        proc.kill()
        proc.wait()
        watcher.join(timeout=5)
        os.close(master)
    text = screen.decode(errors="replace")
    assert text.count("\u2580") >= 48 * 30  # a picture of half blocks, redrawn
    assert "\x1b[38;2;" in text and "\x1b[48;2;" in text


# --- the whole robot (views/film.py, views/render.py)

RAISE = "robot inmoov\n\nraise:\n    r_omoplate 100, r_shoulder 60, r_bicep 150 over 2s\n"


def frames_of(path):
    """The GIF's frames (RGB arrays) and their durations (ms)."""
    import numpy as np

    gif = Image.open(path)
    images, durations = [], []
    for k in range(gif.n_frames):
        gif.seek(k)
        durations.append(gif.info["duration"])
        images.append(np.asarray(gif.convert("RGB"), dtype=int))
    return images, durations


def region(image, centre, half=22):
    x, y = (round(c) for c in centre)
    return image[max(0, y - half):y + half, max(0, x - half):x + half]


def changed(a, b):
    """The share of pixels that differ between two regions."""
    return float((abs(a - b).sum(axis=-1) > 30).mean())


def test_a_robot_gesture_draws_the_whole_robot_moving(tmp_path, capsys):
    """The arm's region changes between the first and the last frame, the other arm's
    does not; a frame per 20 ms servo frame (holds merged): the gesture's length."""
    from inmoov_dsl.views.film import held
    from inmoov_dsl.views.render import Renderer

    source = tmp_path / "raise.gest"
    source.write_text(RAISE)
    out = tmp_path / "raise.gif"
    assert gestc.main(["preview", str(source), "-o", str(out)]) == 0
    images, durations = frames_of(out)
    said = capsys.readouterr().err
    assert said.startswith(f"wrote {out}: {len(images)} frames, ")
    c, plan = compile_program(load(str(source)), "raise", "inmoov")
    assert sum(durations) == 20 * (math.ceil(c.duration / 0.02) + 1)
    assert len(images) > 40 and images[0].shape == (460, 400, 3)
    _, rows = held(plan, c)
    where = Renderer(plan.profile)
    where.fit(rows)
    right, left = (where.pixel(rows[0], f"{side}_palm") for side in ("right", "left"))
    assert (region(images[0], right) < 200).any()  # the hand is drawn where it hangs
    assert changed(region(images[0], right), region(images[-1], right)) > 0.2
    assert changed(region(images[0], left), region(images[-1], left)) == 0
    elbow = where.pixel(rows[-1], "right_forearm")
    assert changed(region(images[0], elbow), region(images[-1], elbow)) > 0.2


def test_a_library_gesture_of_the_head_is_animated_for_its_length(tmp_path, capsys):
    """nod moves no hand: it was one frame of the right hand; it is the robot nodding."""
    out = tmp_path / "nod.gif"
    assert gestc.main(["preview", "nod", "-o", str(out)]) == 0
    images, durations = frames_of(out)
    c, _ = compiled("nod", "inmoov")
    assert sum(durations) == 20 * (math.ceil(c.duration / 0.02) + 1) > 4000
    assert len(images) > 100
    middle = images[len(images) // 3]
    top = slice(30, 160)  # the head, under the title
    assert changed(images[0][top], middle[top]) > 0.005
    assert changed(images[0][300:], middle[300:]) == 0  # the hands stay


def test_a_contact_is_told_and_its_parts_are_red_while_it_lasts(tmp_path, capsys):
    """The forearm enters the chest at 2.12 s: from then on the words at the bottom, in
    red, and the parts in the contact's colour; none before."""
    import numpy as np

    pytest.importorskip("fcl", reason="contacts are found with python-fcl")
    source = tmp_path / "elbow.gest"
    source.write_text("robot inmoov\n\nelbow:\n    r_rotate 125 over 1.5s\n"
                      "    r_bicep 143 over 2s\n")
    out = tmp_path / "elbow.gif"
    assert gestc.main(["preview", str(source), "-o", str(out)]) == 0
    images, durations = frames_of(out)
    starts = np.cumsum([0, *durations[:-1]]) / 1000
    words = [(abs(im[400:] - (200, 30, 30)).sum(axis=-1) == 0).sum() for im in images]
    hot = [(abs(im[30:400] - (242, 64, 51)).sum(axis=-1) < 40).sum() for im in images]
    before, after = starts < 2.1, starts > 2.2
    assert max(np.array(words)[before]) == 0 and min(np.array(words)[after]) > 50
    assert max(np.array(hot)[before]) == 0 and min(np.array(hot)[after]) > 200


def pictures(text):
    """The pictures a terminal view drew, as arrays (two pixels per character cell); a
    frame cut off (the view killed while it drew it, rows of different lengths) left out."""
    import re

    import numpy as np

    cell = re.compile(r"\x1b\[38;2;(\d+);(\d+);(\d+)m\x1b\[48;2;(\d+);(\d+);(\d+)m\u2580")
    found = []
    for frame in re.split(r"\x1b\[\d+F", text):
        rows = []
        for line in frame.split("\n"):
            cells = [tuple(map(int, c)) for c in cell.findall(line)]
            if cells:
                rows += [[c[:3] for c in cells], [c[3:] for c in cells]]
        if rows and len({len(row) for row in rows}) == 1:
            found.append(np.array(rows))
    return found


@POSIX
def test_gestsim_view_draws_the_whole_robot_of_every_board(tmp_path):
    """``gestsim --view --profile inmoov``: one picture of the robot, both boards in it;
    both elbows bent (the right arm on board 181, the left on 183), both arms move in
    the picture, the head stays."""
    master, slave = os.openpty()
    proc = subprocess.Popen([sys.executable, "-m", "inmoov_dsl.cli.gestsim", "--view",
                             "--profile", "inmoov", "--boot", "0.1"],
                            stdout=subprocess.PIPE, stderr=slave, text=True)
    os.close(slave)
    screen = bytearray()

    def watch():  # read the screen as it is drawn, or the view blocks on a full pty
        with contextlib.suppress(OSError):
            while chunk := os.read(master, 1 << 16):
                screen.extend(chunk)

    watcher = threading.Thread(target=watch, daemon=True)
    watcher.start()
    source = tmp_path / "elbows.gest"
    source.write_text("robot inmoov\n\nelbows:\n    r_bicep 90, l_bicep 90 over 1.5s\n")
    try:
        ports = proc.stdout.readline().strip()
        player = subprocess.run([sys.executable, "-m", "inmoov_dsl.cli.gestplay",
                                 str(source), "--port", ports], capture_output=True,
                                timeout=60)
        assert player.returncode == 0, player.stderr
        time.sleep(0.5)
    finally:
        proc.kill()
        proc.wait()
        watcher.join(timeout=5)
        os.close(master)
    drawn = pictures(screen.decode(errors="replace"))
    assert len(drawn) >= 3 and drawn[0].shape == drawn[-1].shape == (64, 56, 3)
    moved = (abs(drawn[0] - drawn[-1]).sum(axis=-1) > 30)
    assert moved[:, :28].sum() > 10 and moved[:, 28:].sum() > 10  # its right arm, its left
    assert not moved[:24].any()  # the head
