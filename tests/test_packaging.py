"""A non-editable install carries the grammar, the profiles and the gesture library."""

import os
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent


@pytest.fixture(scope="module")
def wheel(tmp_path_factory):
    out = tmp_path_factory.mktemp("wheel")
    done = subprocess.run(
        [sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation", "-q",
         "-w", str(out), str(ROOT)], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    (path,) = out.glob("inmoov_dsl-*.whl")
    return path


def test_the_wheel_carries_grammar_profiles_and_library(wheel):
    names = set(zipfile.ZipFile(wheel).namelist())
    assert "inmoov_dsl/_data/grammar/gest.lark" in names
    assert "inmoov_dsl/_data/gestures/profiles/rhand.toml" in names
    assert "inmoov_dsl/_data/gestures/count.gest" in names
    assert "inmoov_dsl/_data/gestures/peace.gest" in names
    for shipped in (*(ROOT / "gestures").glob("*.gest"),
                    *(ROOT / "gestures" / "profiles").glob("*.toml")):
        assert f"inmoov_dsl/_data/{shipped.relative_to(ROOT).as_posix()}" in names
    for part in ("libraries/InmoovDsl/src/servo_core.cpp", "libraries/InmoovDsl/library.properties",
                 "libraries/InmoovDsl/src/servo_pulses.cpp", "harness/simboard.c", "Makefile"):
        assert f"inmoov_dsl/_data/firmware/{part}" in names
    for part in ("package.xml", "launch/display.launch", "rviz/hand.rviz", "scripts/inmoov_node"):
        assert f"inmoov_dsl/_data/ros/{part}" in names  # the ROS package, for roslaunch
    node = zipfile.ZipFile(wheel).getinfo("inmoov_dsl/_data/ros/scripts/inmoov_node")
    assert node.external_attr >> 16 & 0o111  # an executable, as rosrun wants
    entry_points = next(n for n in names if n.endswith("entry_points.txt"))
    text = zipfile.ZipFile(wheel).read(entry_points).decode()
    assert "gestc = inmoov_dsl.cli:run_gestc" in text
    assert "gestplay = inmoov_dsl.cli:run_gestplay" in text
    assert "gestsim = inmoov_dsl.cli:run_gestsim" in text
    assert "[pygments.lexers]\ngest = inmoov_dsl.editor.lexer:GestLexer\n" in text


def test_the_default_install_checks_collisions(wheel):
    """``pip install .`` brings python-fcl wherever PyPI has its wheel: a player that
    drives the whole InMoov checks it for contacts without an extra."""
    from packaging.markers import Marker

    metadata = next(n for n in zipfile.ZipFile(wheel).namelist() if n.endswith("METADATA"))
    text = zipfile.ZipFile(wheel).read(metadata).decode()
    (line,) = [x for x in text.splitlines() if x.startswith("Requires-Dist: python-fcl")
               and "extra ==" not in x]
    marker = Marker(line.partition(";")[2])
    for machine, system in (("x86_64", "linux"), ("AMD64", "win32"), ("arm64", "darwin"),
                            ("x86_64", "darwin")):
        assert marker.evaluate({"platform_machine": machine, "sys_platform": system})
    assert not marker.evaluate({"platform_machine": "aarch64", "sys_platform": "linux"})


def test_the_installed_layout_compiles_the_library(wheel, tmp_path):
    site = tmp_path / "site"
    zipfile.ZipFile(wheel).extractall(site)
    code = ("import inmoov_dsl, inmoov_dsl.resources as r, sys; "
            "print(inmoov_dsl.__file__); print(r.grammar_path()); "
            "from inmoov_dsl.cli.gestc import main; sys.exit(main(['compile', 'count', "
            "'-o', '-', '-f', 'timed']))")
    done = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True,
                          text=True, timeout=120,
                          env={**os.environ, "PYTHONPATH": str(site)})
    assert done.returncode == 0, done.stderr
    lines = done.stdout.splitlines()
    assert lines[0].startswith(str(site))
    assert lines[1] == str(site / "inmoov_dsl" / "_data" / "grammar" / "gest.lark")
    assert lines[2] == "0.000000 255"


@pytest.mark.parametrize("where", ["the clone's root", "elsewhere"])
def test_the_readme_first_line_plays_from_the_root_and_from_elsewhere(wheel, tmp_path, where):
    """``pip install . && gestplay peace --port sim://``: the installed package, run
    from the clone's root (where ./gestures is the library the package carries too) and
    from any other directory."""
    site = tmp_path / "site"
    zipfile.ZipFile(wheel).extractall(site)
    code = "import sys; from inmoov_dsl.cli.gestplay import main; " \
           "sys.exit(main(['peace', '--port', 'sim://']))"
    done = subprocess.run([sys.executable, "-c", code],
                          cwd=ROOT if where == "the clone's root" else tmp_path,
                          capture_output=True, text=True, timeout=120,
                          env={**os.environ, "PYTHONPATH": str(site)})
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("played peace: 0.70 s, ")
    # what the virtual hand now holds, drawn as gestsim draws it, and where to watch it
    bar = "#" * 30
    assert done.stdout.splitlines()[1:8] == [
        "sim://rhand?board=181 now holds (board 181, right hand):",
        "  wrist        0", f"  thumb      180  {bar}", "  index        0",
        "  middle       0", f"  ring       180  {bar}", f"  pinky      180  {bar}"]
    assert "to watch it move: run 'gestsim --view'" in done.stderr
