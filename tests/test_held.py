"""A servo a gesture names is held at its target when the gesture ends, on every kind of
board, even when the target is where the plan believed it was (issue 42: a PCA9685 as
it powers up, every output off, left the fingers peace names at 0 limp); a board found
limp says so at connect; the servos a gesture does not name stay as they were."""

from dataclasses import replace
from pathlib import Path

import pytest

from inmoov_dsl import clock, load_profile
from inmoov_dsl.boards import controller
from inmoov_dsl.boards.pca9685 import chip as regs
from inmoov_dsl.boards.pca9685 import pulse_ticks
from inmoov_dsl.cli import gestplay
from inmoov_dsl.compiling.compiler import compile_program
from inmoov_dsl.language.library import scan_library
from inmoov_dsl.language.load import load
from inmoov_dsl.wire.link import open_board

ROOT = Path(__file__).resolve().parent.parent
LIBRARY = scan_library([ROOT / "gestures"])
PEACE = {"thumb": 180, "ring": 180, "pinky": 180, "index": 0, "middle": 0}
FIVE = dict.fromkeys(("thumb", "index", "middle", "ring", "pinky"), 0)
KINDS = ["rhand", "rhand-maestro", "rhand-pca9685", "rhand-mrlcomm"]


def driven(core, c, j: int) -> int | None:
    """What servo ``j`` of the twin ``core`` is driven at, in its kind's unit (a rig's
    value, quarter-us, ticks, us), or None: no pulses."""
    s = c.servos[j]
    if c.kind == "rig":
        return None if core.relaxed else core.values[j]
    if c.kind == "maestro":
        return core.targets[s.pin] or None
    if c.kind == "pca9685":
        leds = core.chip.registers[regs.led(s.pin):regs.led(s.pin) + 4]
        return pulse_ticks(leds) if core.chip.pulse(s.pin) else None
    servo = core.devices.get(c.devices[j])
    return servo.us if servo is not None and servo.pulsing else None


def target(c, name: str, value: int) -> int:
    """``name`` at ``value`` in ``c``'s unit: what its kind writes for it."""
    sid = next(s.id for s in c.servos if s.name == name)
    return dict(c.moves(c.set_values({sid: value})))[sid]


def play(profile: str, url: str, *argv: str) -> None:
    assert gestplay.main([*argv, "--profile", profile, "--port", url]) == 0


def twin(profile: str, url: str):
    """The virtual board behind ``url`` once it has read all that was sent, and its kind."""
    p = load_profile(profile)
    port = open_board(url, p)
    port.board.advance(max(clock.now(), port.board.sending_until()))  # all has arrived
    port.close()
    return port.board.core, controller(p, p.boards[0])


def names_driven(core, c) -> dict[str, int | None]:
    return {s.name: driven(core, c, j) for j, s in enumerate(c.servos)}


@pytest.mark.parametrize("profile", KINDS)
def test_peace_leaves_every_servo_it_names_driven_at_its_target(profile):
    url = f"sim://{profile}?fresh&boot=0"
    play(profile, url, "peace")
    core, c = twin(profile, url)
    got = names_driven(core, c)
    assert {n: got[n] for n in PEACE} == {n: target(c, n, v) for n, v in PEACE.items()}


@pytest.mark.parametrize(("profile", "gesture", "named"), [
    ("rhand", "peace", PEACE),  # the thumb's write ends the RELAX for every servo
    ("rhand-maestro", "peace", PEACE),  # a Maestro's channels off (as one may start)
    ("rhand-pca9685", "five", FIVE),  # nothing moves
    ("rhand-mrlcomm", "peace", PEACE),  # its pins attached again at connect
])
def test_a_relaxed_board_drives_the_servos_a_gesture_names(profile, gesture, named):
    url = f"sim://{profile}?fresh&boot=0"
    play(profile, url, "relax")
    play(profile, url, gesture)
    core, c = twin(profile, url)
    got = names_driven(core, c)
    assert {n: got[n] for n in named} == {n: target(c, n, v) for n, v in named.items()}
    # a rig's one write drives every servo, as its firmware does, and a connect to
    # MrlComm attaches every pin again: the others leave a servo not named limp
    if c.kind not in ("rig", "mrlcomm"):
        assert got["wrist"] is None


