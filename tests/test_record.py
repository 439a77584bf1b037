"""gestc record: a glove's stream in, a short gesture out that plays the recording back."""

import os
import re
import subprocess
import sys

import numpy as np
import pytest

from inmoov_dsl import load_profile
from inmoov_dsl.compiling.compiler import compile_program
from inmoov_dsl.decode import StreamReader
from inmoov_dsl.language.library import scan_library
from inmoov_dsl.language.load import load
from inmoov_dsl.live.record import Recording, keyframes, shortest_path, start_pose, to_gest, traces
from inmoov_dsl.protocol import SERVO_FRAME
from inmoov_dsl.wire.glove import GloveCore, Imperfections, glove_stream, on_the_clock

RHAND = load_profile("rhand")
GLOVE = RHAND.gloves[0]
FINGERS = frozenset(range(1, 6))
LIBRARY = scan_library()
POSIX = pytest.mark.skipif(not hasattr(os, "openpty"), reason="pseudo-terminals are POSIX")


def truth(name):
    return compile_program(load(str(LIBRARY[name].path)), name, RHAND)[1]


def record(stream, tolerance=3.0):
    reader = StreamReader(FINGERS)
    for t, data in stream:
        reader.feed(t, data)
    tr = traces(reader.samples, RHAND, GLOVE.deadband)
    fit = keyframes(tr, RHAND, tolerance)
    text = to_gest("again", fit.keyframes, RHAND, ["a test"])
    _, plan = compile_program(load("again.gest", text), "again", RHAND,
                              dict(start_pose(fit.keyframes, RHAND)))
    return reader, tr, fit, text, plan


def worst(plan, motion, tr, t0, outside=()):
    """The largest difference between the replayed and the true motion of the fingers,
    on every servo frame (except in the windows ``outside``)."""
    keep = np.ones(len(tr.times), dtype=bool)
    for a, b in outside:
        keep &= (tr.times + t0 < a) | (tr.times + t0 > b + 0.2)
    return max(float(np.abs(plan.tracks[i].position(tr.times[keep])
                            - motion.tracks[i].position(tr.times[keep] + t0)).max())
               for i in range(1, 6))


def test_the_reader_waits_for_a_cancel_and_skips_what_is_not_a_pair():
    reader = StreamReader(frozenset({1, 2}))
    reader.feed(0.0, [90, 2, 45])  # joined mid-command: nothing is a pair yet
    reader.feed(0.02, [255, 1, 30, 254, 2, 200, 7, 9, 253, 2, 60])
    assert reader.samples == [(0.02, 1, 30), (0.02, 2, 60)]
    assert reader.skipped == 3 + 4  # the 3 bytes before the CANCEL; WAIT, 200, (7, 9), DUMP


def test_a_clean_recording_becomes_the_gesture_it_was():
    motion = truth("count")
    reader, tr, fit, text, plan = record(glove_stream(motion, GLOVE))
    assert fit.error <= 3.0 and not fit.stretched
    assert len(fit.keyframes) == 10 and len(reader.samples) > 20 * len(fit.keyframes)
    # within the tolerance of what the glove reported, which is within its dead-band
    assert worst(plan, motion, tr, reader.samples[0][0]) <= 3.0 + GLOVE.deadband
    assert plan.final[1:] == motion.final[1:]
    assert text.startswith("# a test\nagain:\n    thumb 0, index 0, middle 0, ring 0, "
                           "pinky 0\n    thumb 180, middle 180, ring 180, pinky 180 over ")


def test_fingers_that_start_one_after_another_become_a_stagger():
    motion = truth("bye")  # its moves have "stagger 40ms"
    reader, tr, fit, text, plan = record(glove_stream(motion, GLOVE))
    assert fit.error <= 3.0
    assert "stagger" in text
    assert worst(plan, motion, tr, reader.samples[0][0]) <= 3.0 + GLOVE.deadband
    # each keyframe is reached by the recording's segment from the one before
    recording = Recording(tr, RHAND, 3.0)
    cuts = [round(key.at / SERVO_FRAME) for key in fit.keyframes]
    moves = [recording.segment(a, b) for a, b in zip(cuts, cuts[1:], strict=False)]
    assert [(m.stagger, m.order) for m in moves] == [(k.stagger, k.order)
                                                     for k in fit.keyframes[1:]]
    assert any(m.order for m in moves) and max(m.error for m in moves) == fit.error


def test_the_shortest_path_costs_least_then_takes_fewest_hops_then_strays_least():
    costs = {(0, 3): (5.0, 0.0), (0, 2): (1.0, 0.0)}

    def cost(i, j):
        return costs.get((i, j), (0.0, 1.0))

    assert shortest_path(4, cost) == [0, 1, 3]  # as cheap as 0 1 2 3, in fewer hops
    assert shortest_path(4, cost, window=1) == [0, 1, 2, 3]
    assert shortest_path(1, cost) == [0]
    costs[0, 2] = (0.0, 1.0)
    costs[1, 3] = (0.0, 2.0)  # 0 1 3 as cheap and as short as 0 2 3, but strays further
    assert shortest_path(4, cost) == [0, 2, 3]


