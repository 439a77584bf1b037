"""The hand as a ROS node: the conversions and the node's core without ROS, then the
node itself under ROS 1, as a user runs it: a real roscore on a free port, the node
started with ROS's Python (a venv made with --system-site-packages, inmoov-dsl
installed in it), requests published and /joint_states read by a rospy client
(tests/ros_client.py).

The ROS tests skip where ROS 1 is missing, except under CI=true, where that fails."""

from __future__ import annotations

import contextlib
import fcntl
import hashlib
import json
import math
import os
import pty
import shutil
import signal
import socket
import subprocess
import sys
import threading
import time
import tty
import xmlrpc.client
from argparse import Namespace
from pathlib import Path

import pytest
from toolchain import need

from inmoov_dsl.errors import GestError
from inmoov_dsl.model import joints
from inmoov_dsl.profiles.profile import load_profile
from inmoov_dsl.resources import STATE_ENV
from inmoov_dsl.ros import core, trajectory

ROOT = Path(__file__).resolve().parent.parent
CLIENT = Path(__file__).resolve().parent / "ros_client.py"
RHAND = load_profile("rhand")
SERVO = joints.servo_of(RHAND)
FINGERS = ["right_palm_to_thumb", "right_palm_to_index", "right_palm_to_medius",
           "right_palm_to_ring", "right_palm_to_pinky"]
ROS_PYTHON = "/usr/bin/python3"
ROS_PACKAGES = ("python3-rospy python3-roslaunch python3-rostopic ros-robot-state-publisher "
                "python3-sensor-msgs python3-std-msgs python3-trajectory-msgs rosbash ros-core")
WAIT = 30  #: s; the longest any step of these tests waits


def curled(joint: str) -> float:
    """The joint's position when its servo is at its top value (a finger curled)."""
    return joints.limits(SERVO[joint])[1]


def step(joint: str) -> float:
    """One command degree of the joint, in radians: how close a position can come."""
    return joints.scale(SERVO[joint])


# -- a trajectory as steps (pure) --------------------------------------------------------
def test_each_point_of_a_trajectory_is_a_move_over_the_time_since_the_one_before():
    steps = trajectory.steps(RHAND, ["right_palm_to_index", "right_palm_to_thumb"],
                             [([0.5, 0.2], 0.5), ([1.0, 0.0], 1.25)])
    first, second = steps.actions
    index, thumb = RHAND.index("index"), RHAND.index("thumb")
    assert [first.over, second.over] == [0.5, 0.75]
    assert dict(first.targets) == {index: round(0.5 / step("right_palm_to_index")),
                                   thumb: round(0.2 / step("right_palm_to_thumb"))}
    assert dict(second.targets)[thumb] == RHAND.servos[thumb].rest
    assert steps.name == "trajectory (2 points, 1.25 s)"


@pytest.mark.parametrize(("joints_", "points", "message", "hint"), [
    (["right_palm_to_indx"], [([0.1], 1.0)], "profile 'rhand' has no joint "
     "'right_palm_to_indx'", "did you mean 'right_palm_to_index'?"),
    (["right_palm_to_index"], [([5.0], 1.0)], "point 1: joint 'right_palm_to_index' at "
     "5.000 rad is outside its range 0.000..1.745 rad", "index 0..180"),
    (["right_palm_to_index"], [([-0.1], 1.0)], "outside its range", "position 0 is its rest"),
    (["right_palm_to_index"], [([0.1], 1.0), ([0.2], 1.0)], "point 2: time_from_start 1 s "
     "is not after point 1's (1 s)", "must increase"),
    (["right_palm_to_index"], [([math.nan], 1.0)], "joint 'right_palm_to_index' at nan",
     "finite"),
    (["right_palm_to_index"], [([0.1], math.inf)], "time_from_start inf s", "0 or more"),
    (["right_palm_to_index"], [([0.1, 0.2], 1.0)], "point 1 has 2 positions for 1 joints",
     "one position per joint"),
    (["right_palm_to_index"] * 2, [([0.1, 0.2], 1.0)], "named twice", "once"),
    ([], [([], 1.0)], "no joint names", "name the joints"),
    (["right_palm_to_index"], [], "no points", "at least one"),
])
def test_a_trajectory_the_hand_cannot_do_is_an_error_saying_where(joints_, points, message,
                                                                   hint):
    with pytest.raises(GestError) as caught:
        trajectory.steps(RHAND, joints_, points)
    d = caught.value.first
    assert message in d.message and hint in d.hint


