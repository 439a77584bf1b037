"""The command-line tools. The console scripts start here, so that a Ctrl-C (or a
SIGTERM) while the tool is still importing its modules ends with one line and exit
status 130 (143), not a traceback."""

from __future__ import annotations

import importlib
import signal
import sys


def _start(tool: str) -> int:
    def stop(signum: int, frame: object) -> None:
        raise KeyboardInterrupt(128 + signum)

    for name in ("SIGTERM", "SIGHUP"):
        if hasattr(signal, name):
            signal.signal(getattr(signal, name), stop)
    try:
        main = importlib.import_module(f".{tool}", __name__).main
    except KeyboardInterrupt as exc:
        print(f"{tool}: interrupted while starting", file=sys.stderr)
        return exc.args[0] if exc.args else 130
    return main()


def run_gestc() -> int:
    return _start("gestc")


def run_gestplay() -> int:
    return _start("gestplay")


def run_gestsim() -> int:
    return _start("gestsim")
