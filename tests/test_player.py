"""The player: on time against one clock, from the pose the board reports, to sim://,
to a real pseudo-terminal, and safe when things go wrong."""

import itertools
import os
import select
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from boardmodel import final_values, read_stream
from conftest import VirtualClock
from stopping import PROMPT, after_signal, received, stop_mid_gesture, wait_for

from inmoov_dsl import clock, compile_file, load_library
from inmoov_dsl.cli import gestplay, hand
from inmoov_dsl.compiling.compiler import compile_program
from inmoov_dsl.language.load import load
from inmoov_dsl.profiles.profile import load_profile
from inmoov_dsl.protocol import pairs, timed_pairs
from inmoov_dsl.wire import link as wire_link
from inmoov_dsl.wire.pace import HORIZON, WAKE, padded
from inmoov_dsl.wire.player import Link, cancel_all, play
from inmoov_dsl.wire.ports import open_port
from inmoov_dsl.wire.ready import wait_ready

ROOT = Path(__file__).resolve().parent.parent
TWO = ROOT / "tests" / "data" / "two.toml"
POSIX = pytest.mark.skipif(not hasattr(os, "openpty"), reason="pseudo-terminals are POSIX")


FakeClock = VirtualClock


class FakePort:
    """A port at 9600 baud: each byte leaves when the wire is free (the write returns at
    once, as the OS buffers it); ``writes`` counts the player's wake-ups."""

    def __init__(self, clock, baud=9600):
        self.clock, self.sent, self.tau, self.free, self.writes = clock, [], 10 / baud, 0.0, 0

    def write(self, data):
        self.writes += 1
        for b in data:
            t = max(self.clock.t, self.free)
            self.sent.append((t, b))
            self.free = t + self.tau
        return len(data)

    def read(self, size=1):
        return b""


@pytest.mark.parametrize("into", [0.5, 3.0, 7.77])
def test_ctrl_c_sends_at_most_the_horizon_then_cancel(into):
    """On the virtual clock, Ctrl-C ``into`` s into demo: what the player had written
    ahead (at most the horizon) still goes, then the CANCEL, within the horizon and two
    byte-times of the signal (a stop drops what a port that can discard holds: then
    sooner). The same at a board behind a pty: test_wireclock.py; the figure on a real
    machine: benchmarks/stop.py."""
    compiled = compile_file(load_library()["demo"])
    clock = FakeClock()
    port = FakePort(clock)
    signalled = []

    def sleep(seconds):
        clock.sleep(seconds)
        if not signalled and clock.t >= 100.0 + into:
            signalled.append(clock.t)
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        play(compiled, [Link(181, port)], now=clock.now, sleep=sleep)
    cancel_all([Link(181, port)])
    tau = compiled.stream().byte_time
    after = [(t, b) for t, b in port.sent if t + tau > signalled[0]]  # still on the wire
    assert after[-1][1] == 255 and len(after) <= round(HORIZON / tau) + 2
    assert after[-1][0] + tau - signalled[0] <= HORIZON + 2 * tau
    events = read_stream(*zip(*port.sent, strict=True), 9600)
    assert 0 < len(events) < len(pairs(compiled.stream().data))  # stopped mid-gesture


