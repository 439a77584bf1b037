"""The command-line tools. The console scripts start here, so that a Ctrl-C (or a
SIGTERM) while the tool is still importing its modules ends with one line and exit
status 130 (143), not a traceback, and so that starting is quick: no garbage collection
while the tool imports (``common.run`` turns it on for the command, past what start-up
made: benchmarks/cli_startup.py)."""

from __future__ import annotations

import gc
import importlib
import sys


def _start(tool: str) -> int:
    """Import the tool (a Ctrl-C meanwhile is one line) and run its ``main``."""
    gc.disable()  # importing makes many objects and frees few: nothing to collect
    from .common import status_of, stop_on_signals, why

    stop_on_signals()
    try:
        main = importlib.import_module(f".{tool}", __name__).main
    except KeyboardInterrupt as exc:
        print(f"{tool}: {why(exc)} while starting", file=sys.stderr)
        return status_of(exc)
    return main()


def run_gestc() -> int:
    """The gestc console script."""
    return _start("gestc")


def run_gestplay() -> int:
    """The gestplay console script."""
    return _start("gestplay")


def run_gestsim() -> int:
    """The gestsim console script."""
    return _start("gestsim")