# -- the node's core, without ROS --------------------------------------------------------
class FakeEdge:
    """An edge that keeps what the node says, and hands the node to the test."""

    def __init__(self):
        self.said: list[str] = []
        self.node: core.Node | None = None
        self.cond = threading.Condition()

    def check(self) -> None:
        pass

    def start(self, node: core.Node) -> None:
        with self.cond:
            self.node = node
            self.cond.notify_all()

    def say(self, kind: str, text: str) -> None:
        with self.cond:
            self.said.append(text)
            self.cond.notify_all()

    def stop(self) -> None:
        pass

    def after(self, request, ends=("done", "error")) -> list[str]:
        """Send a request (a callable on the node); what the node says until it ends."""
        first = len(self.said)
        request(self.node)
        with self.cond:
            assert self.cond.wait_for(lambda: any(s.startswith(ends)
                                                  for s in self.said[first:]), WAIT)
            return self.said[first:]


def test_the_core_plays_requests_reports_errors_and_keeps_serving():
    edge = FakeEdge()
    args = Namespace(port=["sim://?boot=0"], profile="rhand", listen=False, rate=50.0,
                     allow_contact=False, blind=False, lib=[])
    result: list[int] = []
    serving = threading.Thread(target=lambda: result.append(core.serve(args, edge)))
    serving.start()
    try:
        with edge.cond:
            assert edge.cond.wait_for(lambda: edge.node is not None, WAIT)
        assert edge.after(lambda n: n.gesture("fist")) == ["playing fist", "done"]
        at = dict(zip(edge.node.joint_names(), edge.node.joint_positions(), strict=True))
        assert at == {"right_arm_to_wrist": 0.0, **{j: curled(j) for j in FINGERS}}
        said = edge.after(lambda n: n.gesture("fsit"))
        assert said == ["error: unknown servo, group, pose or gesture 'fsit' (did you mean "
                        "'fist'?)"]
        said = edge.after(lambda n: n.trajectory(["right_palm_to_index"], [([0.5], 0.3)]))
        assert said[-1] == "done"
        index = edge.node.joint_positions()[RHAND.index("index")]
        assert abs(index - 0.5) <= step("right_palm_to_index") / 2
    finally:
        if edge.node is not None:
            edge.node.close()
        serving.join(WAIT)
    assert result == [0]


def test_without_rospy_the_node_says_where_to_run_it():
    if subprocess.run([sys.executable, "-c", "import rospy"], capture_output=True).returncode \
            == 0:
        pytest.skip("this Python has rospy")
    done = subprocess.run([sys.executable, "-m", "inmoov_dsl.ros", "--port", "sim://"],
                          capture_output=True, text=True, timeout=WAIT)
    assert done.returncode == 1
    assert done.stderr.startswith("inmoov_dsl.ros: error: rospy not found: run under ROS 1's "
                                  "Python, see docs/ros.md")
    assert "Traceback" not in done.stderr


def test_the_node_tells_its_version_and_usage_with_or_without_rospy(capsys):
    from inmoov_dsl import __version__
    from inmoov_dsl.ros.__main__ import main

    with pytest.raises(SystemExit) as done:
        main(["--version"])
    assert done.value.code == 0
    assert capsys.readouterr().out == f"python -m inmoov_dsl.ros {__version__}\n"
    with pytest.raises(SystemExit) as done:
        main(["--help", "__name:=renamed"])  # roslaunch's arguments are not the node's
    assert done.value.code == 0
    assert capsys.readouterr().out.startswith("usage: python -m inmoov_dsl.ros [-h] --port")