@pytest.mark.parametrize("speed", [1.0, 0.5])
def test_the_stream_goes_as_one_run_the_wire_times(speed):
    compiled = compile_file(load_library()["count"])
    clock = FakeClock()
    port = FakePort(clock)
    late = play(compiled, [Link(181, port)], speed, now=clock.now, sleep=clock.sleep)
    stream = compiled.stream()
    tau = stream.byte_time
    sent = bytes(b for _, b in port.sent)
    # the stream's bytes at their places, CANCEL between them, from first to last
    assert sent == padded(stream.times, stream.data, tau, speed)
    assert len(sent) == pytest.approx(stream.times[-1] / speed / tau + 1, abs=1)
    start = port.sent[0][0]
    times = np.array([t for t, _ in port.sent]) - start
    assert np.allclose(np.diff(times), tau)  # the wire never ran dry
    # the board reads the pairs of the stream as sent bare, each at its planned time
    # (exactly at full speed; slowed down, a pair's ID goes at the grid point nearest
    # its time and its value right after it, not a stretched byte-time later)
    padded_pairs = read_stream(times, sent, 9600)
    planned = read_stream(stream.times / speed, stream.data, 9600)
    assert [p[1:] for p in padded_pairs] == [p[1:] for p in planned]
    error = max(abs(a[0] - b[0]) for a, b in zip(padded_pairs, planned, strict=True))
    assert error <= (1e-9 if speed == 1 else 1.5 * tau + 1e-9)
    assert late == 0.0
    # the player returns after the gesture's full length, final hold included, having
    # topped the port up every few milliseconds, not once a byte
    assert clock.t - start == pytest.approx(compiled.duration / speed, abs=1e-3)
    assert port.writes <= compiled.duration / speed / WAKE * 1.1 + 2
    assert port.writes < len(sent) / 2


class StallingClock(FakeClock):
    """A machine so busy that now and then the player sleeps 40 ms past its time."""

    def __init__(self):
        super().__init__()
        self.naps = 0

    def sleep(self, seconds):
        self.naps += 1
        super().sleep(seconds + (0.040 if self.naps % 97 == 0 else 0.0))


def test_a_stalled_player_leaves_out_filler_and_never_splits_a_pair():
    compiled = compile_file(load_library()["count"])
    clock = StallingClock()
    port = FakePort(clock)
    late = play(compiled, [Link(181, port)], now=clock.now, sleep=clock.sleep)
    stream = compiled.stream()
    sent = bytes(b for _, b in port.sent)
    times = [t - port.sent[0][0] for t, _ in port.sent]
    padded_pairs = read_stream(times, sent, 9600)
    planned = read_stream(stream.times, stream.data, 9600)
    assert [p[1:] for p in padded_pairs] == [p[1:] for p in planned]  # all, in order
    errors = [a[0] - b[0] for a, b in zip(padded_pairs, planned, strict=True)]
    assert min(errors) >= -1e-9  # never early
    assert 0 < late <= 0.040 + 1e-6 and max(errors) <= late + 1e-9  # late by a stall
    assert len(sent) < len(padded(stream.times, stream.data, stream.byte_time))


def test_two_boards_run_on_one_clock():
    compiled, _ = compile_program(load("t.gest", "g: r_index 90, l_index 45 over 0.5s"), "g",
                                  str(TWO))
    clock = FakeClock()
    ports = {181: FakePort(clock), 183: FakePort(clock)}
    play(compiled, [Link(board, port) for board, port in ports.items()], now=clock.now,
         sleep=clock.sleep)
    for stream in compiled.streams:  # each board its own run, both from the same moment
        sent = ports[stream.board].sent
        assert bytes(b for _, b in sent) == padded(stream.times, stream.data,
                                                   stream.byte_time)
    assert ports[181].sent[0][0] == ports[183].sent[0][0]


class NoisyBoard:
    """A board that talks too much: WAITs, stray bytes, a half START and another board's
    reply before its own DUMP reply, the reply cut over several reads, and rubbish all
    through the gesture."""

    def __init__(self):
        self.sent, self.chunks = bytearray(), [bytes([254, 7, 252, 200, 254, 252, 9, 0, 251])]

    def write(self, data):
        self.sent += data
        if 253 in data:
            reply = bytes([252, 181, 6, 0, 0, 1, 0, 2, 90, 3, 0, 4, 0, 5, 30, 251])
            self.chunks += [bytes([254, 252]), reply[:5], reply[5:11], reply[11:], b"\xfe"]
        return len(data)

    def read(self, size=1):
        return self.chunks.pop(0) if self.chunks else bytes([254, 13, 252, 0, 251])


