"""Tests that need a toolchain (gcc-avr, simavr, avrdude...) skip without it, except
under CI=true, where a missing toolchain is a failure."""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import pytest

PACKAGES = ("make g++ gcc-avr avr-libc arduino-core-avr simavr libsimavr-dev libelf-dev "
            "avrdude")


def require(what: str, found: bool, install: str) -> None:
    """Skip (fail under CI=true) unless ``what`` was ``found``; ``install``: how to get it."""
    if found:
        return
    message = f"needs {what} ({install})"
    if os.environ.get("CI") == "true":
        pytest.fail(f"CI: {message}")
    pytest.skip(message)


def need(*tools: str, packages: str = PACKAGES) -> None:
    """Skip (fail under CI=true) unless every tool is on the PATH or is an existing path;
    ``packages``: the Debian packages that bring them."""
    missing = [t for t in tools if shutil.which(t) is None and not Path(t).exists()]
    require(", ".join(missing), not missing, f"apt-get install {packages}")