def test_noise_lost_bytes_a_gap_and_a_mid_command_start_do_not_break_it():
    motion = truth("wiggle")
    gap = (2.3, 2.6)  # nothing arrives for 0.3 s, in the middle of a move
    untidy = Imperfections(noise=0.5, drop=0.005, gaps=(gap,), seed=3)
    reader, tr, fit, text, plan = record(glove_stream(motion, GLOVE, untidy), tolerance=4)
    assert reader.skipped >= 2  # the tail of a command before the first CANCEL
    assert len(fit.keyframes) < len(reader.samples) / 10
    assert worst(plan, motion, tr, reader.samples[0][0], [gap]) <= 4 + GLOVE.deadband + 1.5
    assert plan.final[1:] == motion.final[1:]


def test_a_lost_byte_that_makes_a_wrong_pair_is_dropped():
    motion = truth("peace")
    stream = glove_stream(motion, GLOVE, Imperfections(mid_command=False))
    t_end = stream[-1][0]
    # "255 4 180 3 0" lost its "180": the ring (4) seems to jump to 3
    stream.append((t_end + 0.02, bytes([255, 4, 3, 0])))
    reader, tr, fit, _, plan = record(stream)
    assert tr.dropped == 1
    assert plan.final == motion.final


def test_late_arrivals_are_put_back_on_the_gloves_clock():
    rng = np.random.default_rng(2)
    sent = [(k * 0.02, 1, k) for k in range(100)]
    late = [(t + 0.5 + rng.uniform(0, 0.006), sid, v) for t, sid, v in sent]
    snapped = on_the_clock(late, 0.02)
    assert [v for _, _, v in snapped] == list(range(100))
    steps = np.diff([t for t, _, _ in snapped])
    assert np.allclose(steps, 0.02)
    scattered = [(rng.uniform(0, 2), 1, k) for k in range(100)]
    scattered.sort()
    assert on_the_clock(scattered, 0.02) == scattered  # not a clock: left as it is


def test_the_python_glove_maps_and_keeps_its_dead_band():
    core = GloveCore([1, 2], [(500, 700), (500, 700)], [False, True], 2)
    assert core.update([500, 500]) == bytes([255, 1, 0, 2, 180])
    assert core.update([501, 501]) == b""
    assert core.update([600, 700]) == bytes([255, 1, 90, 2, 0])
    core.feed(250, [600, 600])  # MIN: these readings are now 0
    assert core.update([600, 600]) == bytes([255, 1, 0, 2, 180])


@POSIX
def test_record_a_virtual_glove_on_a_pseudo_terminal(tmp_path):
    """A process streams count (noisy, losing a byte now and then, and silent for 0.3 s
    while the hand holds) into a pseudo-terminal at the glove's rate; gestc record
    listens in real time; the gesture it writes, compiled, follows the motion."""
    sim = subprocess.Popen([sys.executable, "-m", "inmoov_dsl.cli.gestsim", "--glove",
                            "count", "--noise", "0.3", "--drop", "0.003", "--gap", "0.7-1.0",
                            "--boot", "0.1"],
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        path = sim.stdout.readline().strip()
        assert path.startswith("/dev/"), sim.stderr.read()
        out = tmp_path / "counted.gest"
        done = subprocess.run([sys.executable, "-m", "inmoov_dsl.cli.gestc", "record",
                               "--port", path, "-o", str(out), "--seconds", "6.5"],
                              capture_output=True, text=True, timeout=60)
    finally:
        sim.kill()
        sim.wait()
    assert done.returncode == 0, done.stderr
    assert f"wrote {out}: counted, " in done.stderr
    compiled, _ = compile_program(load(str(out)), None, RHAND)
    assert compiled.gesture == "counted"
    assert compiled.final[1:] == (0, 0, 0, 0, 0)
    keys, samples = (int(x) for x in re.search(r"(\d+) keyframes from (\d+) samples",
                                                done.stderr).groups())
    assert keys < samples / 10
    # from the first recorded pose, the replay passes through the poses of the motion
    # and through no others: each within the tolerance (3) of what the glove reported,
    # which is within its dead-band (2) and the noise of the true motion. When each byte
    # came depends on when two processes ran on a busy machine, so the poses are compared
    # here, not their times (the times: test_late_arrivals_are_put_back_on_the_gloves_
    # clock and the clean recordings above, on the glove's own clock)
    first_pose = out.read_text().splitlines()[2].strip()  # the step after "counted:"
    _, replay = compile_program(load(str(out)), None, RHAND, first_pose)
    motion = truth("count")
    poses = [np.stack([plan.tracks[i].position(np.arange(0, plan.duration, 0.01))
                       for i in range(1, 6)], axis=1) for plan in (motion, replay)]
    far = [float(np.abs(a[:, None, :] - b[None, :, :]).max(axis=2).min(axis=1).max())
           for a, b in (poses, poses[::-1])]
    assert max(far) <= 3 + 2 + 1, (far, out.read_text())


def test_nothing_recorded_is_a_clear_error(tmp_path, capsys):
    from inmoov_dsl.cli import gestc

    code = gestc.main(["record", "--port", "sim://?boot=0", "-o", str(tmp_path / "x.gest"),
                       "--seconds", "0.3"])
    assert code == 1
    assert capsys.readouterr().err.endswith(
        "gestc: error: no servo command for profile 'rhand' came from sim://?boot=0\n"
        "  hint: is the glove on this port, sending to these servo IDs?\n")
    assert not (tmp_path / "x.gest").exists()