def test_a_noisy_board_is_understood_and_never_crashes_the_player():
    port = NoisyBoard()
    link = Link(181, port, "noisy")
    pose = hand.board_pose([link], load_profile("rhand"))
    assert pose == {"wrist": 0, "thumb": 0, "index": 90, "middle": 0, "ring": 0, "pinky": 30}
    program = load(str(load_library()["peace"]))
    compiled, _ = compile_program(program, "peace", "rhand", pose)
    port.sent.clear()
    clock = FakeClock()
    play(compiled, [link], now=clock.now, sleep=clock.sleep)
    stream = compiled.stream()
    assert bytes(port.sent) == padded(stream.times, stream.data, stream.byte_time)


def sim_links(url="sim://?boot=0.05", board=181):
    port = open_port(url, 9600)
    return Link(board, port, url)


def test_play_to_the_virtual_board_in_process(virtual_clock):
    link = sim_links()
    board = link.port.board
    hand.board_pose([link], load_profile("rhand"))
    compiled = compile_file(load_library()["peace"])
    start = clock.now()
    play(compiled, [link])
    link.port.close()
    board.advance(clock.now())
    assert board.positions() == dict(enumerate(compiled.final))
    # on the virtual clock each write happens when the plan says its pair arrives (a
    # byte-time after its value left), on the link's byte grid: at most a byte-time
    # early; how late a real computer is, is benchmarks/timing.py's figure
    stream = compiled.stream()
    tau = stream.byte_time
    arrivals = [t - start for t, _ in board.log]
    planned = [t + tau for t, _, _ in timed_pairs(stream.times, stream.data)]
    late = sorted(a - p for a, p in zip(arrivals, planned, strict=True))
    assert -tau - 1e-6 <= late[0] and late[-1] <= 1e-6


def test_the_gesture_is_planned_from_the_pose_the_board_reports():
    link = sim_links()
    wait_ready(link.port)
    link.port.write(bytes([255, 2, 90, 5, 30]))  # someone left the index and pinky bent
    time.sleep(0.02)
    pose = hand.board_pose([link], load_profile("rhand"))
    assert pose == {"wrist": 0, "thumb": 0, "index": 90, "middle": 0, "ring": 0, "pinky": 30}
    program = load(str(load_library()["peace"]))
    compiled, _ = compile_program(program, "peace", "rhand", pose)
    assert compiled.start == (0, 0, 90, 0, 0, 30)
    play(compiled, [link])
    link.port.board.advance(clock.now())
    assert link.port.board.positions() == dict(enumerate(compiled.final))
    link.port.close()


def test_two_boards_in_lockstep(virtual_clock):
    compiled, _ = compile_program(load("t.gest", "g: r_index 90, l_index 45 over 0.5s"), "g",
                                  str(TWO))
    links = [sim_links(f"sim://{TWO}?board=181&boot=0", 181),
             sim_links(f"sim://{TWO}?board=183&boot=0", 183)]
    play(compiled, links)
    right, left = (link.port.board for link in links)
    for board in (right, left):
        board.advance(clock.now())
    assert right.positions() == {1: 0, 2: 90}
    assert left.positions() == {11: 0, 12: 45}
    # both boards finished their last move within a few milliseconds of each other
    assert abs(right.log[-1][0] - left.log[-1][0]) < 0.01


def run(capsys, *argv):
    code = gestplay.main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_the_cli_plays_to_sim(capsys):
    code, out, _ = run(capsys, "peace", "--port", "sim://")
    assert code == 0
    assert out.startswith("played peace: 0.70 s, 201 bytes, worst lateness ")


