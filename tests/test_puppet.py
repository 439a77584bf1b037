"""gestplay puppet: a MIDI controller (a take written by mido, a port of mido's backend
interface) drives the hand live through the drive loop, and its take is recorded."""

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from test_repl import ClockedPort, Timeline

from inmoov_dsl.boards.rig.core import BoardCore
from inmoov_dsl.live.controls import read_map
from inmoov_dsl.live.drive import Drive, library_program
from inmoov_dsl.live.midi import TakeFile, open_input, read_take
from inmoov_dsl.live.puppet import Puppet, midi_reading
from inmoov_dsl.profiles.profile import load_profile
from inmoov_dsl.wire.player import Link
from inmoov_dsl.wire.sim import VirtualBoard

mido = pytest.importorskip("mido", reason="the midi extra (pip install '.[test]')")

RHAND = load_profile("rhand")
ID = {s.name: s.id for s in RHAND.servos}
MAP = """\
[[control]]
cc = 1
servo = "index"

[[control]]
cc = 2
servo = "middle"
low = 20
high = 160
"""
FRAME = 0.02  #: s: a servo frame, and the controller's message rate here


def fader_take() -> list[tuple[float, int, int, int]]:
    """Fader 1 up over 2 s, then fader 2 down over 1 s, a message a frame; a knob the
    map does not take."""
    up = [(k * FRAME, 1, 1, round(127 * k / 100)) for k in range(101)]
    down = [(2 + k * FRAME, 1, 2, round(127 * (1 - k / 50))) for k in range(51)]
    return [*up, *down, (3.2, 1, 7, 64)]


def write_mid(path: Path, messages) -> Path:
    mid = mido.MidiFile(ticks_per_beat=480)
    track = mido.MidiTrack()
    mid.tracks.append(track)
    before = 0
    for t, channel, cc, value in messages:
        tick = round(mido.second2tick(t, 480, 500000))
        track.append(mido.Message("control_change", channel=channel - 1, control=cc,
                                  value=value, time=tick - before))
        before = tick
    mid.save(path)
    return path


def fader_value(take, cc: int, t: float, low: int, high: int) -> float:
    levels = [(m[0], m[3]) for m in take if m[2] == cc and m[0] <= t]
    return low + (high - low) * levels[-1][1] / 127 if levels else None


def test_the_hand_follows_the_faders_within_a_few_frames_and_never_jumps(tmp_path):
    take = fader_take()
    clock = Timeline([])  # time passes only when the loop sleeps or waits
    board = VirtualBoard(BoardCore.from_profile(RHAND, RHAND.boards[0]), 9600)
    link = Link(181, ClockedPort(board, clock), "clock")
    source = TakeFile(read_take(str(write_mid(tmp_path / "take.mid", take))), clock.now,
                      clock.sleep)
    puppet = Puppet(source, midi_reading(read_map(MAP, "map.toml", RHAND), RHAND), RHAND)
    Drive([link], RHAND, {}, library_program([]), lambda note: None, now=clock.now,
          sleep=clock.sleep).run(puppet)
    board.advance(clock.t + 1)
    assert board.positions()[ID["index"]] == 180 and board.positions()[ID["middle"]] == 20
    index = [(t, w.value) for t, w in board.log if w.id == ID["index"]]
    vmax = RHAND.servos[RHAND.index("index")].max_velocity
    times, values = np.array([t for t, _ in index]), np.array([v for _, v in index])
    assert np.all(np.abs(np.diff(values)) <= vmax * np.maximum(np.diff(times), FRAME) + 1)
    # while the fader moves, the finger is where the fader was at most 3 frames before
    lagging = [min(abs(v - fader_value(take, 1, t - lag, 0, 180)) for lag in
                   np.arange(0, 3 * FRAME + 1e-9, FRAME / 4))
               for t, v in index if 0.1 < t < 2.0]
    assert len(lagging) > 50 and max(lagging) <= 3, max(lagging)
    assert puppet.moves <= len(take) - 1  # the knob the map does not take moved nothing


