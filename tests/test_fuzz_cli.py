"""Hostile command lines: whatever the arguments, a tool answers with a message and an
exit status, never a traceback or a hang (a seeded run over every command's options)."""

from __future__ import annotations

import contextlib
import io
import random
import threading

import pytest

from inmoov_dsl.cli import gestc, gestplay

#: values a careless user or a script might pass anywhere
HOSTILE = ["nan", "inf", "-inf", "-1", "0", "1e308", "-1e308", "9" * 400, "", " ", "\x00",
           "é", "\n", "index 0\nfoo: index 1", "fingers 90", "peace", "count", "wait",
           "rhand", "inmoov", "sim://", "sim://nosuch", "loop://", "COM3", "181=sim://",
           "999=sim://", "/nonexistent/x.gest", "..", "-", "x.png", "-o", "--help=1",
           "\udcff", "0x10", "1_000", "½"]

#: (tool, words): a command's fixed words, then option names that take a value
COMMANDS = [
    (gestc, ["compile", "peace"], ["-o", "-g", "--from", "-p", "--board", "-f"]),
    (gestc, ["check", "peace.gest"], ["-p", "--from"]),
    (gestc, ["show", "count"], ["-p", "--from", "-g", "--color"]),
    (gestc, ["export", "peace"], ["--joint-states", "--rate", "-p", "--from"]),
    (gestc, ["fmt", "--check"], []),
    (gestc, ["urdf"], ["-p", "-o"]),
    (gestc, ["list"], ["--lib"]),
    (gestc, ["firmware", "rhand", "--check"], ["--baud", "-o"]),
    (gestc, ["upload", "servo_rhand", "--dry-run"], ["--port", "-p", "--hex", "--baud"]),
    (gestplay, ["peace", "--dry-run"], ["--speed", "--loop", "-p", "-g", "--lib", "--hand"]),
    (gestplay, ["send", "--port", "sim://?boot=0", "cancel"], ["--listen", "-p"]),
    (gestplay, ["dump"], ["--port", "-p"]),
]

SEED, RUNS = 11, 250
LIMIT = 20.0  #: s a single command may take on a loaded machine (a hang fails the test)


def command_lines(seed: int, runs: int):
    rng = random.Random(seed)
    for _ in range(runs):
        tool, words, options = rng.choice(COMMANDS)
        argv = list(words)
        for _ in range(rng.randint(0, 3)):
            if options and rng.random() < 0.8:
                argv += [rng.choice(options), rng.choice(HOSTILE)]
            else:
                argv.append(rng.choice(HOSTILE))
        yield tool, argv


def run_watched(tool, argv: list[str]) -> tuple[object, str]:
    """Run ``tool.main(argv)`` in a thread: (exit status or the exception, what it said:
    stderr, then stdout)."""
    result: list[object] = []
    err, out = io.StringIO(), io.StringIO()

    def body():
        try:
            with contextlib.redirect_stderr(err), contextlib.redirect_stdout(out):
                result.append(tool.main(argv))
        except SystemExit as exc:
            result.append(exc.code)
        except BaseException as exc:  # noqa: BLE001 (what we are looking for)
            result.append(exc)

    thread = threading.Thread(target=body, daemon=True)
    thread.start()
    thread.join(LIMIT)
    assert not thread.is_alive(), f"{tool.PROG} {argv!r} still running after {LIMIT} s"
    return result[0], err.getvalue() + out.getvalue()


@pytest.mark.parametrize("chunk", range(5))
def test_hostile_command_lines_get_a_message_and_an_exit_status(chunk, tmp_path,
                                                                monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "peace.gest").write_text("peace: index 90\n")
    lines = list(command_lines(SEED + chunk, RUNS // 5))
    assert len(lines) == RUNS // 5
    for tool, argv in lines:
        status, err = run_watched(tool, argv)
        assert status in (0, 1, 2), f"{tool.PROG} {argv!r}: {status!r}\n{err}"
        assert "Traceback" not in err, f"{tool.PROG} {argv!r}\n{err}"
        if status == 1:
            assert err.strip(), f"{tool.PROG} {argv!r} failed without a word"