def test_a_loop_reports_the_whole_run(virtual_clock, capsys):
    one = compile_file(load_library()["wiggle"])
    again = compile_file(load_library()["wiggle"], start=dict(zip(one.servos, one.final,
                                                                        strict=True)))
    code, out, _ = run(capsys, "wiggle", "--port", "sim://", "--loop", "2")
    assert code == 0
    assert out.startswith(f"played wiggle twice: {one.duration + again.duration:.2f} s, "
                          f"{len(one.stream().data) + len(again.stream().data):,} bytes, ")


def test_a_gesture_is_expanded_once_for_its_boards_and_every_pass(capsys, monkeypatch):
    """gestplay finds the boards a gesture drives from its actions, and plans every
    pass from the same actions: the gesture is expanded once."""
    from inmoov_dsl.compiling.resolve import Resolver

    expanded = []
    gesture = Resolver.gesture
    monkeypatch.setattr(Resolver, "gesture",
                        lambda self, *a: expanded.append(a) or gesture(self, *a))
    code, out, err = run(capsys, "peace", "--port", "sim://?boot=0&fresh", "--loop", "2")
    assert code == 0, err
    assert out.startswith("played peace twice: ")  # two plans: from rest, from peace
    assert expanded == [("peace", None)]


def test_a_loop_stopped_in_its_second_pass_was_played_once(virtual_clock, capsys, monkeypatch):
    from inmoov_dsl.cli.gestplay import play as playing

    passes = []

    def one_pass(*args, **kwargs):
        if passes:
            raise KeyboardInterrupt
        passes.append(1)
        return play(*args, **kwargs)

    monkeypatch.setattr(playing, "play", one_pass)
    code, out, _ = run(capsys, "wiggle", "--port", "sim://", "--loop")
    assert code == 130
    assert out.startswith("played wiggle once, then stopped in pass 2: ")


def test_dry_run_prints_the_schedule(capsys):
    code, out, _ = run(capsys, "count", "--dry-run", "--speed", "0.5")
    assert code == 0
    times = [float(line.split()[0]) for line in out.splitlines()]
    assert times[-1] == pytest.approx(2 * compile_file(load_library()["count"]).stream()
                                      .times[-1], abs=1e-5)


class SilentPort:
    """A port with nothing behind it: it keeps what is written and never answers."""

    def __init__(self):
        self.sent = bytearray()

    def write(self, data):
        self.sent += data

    def read(self, size=1):
        return b""

    def close(self):
        pass


@pytest.mark.parametrize("tool", [[], ["repl"], ["teach"], ["relax"]])
def test_no_board_is_an_error_before_any_gesture_byte(capsys, monkeypatch, tool,
                                                      virtual_clock):
    port = SilentPort()
    monkeypatch.setattr(wire_link, "open_port", lambda name, baud, timeout=0: port)
    code, _, err = run(capsys, *(tool or ["peace"]), "--port", "COM7")
    assert code == 1
    assert err.startswith("gestplay: error: no board answered on COM7 (board 181, 9600 baud)")
    assert "gestc upload servo_rhand --port COM7" in err and "--blind" in err
    assert set(port.sent) <= {255, 253}  # CANCEL probes and a DUMP: no servo ID, no value


def test_one_port_is_enough_for_a_gesture_on_one_board_of_many(virtual_clock, capsys, monkeypatch):
    opened = []

    def open_port(name, baud, timeout=0):
        opened.append(name)
        return SilentPort()

    monkeypatch.setattr(wire_link, "open_port", open_port)
    code, out, err = run(capsys, "peace", "--profile", "inmoov", "--port", "COM7", "--blind")
    assert code == 0, err
    assert opened == ["COM7"]  # the right hand's board (181) only, of the robot's six
    assert "board 181 on COM7 did not answer (--blind)" in err
    assert out.startswith("played peace: 0.70 s")


