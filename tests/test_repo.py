"""The repository's own promises: the README's commands, CI, lint."""

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def readme_commands():
    lines = (ROOT / "README.md").read_text().splitlines()
    return [line.strip() for line in lines[2:4]]


def test_readme_opens_with_the_two_commands():
    main_job, tests = readme_commands()
    venv = "python3 -m venv .venv && . .venv/bin/activate && "  # no pip into Debian's own
    assert main_job == venv + "python -m pip install . && gestplay peace --port sim://"
    assert tests == venv + "python -m pip install -e '.[test]' && python -m pytest"


def test_ci_runs_the_readme_test_command():
    ci = (ROOT / ".ci" / "run").read_text().splitlines()
    assert readme_commands()[1] in ci


def test_ruff_is_clean():
    done = subprocess.run([sys.executable, "-m", "ruff", "check", str(ROOT)],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stdout + done.stderr