def test_puppet_plays_a_take_on_sim_shows_each_move_and_records_it(tmp_path):
    mid = write_mid(tmp_path / "take.mid", fader_take())
    (tmp_path / "map.toml").write_text(MAP)
    done = subprocess.run(
        [sys.executable, "-m", "inmoov_dsl.cli.gestplay", "puppet", "--midi", str(mid),
         "--map", str(tmp_path / "map.toml"), "--port", "sim://", "--record",
         str(tmp_path / "take.gest")], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    shown = done.stdout.splitlines()
    assert shown[0] == "index 0" and shown[-1] == "middle 20" and len(shown) > 100
    assert "152 control changes" in done.stderr
    written = (tmp_path / "take.gest").read_text()
    steps = [line for line in written.splitlines() if line.startswith("    ")]
    assert 3 <= len(steps) <= 10, written
    check = subprocess.run([sys.executable, "-m", "inmoov_dsl.cli.gestc", "check",
                            str(tmp_path / "take.gest")], capture_output=True, text=True,
                           timeout=120)
    assert check.returncode == 0, check.stderr


def test_a_mistaken_map_is_told_at_its_key_before_any_port_is_opened(tmp_path):
    (tmp_path / "map.toml").write_text(MAP.replace('"middle"', '"midle"').replace(
        "cc = 1", "cc = 128"))
    done = subprocess.run(
        [sys.executable, "-m", "inmoov_dsl.cli.gestplay", "puppet", "--midi", "nowhere",
         "--map", str(tmp_path / "map.toml"), "--port", "/dev/nonexistent-port"],
        capture_output=True, text=True, timeout=120)
    assert done.returncode == 1
    assert f"{tmp_path / 'map.toml'}:2:1: error: control 1: 'cc' must be a MIDI control" \
        in done.stderr
    assert "unknown servo 'midle'" in done.stderr and "did you mean 'middle'" in done.stderr
    assert "nowhere" not in done.stderr and "nonexistent" not in done.stderr
    assert "Traceback" not in done.stderr


def backend_env(tmp_path: Path, script) -> dict[str, str]:
    (tmp_path / "script.txt").write_text("".join(f"{t:.3f} {ch} {cc} {v}\n"
                                                 for t, ch, cc, v in script))
    return {**os.environ, "MIDO_BACKEND": "midi_backend",
            "PYTHONPATH": os.pathsep.join([str(Path(__file__).parent),
                                           os.environ.get("PYTHONPATH", "")]),
            "MIDI_PORTS": "nanoKONTROL2:nanoKONTROL2 MIDI 1 20:0|Through Port-0",
            "MIDI_SCRIPT": str(tmp_path / "script.txt")}


def test_a_port_is_found_by_part_of_its_name_and_an_unknown_one_lists_them(tmp_path):
    env = backend_env(tmp_path, [])
    (tmp_path / "map.toml").write_text(MAP)
    done = subprocess.run(
        [sys.executable, "-m", "inmoov_dsl.cli.gestplay", "puppet", "--midi", "korg",
         "--map", str(tmp_path / "map.toml"), "--port", "sim://"],
        capture_output=True, text=True, timeout=120, env=env)
    assert done.returncode == 1
    assert ("error: 'korg' is neither a .mid file nor MIDI input port; the ports: "
            "'nanoKONTROL2:nanoKONTROL2 MIDI 1 20:0', 'Through Port-0'") in done.stderr
    before = mido.backend
    os.environ["MIDI_PORTS"] = env["MIDI_PORTS"]
    try:
        mido.set_backend("midi_backend", load=True)
        port = open_input("nanokontrol2")  # a part of its name, in any case
        assert port.name == "nanoKONTROL2:nanoKONTROL2 MIDI 1 20:0"
        port.close()
    finally:
        mido.backend = before
        os.environ.pop("MIDI_PORTS")


def test_a_controller_live_drives_sim_until_ctrl_c_and_the_take_is_kept(tmp_path):
    env = backend_env(tmp_path, fader_take()[:101])
    (tmp_path / "map.toml").write_text(MAP)
    proc = subprocess.Popen(
        [sys.executable, "-m", "inmoov_dsl.cli.gestplay", "puppet", "--midi", "nanoKONTROL2",
         "--map", str(tmp_path / "map.toml"), "--port", "sim://", "--record",
         str(tmp_path / "take.gest")], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
        text=True, env=env)
    seen = []
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and "index 180" not in seen:
        line = proc.stdout.readline()
        if not line:
            break
        seen.append(line.strip())
    assert "index 180" in seen, seen
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=60)
    assert proc.returncode == 130, err
    assert "interrupted: CANCEL sent, the hand holds its pose" in err, err
    assert "wrote " in err and (tmp_path / "take.gest").exists()
    assert "index 180" in (tmp_path / "take.gest").read_text()


def test_gestc_record_listens_to_a_controller_s_port_for_its_seconds(tmp_path):
    env = backend_env(tmp_path, fader_take()[:101])
    (tmp_path / "map.toml").write_text(MAP)
    done = subprocess.run(
        [sys.executable, "-m", "inmoov_dsl.cli.gestc", "record", "--midi", "nano", "--map",
         str(tmp_path / "map.toml"), "--seconds", "3", "-o", str(tmp_path / "up.gest")],
        capture_output=True, text=True, timeout=120, env=env)
    assert done.returncode == 0, done.stderr
    assert "gestc record: listening to nanoKONTROL2:nanoKONTROL2 MIDI 1 20:0" in done.stderr
    written = (tmp_path / "up.gest").read_text()
    assert "recorded from nano," in written and "index 180" in written


def test_a_fader_into_the_body_is_refused_once_told_and_the_arm_stays_clear(tmp_path):
    """On the whole robot the guard refuses every move that would bring the forearm into
    the chest (test_collide_play's elbow): told once, not at each of the fader's
    messages, and the arm stops short of it."""
    pytest.importorskip("fcl", reason="the [collide] extra brings python-fcl")
    take = [(0.1, 1, 1, 127)] + [(0.5 + k * 0.04, 1, 2, round(127 * k / 50))
                                 for k in range(51)]
    mid = write_mid(tmp_path / "elbow.mid", take)
    (tmp_path / "map.toml").write_text('[[control]]\ncc = 1\nservo = "r_rotate"\nlow = 60\n'
                                       'high = 125\n\n[[control]]\ncc = 2\n'
                                       'servo = "r_bicep"\nlow = 0\nhigh = 143\n')
    done = subprocess.run(
        [sys.executable, "-m", "inmoov_dsl.cli.gestplay", "puppet", "--midi", str(mid),
         "--map", str(tmp_path / "map.toml"), "--profile", "inmoov", "--port", "sim://"],
        capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stderr.count("error: at ") == 1, done.stderr
    assert "the right forearm comes near the chest" in done.stderr
    assert "the moves refused after this one are not told" in done.stderr
    dump = subprocess.run([sys.executable, "-m", "inmoov_dsl.cli.gestplay", "dump", "--port",
                           "sim://", "--profile", "inmoov"], capture_output=True, text=True,
                          timeout=120)
    held = {line.split()[0]: int(line.split()[-1]) for line in dump.stdout.splitlines()
            if line.strip().startswith(("r_bicep", "r_rotate"))}
    assert held["r_rotate"] == 125 and 0 < held["r_bicep"] < 143, held