def test_blind_plays_on_a_link_that_cannot_answer(capsys, monkeypatch, virtual_clock):
    """On the virtual clock: the bytes are the stream's run exactly, however busy the
    machine (on the real one a stall longer than the horizon leaves filler out)."""
    port = SilentPort()
    monkeypatch.setattr(wire_link, "open_port", lambda name, baud, timeout=0: port)
    code, out, err = run(capsys, "peace", "--port", "COM7", "--blind")
    assert code == 0
    assert ("gestplay: warning: board 181 on COM7 did not answer (--blind): starting from "
            "the profile's rest pose") in err
    assert out.startswith("played peace: 0.70 s, 201 bytes")
    stream = compile_file(load_library()["peace"]).stream()
    assert port.sent.endswith(padded(stream.times, stream.data, stream.byte_time))


@pytest.mark.parametrize(("argv", "message"), [
    (["peace", "--port", "/dev/ttyNOPE0"], "gestplay: error: port /dev/ttyNOPE0 not found; "
                                           "ports on this machine: "),
    (["peace"], "gestplay: error: no port given"),
    (["pece", "--port", "sim://"], "gestplay: error: no file or library gesture 'pece'"),
    (["both.gest", "--profile", str(TWO), "--port", "loop://"],
     "gestplay: error: profile 'two' has 2 boards: give a port for each"),
    (["both.gest", "--profile", str(TWO), "--port", "181=sim://"],
     "gestplay: error: no port for board 183"),
    (["both.gest", "--profile", "inmoov", "--port", "right=loop://"],  # a board's name
     "gestplay: error: no port for board 183"),
    (["both.gest", "--profile", "inmoov-six", "--port", "loop://"],
     "gestplay: error: this needs 2 boards: give a port for each\n"
     "  hint: --port 181=PORT --port 183=PORT"),
    (["once.gest", "--profile", "inmoov-six", "--port", "loop://"],  # the boards of 'a & b'
     "gestplay: error: this needs 3 boards: give a port for each\n"
     "  hint: --port 181=PORT --port 183=PORT --port 184=PORT"),
    (["peace", "--port", "sim://nosuchprofile"],
     "gestplay: error: cannot open port sim://nosuchprofile: unknown profile 'nosuchprofile'"),
    (["dump", "--port", "loop://"], "gestplay: error: no DUMP reply from loop://"),
])
def test_bad_ports_and_options_are_one_clear_message(virtual_clock, capsys, tmp_path,
                                                     monkeypatch, argv, message):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "both.gest").write_text("g: r_index 90, l_index 90\n")
    (tmp_path / "once.gest").write_text("g:\n    r_index 90\n    l_index 90 & neck 100\n")
    code, _, err = run(capsys, *argv)
    assert code == 1
    assert err.startswith(message)
    assert "Traceback" not in err


def test_bench_tools(capsys):
    code, out, _ = run(capsys, "dump", "--port", "sim://")
    assert code == 0
    assert out.splitlines()[0] == "board 181 (right hand): 6 servos"
    assert out.splitlines()[3] == "  index      id   2  value   0"
    code, out, _ = run(capsys, "send", "--port", "sim://", "cancel", "2", "90", "dump")
    assert code == 0
    assert "START 181 6 0 0 1 0 2 90 3 0 4 0 5 0 END" in out
    code, _, err = run(capsys, "send", "--port", "sim://", "300")
    assert code == 1 and err.startswith("gestplay: error: '300' is not a byte")


def test_ports_marks_the_likely_arduinos(capsys, monkeypatch):
    from serial.tools import list_ports, list_ports_common

    def port(device, description, vid=None, pid=None):
        info = list_ports_common.ListPortInfo(device, skip_link_detection=True)
        info.description, info.vid, info.pid = description, vid, pid
        return info

    monkeypatch.setattr(list_ports, "comports", lambda: [
        port("/dev/ttyS0", "n/a"), port("/dev/ttyUSB0", "USB2.0-Serial", 0x1A86, 0x7523),
        port("/dev/ttyACM0", "Arduino Uno", 0x2341, 0x0043)])
    code, out, _ = run(capsys, "ports", "--no-ask")
    assert code == 0
    assert out.splitlines() == [
        "/dev/ttyACM0\tArduino Uno\tUSB 2341:0043\tlikely an Arduino",
        "/dev/ttyUSB0\tUSB2.0-Serial\tUSB 1A86:7523\tlikely a CH340: most Nano and Uno clones",
        "/dev/ttyS0\tn/a\t-"]
    monkeypatch.setattr(list_ports, "comports", lambda: [port("/dev/ttyS0", "n/a")])
    code, _, err = run(capsys, "ports")
    assert code == 0 and "none of these looks like an Arduino or a Maestro" in err