def test_a_pca9685_found_with_its_outputs_off_says_which_servos_are_limp(capsys):
    url = "sim://rhand-pca9685?fresh"
    play("rhand-pca9685", url, "peace")
    said = [line for line in capsys.readouterr().err.splitlines() if "warning" in line]
    assert said == ["gestplay: warning: the PCA9685 of board 181 has its outputs off: "
                    "wrist, thumb, index, middle, ring, pinky limp until a gesture names "
                    "them; the plan takes each to be at its rest (wrist 0, thumb 0, index 0, "
                    "middle 0, ring 0, pinky 0), where its first move starts"]
    play("rhand-pca9685", url, "peace")  # the wrist, not named, is still limp
    said = [line for line in capsys.readouterr().err.splitlines() if "warning" in line]
    assert said == ["gestplay: warning: the PCA9685 of board 181 has its outputs off: "
                    "wrist limp until a gesture names it; the plan takes each to be at its "
                    "rest (wrist 0), where its first move starts"]
    core, c = twin("rhand-pca9685", url)
    assert driven(core, c, 0) is None
    play("rhand-pca9685", url, "reset")  # 'hand 0': the wrist too
    capsys.readouterr()
    play("rhand-pca9685", url, "five")
    assert "warning" not in capsys.readouterr().err


def compiled(gesture: str, profile: str):
    path = LIBRARY[gesture].path
    return compile_program(load(str(path)), gesture, profile)


def writes(c, times, data) -> set[tuple[int, int, int]]:
    """(frame, servo ID, width in the kind's unit) of each servo write of a stream."""
    return {(int(times[b - 1] // 0.020), sid, unit) for a, b in c.commands(data)
            for sid, unit in c.moves(data[a:b])}


def test_a_rig_stream_is_the_same_when_the_servos_named_do_not_move():
    """peace names index and middle at the rest they start from; the thumb moves, and
    on our firmware that one write drives every servo: nothing more is sent."""
    got, plan = compiled("peace", "rhand")
    c = controller(plan.profile, plan.profile.boards[0])
    assert got.streams[0].data == c.encode(replace(plan, named=frozenset()))[1]
    ids = {s.id: s.name for s in plan.profile.servos}
    assert {ids[sid] for sid in got.streams[0].servo_ids} == {"thumb", "ring", "pinky"}


@pytest.mark.parametrize("profile", KINDS[1:])
def test_a_servo_named_and_never_moved_is_written_once_in_the_first_frame(profile):
    """peace from rest on a controller: index and middle get their width once, in the
    first frame, beside the moves, which are as they would be without them."""
    got, plan = compiled("peace", profile)
    c = controller(plan.profile, plan.profile.boards[0])
    held = writes(c, got.streams[0].times, got.streams[0].data)
    bare = writes(c, *c.encode(replace(plan, named=frozenset())))
    ids = {s.name: s.id for s in c.servos}
    assert held - bare == {(0, ids[n], target(c, n, 0)) for n in ("index", "middle")}
    assert bare <= held


def test_mrlcomm_s_moves_a_frame_go_first_to_the_servos_that_move():
    """Six moves a frame at most: a servo to hold takes a frame's room that no moving
    servo needs, and every move goes as it would without it."""
    text = "g: r_wrist 90, r_thumb 90, r_index 90, r_middle 90, r_ring 90, r_pinky 90, " \
        "r_bicep 90, r_omoplate 0 over 0.5s\n"  # seven move; the omoplate rests at 0
    got, plan = compile_program(load("g.gest", text), "g", "inmoov-mrlcomm")
    c = controller(plan.profile, plan.profile.boards[0])
    held = writes(c, got.streams[0].times, got.streams[0].data)
    bare = writes(c, *c.encode(replace(plan, named=frozenset())))
    omoplate = next(s.id for s in c.servos if s.name == "r_omoplate")
    assert bare <= held
    assert [(sid, unit) for _, sid, unit in held - bare] == [
        (omoplate, target(c, "r_omoplate", 0))]
    frames = [f for f, _, _ in held]
    assert max(frames.count(f) for f in frames) == 6  # as many as MrlComm keeps up with