@pytest.mark.skipif(sys.platform == "win32", reason="COM3 is a port name on Windows")
@pytest.mark.parametrize("listen", [False, True])
def test_a_wrong_port_name_gets_the_hint_every_command_gives(listen):
    from inmoov_dsl.wire.ports import not_found

    args = Namespace(port=["COM3"], profile="rhand", listen=listen, rate=50.0, blind=False,
                     allow_contact=False, lib=[])
    with pytest.raises(GestError) as failed:
        core.serve(args, FakeEdge())
    assert failed.value.diagnostics == (not_found("COM3"),)


# -- ROS 1: a real master, the node as a user runs it ------------------------------------
def need_ros() -> None:
    """Skip (fail under CI=true) without ROS 1: its tools, and rospy for its Python."""
    need("roscore", "rostopic", "roslaunch",
         "/usr/lib/robot_state_publisher/robot_state_publisher", ROS_PYTHON,
         packages=ROS_PACKAGES)
    probe = subprocess.run([ROS_PYTHON, "-c", "import rospy, sensor_msgs.msg, std_msgs.msg, "
                            "trajectory_msgs.msg"], capture_output=True, text=True)
    if probe.returncode != 0:
        message = f"{ROS_PYTHON} has no rospy (apt-get install {ROS_PACKAGES})"
        if os.environ.get("CI") == "true":
            pytest.fail(f"CI: {message}")
        pytest.skip(message)


