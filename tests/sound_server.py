"""A sound server for the tests: PulseAudio with one null sink (a virtual output that
plays in real time and can be recorded from its monitor), on a socket of the test's own;
``PULSE_SERVER`` points there, for this process and the programs it starts."""

from __future__ import annotations

import contextlib
import os
import shutil
import subprocess
import time
from collections.abc import Iterator
from pathlib import Path

import pytest
from toolchain import require

SINK = "speaker"


def need_sounddevice() -> None:
    import importlib.util

    require("sounddevice", importlib.util.find_spec("sounddevice") is not None,
         "pip install sounddevice; apt-get install libportaudio2")


def rescan() -> None:
    """PortAudio lists the outputs when it starts: again, now that the server is up."""
    import sounddevice

    sounddevice._terminate()
    sounddevice._initialize()


@contextlib.contextmanager
def null_sink(home: Path) -> Iterator[str]:
    """A PulseAudio server with a null sink, its files in ``home``: its socket's address
    (for ``PULSE_SERVER``), until the block ends (the benchmarks use it too)."""
    exe = shutil.which("pulseaudio")
    require("pulseaudio", exe is not None, "apt-get install pulseaudio")
    home.mkdir(exist_ok=True)
    config = home / "default.pa"
    config.write_text(f"load-module module-null-sink sink_name={SINK} rate=48000\n"
                      f"set-default-sink {SINK}\n"
                      f"load-module module-native-protocol-unix socket={home}/native "
                      f"auth-anonymous=1\n")
    env = {**os.environ, "XDG_RUNTIME_DIR": str(home), "HOME": str(home)}
    proc = subprocess.Popen([exe, "-n", "-F", str(config), "--exit-idle-time=-1",
                             "--daemonize=no", "--use-pid-file=no", "--disable-shm"],
                            env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    try:
        deadline = time.monotonic() + 20
        while not Path(home, "native").exists():
            assert proc.poll() is None, proc.stderr.read().decode()
            assert time.monotonic() < deadline, "pulseaudio did not start in 20 s"
            time.sleep(0.05)
        yield f"unix:{home}/native"
    finally:
        proc.terminate()
        try:
            proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            proc.kill()


@pytest.fixture
def sound_server(tmp_path, monkeypatch):
    """A PulseAudio server with a null sink, for this test: its socket's address."""
    need_sounddevice()
    with null_sink(tmp_path / "pulse") as address:
        monkeypatch.setenv("PULSE_SERVER", address)
        try:
            rescan()
        except OSError as exc:
            require("PortAudio", False, f"apt-get install libportaudio2 ({exc})")
        yield address