@pytest.mark.skipif(sys.platform == "win32", reason="COM3 is a port name on Windows")
def test_a_windows_port_name_elsewhere_says_what_names_are_used_here(capsys):
    code, _, err = run(capsys, "peace", "--port", "COM3")
    assert code == 1 and "COM ports are Windows names; here an Arduino is /dev/" in err


# -- real processes over a real pseudo-terminal ------------------------------------------
def gestplay_proc(*argv):
    return subprocess.Popen([sys.executable, "-m", "inmoov_dsl.cli.gestplay", *argv],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


@POSIX
def test_play_through_a_pty_with_pyserial(gestsim):
    proc, path, log = gestsim
    player = gestplay_proc("count", "--port", path)
    _, err = player.communicate(timeout=60)
    assert player.returncode == 0, err
    # the board logs each byte as it reads it: on a busy machine, after the player ended
    wait_for(lambda: final_values(read_stream(*received(log), 9600), {}) ==
             {1: 0, 3: 0, 4: 0, 5: 0}, "count's last pairs at the board")  # count ends open
    times, data = received(log)
    dump = data.index(253)  # CANCELs (until the board answers), then DUMP before the stream
    assert dump >= 1 and set(data[:dump]) == {255}


@POSIX
def test_a_pulled_cable_is_one_line_and_a_quick_exit(gestsim):
    proc, path, log = gestsim
    player = gestplay_proc("count", "--port", path)
    wait_for(lambda: " 1\n" in log.read_text(), "the gesture under way", 60)  # 5 s long
    proc.kill()
    pulled = time.monotonic()
    _, err = player.communicate(timeout=10)
    # noticed within a second (the player drains its links that often); on a busy
    # machine, a bound it meets
    assert time.monotonic() - pulled < PROMPT + 1.0
    assert player.returncode == 1
    assert err.startswith(f"gestplay: error: lost the link (board 181 on {path}): ")
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err


@POSIX
@pytest.mark.parametrize(("signum", "status", "said"), [
    (signal.SIGINT, 130, "interrupted"),
    (getattr(signal, "SIGTERM", None), 143, "stopped by SIGTERM"),
    (getattr(signal, "SIGHUP", None), 129, "stopped by SIGHUP"),
])
def test_ctrl_c_or_a_stop_signal_sends_cancel(gestsim, signum, status, said):
    """In the middle of demo: the player drops what the port holds and sends CANCEL; a
    pty's other end keeps what it has read, as a USB adapter's chip does, so the board
    gets at most that and the horizon the player wrote ahead, then the CANCEL."""
    _, _, log = gestsim
    ended, signalled, times, data = stop_mid_gesture(log, ["demo", "--port", gestsim[1]],
                                                     signum, 1.5)
    assert ended.returncode == status
    assert f"gestplay: {said}: CANCEL sent, the hand holds its pose" in ended.stderr
    assert "Traceback" not in ended.stderr
    after_signal(times, data, signalled)
    stream = compile_file(load_library()["demo"]).stream()
    assert len(read_stream(times, data, 9600)) < len(pairs(stream.data))  # mid-move


@POSIX
def test_a_loop_without_a_count_plays_until_ctrl_c_and_counts_the_passes(gestsim, tmp_path):
    _, path, log = gestsim
    tap = tmp_path / "tap.gest"
    tap.write_text("tap:\n    index 90 over 0.4s\n    index 0 over 0.4s\n")
    player = gestplay_proc(str(tap), "--port", path, "--loop")
    one = len(pairs(compile_file(tap).stream().data))
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline and len(read_stream(*received(log), 9600)) < 2.5 * one:
        time.sleep(0.05)  # two passes sent, the third under way
    player.send_signal(signal.SIGINT)
    out, err = player.communicate(timeout=10)
    assert player.returncode == 130
    said = next(line for line in out.splitlines() if line.startswith("played"))
    passes = int(said.split("then stopped in pass ")[1].split(":")[0]) - 1
    counted = {1: "once", 2: "twice"}.get(passes, f"{passes} times")
    assert said.startswith(f"played tap {counted}, then stopped in pass {passes + 1}: ")
    assert "Traceback" not in err
    assert passes >= 2
    assert "CANCEL sent, the hand holds its pose" in err
    index = [v for _, k, v in read_stream(*received(log), 9600) if k == 2]
    curls = sum(1 for a, b in itertools.pairwise(index) if a < 90 <= b)
    assert curls >= passes  # every pass curled the finger from where the last one left it
    assert max(abs(b - a) for a, b in itertools.pairwise(index)) < 30  # and never jumped


@POSIX
def test_ctrl_c_while_starting_is_one_line(tmp_path):
    """A Ctrl-C while the tool still imports its modules: no traceback."""
    script = tmp_path / "slow_start.py"
    script.write_text("import os, signal, sys\n"
                      "import inmoov_dsl.cli as cli\n"
                      "real = cli.importlib.import_module\n"
                      "def slow(name, package=None):\n"
                      "    os.kill(os.getpid(), signal.SIGINT)\n"
                      "    return real(name, package)\n"
                      "cli.importlib.import_module = slow\n"
                      "sys.exit(cli.run_gestplay())\n")
    done = subprocess.run([sys.executable, str(script), "peace", "--dry-run"],
                          capture_output=True, text=True, timeout=60)
    assert done.returncode == 130
    assert done.stderr == "gestplay: interrupted while starting\n"


@POSIX
def test_gestsim_shows_the_servos_live_on_a_terminal():
    master, slave = os.openpty()
    proc = subprocess.Popen([sys.executable, "-m", "inmoov_dsl.cli.gestsim", "--boot", "0.1"],
                            stdout=subprocess.PIPE, stderr=slave, text=True)
    os.close(slave)
    try:
        path = proc.stdout.readline().strip()
        player = gestplay_proc("peace", "--port", path)
        assert player.wait(timeout=30) == 0
        time.sleep(0.2)  # a redraw or two
        screen, deadline = b"", time.monotonic() + 5
        while select.select([master], [], [], 0.1)[0] and time.monotonic() < deadline:
            screen += os.read(master, 65536)
    finally:
        proc.kill()
        proc.wait()
        os.close(master)
    last = screen.decode().rsplit("\x1b[6F", 1)[-1]  # the last redraw of the 6 lines
    rows = [line.replace("\x1b[2K", "").split() for line in last.splitlines()[:6]]
    assert [r[:2] for r in rows] == [["wrist", "0"], ["thumb", "180"], ["index", "0"],
                                     ["middle", "0"], ["ring", "180"], ["pinky", "180"]]
    assert rows[1][2] == "#" * 30  # a bar as long as the value


def test_a_board_s_port_is_given_by_its_id_or_its_name_one_option_or_several():
    from inmoov_dsl.wire.link import board_ports

    inmoov = load_profile("inmoov")
    for specs in (["left=COM3,right=COM4"], ["right=COM4", "left=COM3"],
                  ["181=COM4", "left=COM3"]):
        assert board_ports(specs, inmoov) == {181: "COM4", 183: "COM3"}
    assert board_ports(["sim://a,b"], load_profile("rhand")) == {181: "sim://a,b"}