@pytest.fixture(scope="session")
def ros_python(request, tmp_path_factory) -> Path:
    """ROS's Python with inmoov-dsl, as docs/ros.md tells a user to make it: a venv of
    /usr/bin/python3 with --system-site-packages, the repository pip-installed in it
    (editable: made once, kept in pytest's cache while pyproject.toml is unchanged)."""
    need_ros()
    cache = getattr(request.config, "cache", None)
    home = cache.mkdir("ros-venv") if cache else tmp_path_factory.mktemp("ros-venv")
    venv, python = home / "venv", home / "venv" / "bin" / "python"
    key = hashlib.sha256((ROOT / "pyproject.toml").read_bytes() + str(ROOT).encode() +
                         Path(ROS_PYTHON).resolve().name.encode()).hexdigest()
    with open(home / "lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)  # another pytest may be making it
        if not (home / "key").exists() or (home / "key").read_text() != key \
                or not python.exists():
            shutil.rmtree(venv, ignore_errors=True)
            (home / "key").unlink(missing_ok=True)
            for cmd in ([ROS_PYTHON, "-m", "venv", "--system-site-packages", str(venv)],
                        [str(python), "-m", "pip", "install", "-q", "-e", str(ROOT)]):
                made = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
                assert made.returncode == 0, f"{' '.join(cmd)}:\n{made.stderr}"
            (home / "key").write_text(key)
    return python


def outside_this_venv() -> list[str]:
    """PATH without this interpreter's own venv: what pip put there (the reach extra
    brings pip's rospkg, whose rosversion script would shadow ROS's own) is not ROS's."""
    own = Path(sys.prefix, "bin").resolve()
    return [p for p in os.environ["PATH"].split(os.pathsep) if p and Path(p).resolve() != own]


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture(scope="module")
def ros_env(ros_python, tmp_path_factory) -> dict[str, str]:
    """A roscore of our own on a free port: the environment that reaches it."""
    home = tmp_path_factory.mktemp("ros-home")
    port = free_port()
    env = {**os.environ, "ROS_MASTER_URI": f"http://127.0.0.1:{port}", "ROS_IP": "127.0.0.1",
           "ROS_HOME": str(home), "ROS_LOG_DIR": str(home / "log"),
           "PATH": os.pathsep.join([str(ros_python.parent), *outside_this_venv()]),
           "PYTHONUNBUFFERED": "1",
           # virtual boards of its own (made before the tests' own state directories:
           # the user's would carry the poses other programs left)
           STATE_ENV: str(home / "state")}
    env.pop("ROS_PACKAGE_PATH", None)
    master = subprocess.Popen(["roscore", "-p", str(port)], env=env, stdin=subprocess.DEVNULL,
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                              start_new_session=True)
    try:
        deadline = time.monotonic() + WAIT
        while not _master_up(env["ROS_MASTER_URI"]):
            assert master.poll() is None, "roscore ended"
            assert time.monotonic() < deadline, "roscore did not come up"
            time.sleep(0.2)
        yield env
    finally:
        _end(master, signal.SIGINT)


def _master_up(uri: str) -> bool:
    try:
        return xmlrpc.client.ServerProxy(uri).getPid("/test")[0] == 1
    except OSError:
        return False


def _end(proc: subprocess.Popen, how: int) -> int:
    """Stop a process group we started, gently first; its exit status."""
    with contextlib.suppress(ProcessLookupError):
        os.killpg(proc.pid, how)
    try:
        return proc.wait(WAIT)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        return proc.wait(WAIT)


class Proc:
    """A process whose output is read as it comes (bounded waits for a line)."""

    def __init__(self, cmd: list[str], env: dict[str, str]):
        self.proc = subprocess.Popen(cmd, env=env, stdin=subprocess.DEVNULL, text=True,
                                     stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                     start_new_session=True)
        self.out: list[str] = []
        self.cond = threading.Condition()
        for stream in (self.proc.stdout, self.proc.stderr):
            threading.Thread(target=self._read, args=(stream,), daemon=True).start()

    def _read(self, stream) -> None:
        for line in stream:
            with self.cond:
                self.out.append(line)
                self.cond.notify_all()

    def wait_for(self, text: str) -> None:
        with self.cond:
            assert self.cond.wait_for(lambda: any(text in line for line in self.out) or
                                      self.proc.poll() is not None, WAIT)
        assert any(text in line for line in self.out), self.text

    @property
    def text(self) -> str:
        with self.cond:
            return "".join(self.out)

    def stop(self, how: int = signal.SIGTERM) -> int:
        code = _end(self.proc, how)
        time.sleep(0.05)  # the readers take the last lines
        return code


def node(ros_python: Path, env: dict[str, str], *args: str) -> Proc:
    return Proc([str(ros_python), "-m", "inmoov_dsl.ros", *args], env)


def client(ros_python: Path, env: dict[str, str], requests: list[dict]) -> list[dict]:
    """Run tests/ros_client.py with these requests: one answer each."""
    done = subprocess.run([str(ros_python), str(CLIENT)], input=json.dumps(requests),
                          env=env, capture_output=True, text=True, timeout=120)
    answers = [json.loads(line) for line in done.stdout.splitlines() if line.startswith("{")]
    assert len(answers) == len(requests) and not any("timeout" in a for a in answers), \
        f"{answers}\n{done.stderr[-2000:]}"
    return answers


@pytest.fixture(scope="module")
def hand_node(ros_python, ros_env):
    """The node on a virtual board, for the tests that follow."""
    proc = node(ros_python, ros_env, "--port", "sim://?boot=0.05")
    proc.wait_for("ready: rhand on sim://")
    yield proc
    proc.stop()


def test_the_node_publishes_the_hand_after_a_gesture_and_a_trajectory(ros_python, ros_env,
                                                                      hand_node):
    index = ["right_palm_to_index"]
    fist, traj = client(ros_python, ros_env, [
        {"gesture": "fist"},
        {"trajectory": [index, [[[1.0], 0.6], [[1.5], 1.2], [[0.5], 1.8]]], "trace": True}])
    assert fist["status"] == ["playing fist", "done"]
    assert fist["joints"] == pytest.approx({"right_arm_to_wrist": 0.0,
                                            **{j: curled(j) for j in FINGERS}})
    assert traj["status"] == ["playing trajectory (3 points, 1.8 s)", "done"]
    at = traj["joints"]
    assert abs(at["right_palm_to_index"] - 0.5) <= step("right_palm_to_index") / 2
    # the joints it does not name stay where the fist left them
    assert at["right_palm_to_thumb"] == pytest.approx(curled("right_palm_to_thumb"))
    # it went through every point, in order: from the fist down to 1.0, up to 1.5, down
    turns = turning_points([s["right_palm_to_index"] for s in traj["trace"]])
    assert turns == pytest.approx([curled("right_palm_to_index"), 1.0, 1.5, 0.5], abs=0.1)


def turning_points(trace: list[float]) -> list[float]:
    """Where a trace starts, turns back and ends."""
    out = trace[:1]
    for x in trace[1:]:
        if x == out[-1]:
            continue
        if len(out) >= 2 and (out[-1] - out[-2]) * (x - out[-1]) > 0:
            out[-1] = x  # on the same way
        else:
            out.append(x)
    return out


def test_bad_requests_are_errors_on_the_status_and_the_node_serves_on(ros_python, ros_env,
                                                                      hand_node):
    index = ["right_palm_to_index"]
    answers = client(ros_python, ros_env, [
        {"gesture": "fsit"},
        {"trajectory": [["right_palm_to_indx"], [[[0.5], 1.0]]]},
        {"trajectory": [index, [[[5.0], 1.0]]]},
        {"trajectory": [index, [[[0.5], 1.0], [[0.6], 0.5]]]},
        {"gesture": "open"}])
    errors = [a["status"] for a in answers[:4]]
    assert errors == [
        ["error: unknown servo, group, pose or gesture 'fsit' (did you mean 'fist'?)"],
        ["error: profile 'rhand' has no joint 'right_palm_to_indx' (did you mean "
         "'right_palm_to_index'?)"],
        ["error: point 1: joint 'right_palm_to_index' at 5.000 rad is outside its range "
         "0.000..1.745 rad (index 0..180 in command degrees; position 0 is its rest, "
         "index 0)"],
        ["error: point 2: time_from_start 0.5 s is not after point 1's (1 s) (the points' "
         "times must increase)"]]
    assert answers[4]["status"] == ["playing open", "done"]
    assert all(x == pytest.approx(0.0) for x in answers[4]["joints"].values())
    assert "[ERROR]" in hand_node.text and "'fsit'" in hand_node.text  # logged too


def test_sigterm_mid_move_cancels_and_stops_the_node(ros_python, ros_env):
    proc = node(ros_python, ros_env, "--port", "sim://?boot=0.05", "--rate", "20")
    try:
        proc.wait_for("ready:")
        client(ros_python, ros_env, [{"gesture": "fist", "until": "playing"}])
    finally:
        code = proc.stop(signal.SIGTERM)
    assert code == 143, proc.text
    assert "inmoov_dsl.ros: stopped by SIGTERM: CANCEL sent, the hand holds its pose" \
        in proc.text
    assert "Traceback" not in proc.text


def test_listen_reads_a_glove_stream_and_never_writes(ros_python, ros_env):
    master, slave = pty.openpty()
    tty.setraw(slave)  # no echo: what comes back to us was written by the node
    os.set_blocking(master, False)
    proc = node(ros_python, ros_env, "--port", os.ttyname(slave), "--listen")
    try:
        proc.wait_for("listening: rhand on")
        # a glove's stream: joined mid-pair, then CANCEL and pairs (index 90, ring 180)
        os.write(master, bytes([7, 255, 2, 90, 4, 180]))
        answers = client(ros_python, ros_env, [{"joints": True}, {"gesture": "fist"}])
    finally:
        code = proc.stop(signal.SIGTERM)
    with contextlib.suppress(BlockingIOError):
        assert os.read(master, 100) == b""  # nothing was written to the glove
    os.close(master)
    os.close(slave)
    at = answers[0]["joints"]
    assert at["right_palm_to_index"] == pytest.approx(joints.position(SERVO[
        "right_palm_to_index"], 90))
    assert at["right_palm_to_ring"] == pytest.approx(curled("right_palm_to_ring"))
    assert at["right_palm_to_thumb"] == 0.0
    assert answers[1]["status"] == ["error: this node only listens (--listen): it sends "
                                    "nothing to its port"]
    assert code == 143


@pytest.mark.parametrize(("args", "master", "message"), [
    (["--port", "sim://", "--profile", "nohand"], True, "unknown profile 'nohand'"),
    (["--port", "/dev/nonexistent-port"], True, "/dev/nonexistent-port"),
    (["--port", "sim://"], False, "no ROS master at http://127.0.0.1:"),
    (["--port", "sim://", "--rate", "0"], True, "'0' is not a number above 0"),
])
def test_errors_at_start_are_messages_and_a_non_zero_exit(ros_python, ros_env, args,
                                                           master, message):
    env = ros_env if master else {**ros_env,
                                  "ROS_MASTER_URI": f"http://127.0.0.1:{free_port()}"}
    done = subprocess.run([str(ros_python), "-m", "inmoov_dsl.ros", *args,
                           "__name:=renamed"], env=env, capture_output=True, text=True,
                          timeout=WAIT)
    assert done.returncode in (1, 2), done.stderr
    assert message in done.stderr and "Traceback" not in done.stderr


def test_under_ros_the_node_tells_its_version(ros_python):
    from inmoov_dsl import __version__

    done = subprocess.run([str(ros_python), "-m", "inmoov_dsl.ros", "--version",
                           "__name:=renamed"], capture_output=True, text=True, timeout=WAIT)
    assert (done.returncode, done.stdout) == (0, f"python -m inmoov_dsl.ros {__version__}\n")


def test_roslaunch_brings_up_the_node_and_robot_state_publisher(ros_python, ros_env):
    env = {**ros_env, "ROS_PACKAGE_PATH": str(ROOT / "ros")}
    launch = Proc(["roslaunch", "inmoov_dsl", "display.launch", "port:=sim://?boot=0.05",
                   "rviz:=false"], env)
    try:
        launch.wait_for("ready: rhand on sim://")
        model, fist, tf = client(ros_python, env, [
            {"param": "/robot_description"}, {"gesture": "fist"}, {"tf": "right_index_3"}])
    finally:
        launch.stop(signal.SIGINT)
    assert "<robot name=\"rhand\">" in model["param"]
    assert fist["joints"]["right_palm_to_index"] == pytest.approx(curled(
        "right_palm_to_index"))
    assert tf["tf"]


def test_the_launch_file_s_allow_contact_is_the_node_s(ros_python):
    """``allow_contact:=true`` starts the node with --allow-contact (roslaunch itself
    says the command line it would run); by default, and with false, it refuses."""
    env = {**os.environ, "ROS_PACKAGE_PATH": str(ROOT / "ros"),
           "PATH": os.pathsep.join([str(ros_python.parent), *outside_this_venv()])}

    def node(*args: str) -> list[str]:
        done = subprocess.run(["roslaunch", "--args", "/inmoov_hand", "inmoov_dsl",
                               "display.launch", "port:=sim://", *args], env=env,
                              capture_output=True, text=True, timeout=WAIT)
        assert done.returncode == 0, done.stderr
        return done.stdout.split()

    assert "--allow-contact" in node("profile:=inmoov", "allow_contact:=true")
    assert "--allow-contact" not in node("profile:=inmoov")
    assert "--allow-contact" not in node("allow_contact:=false")


def test_the_node_says_where_its_ros_package_is(capsys):
    from inmoov_dsl.ros.__main__ import main

    assert main(["--package-path"]) == 0
    where = Path(capsys.readouterr().out.strip())
    assert (where / "launch" / "display.launch").is_file()
    assert (where / "package.xml").read_text().count("<name>inmoov_dsl</name>") == 1
