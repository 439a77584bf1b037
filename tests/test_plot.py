"""gestc plot: a picture of every library gesture, and a clear word without matplotlib."""

import sys
from pathlib import Path

import numpy as np
import pytest
from conftest import early, library_profile

from inmoov_dsl.cli import gestc
from inmoov_dsl.compiling.compiler import compile_program
from inmoov_dsl.language.library import scan_library
from inmoov_dsl.language.load import load
from inmoov_dsl.views.plot import moving_servos, sent_values

ROOT = Path(__file__).resolve().parent.parent
LIBRARY = scan_library([ROOT / "gestures"])
PNG = b"\x89PNG\r\n\x1a\n"


def profile_for(name):
    return library_profile(LIBRARY[name].path)


#: what changes a plot: the profile (a panel a servo: the hand's six, the robot's
#: twenty-eight), a long gesture's many steps, a say's sound; every gesture compiling is
#: test_library's (a plot of each was a twentieth of the suite, the same drawing each time)
PLOTTED = ["peace", "demo", "hello", "hello_talk"]


@pytest.mark.parametrize("name", PLOTTED)
def test_library_gestures_plot(name, tmp_path, capsys):
    out = tmp_path / f"{name}.png"
    assert gestc.main(["plot", name, "--profile", profile_for(name), "-o", str(out)]) == 0
    assert capsys.readouterr().err == f"wrote {out}\n"
    assert out.read_bytes().startswith(PNG)


def test_svg_and_the_default_name(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert gestc.main(["plot", "peace", "-o", "p.svg"]) == 0
    assert b"<svg" in (tmp_path / "p.svg").read_bytes()[:500]
    assert gestc.main(["plot", "peace"]) == 0
    assert (tmp_path / "peace.png").read_bytes().startswith(PNG)


def test_output_into_a_directory_or_refused(tmp_path, capsys):
    assert gestc.main(["plot", "peace", "-o", str(tmp_path)]) == 0
    assert capsys.readouterr().err == f"wrote {tmp_path / 'peace.png'}\n"
    assert (tmp_path / "peace.png").read_bytes().startswith(PNG)
    for out, message in [(tmp_path / "pics", "write a .png, .svg or .pdf file, or into a "
                                              "directory"),
                         (tmp_path / "p.jpg", "write a .png, .svg or .pdf file"),
                         (f"{tmp_path / 'none'}/", "no such directory")]:
        assert gestc.main(["plot", "peace", "-o", str(out)]) == 1
        assert f"gestc: error: -o {out}: {message}" in capsys.readouterr().err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["peace.png"]


def test_the_plot_shows_what_the_board_is_sent():
    compiled, plan = compile_program(load(str(LIBRARY["count"].path)), "count")
    sent = sent_values(plan, compiled)
    # index never moves in count: no row for it; the others end where the plan ends
    rows = [plan.profile.servos[i].name for i in moving_servos(plan, sent)]
    assert rows == ["thumb", "middle", "ring", "pinky"]
    # a pair arrives up to a byte-time before its slot (the byte grid), with its slot's value
    bound = 0.5 + early(plan.profile, plan.profile.boards[0].baud)
    for i in moving_servos(plan, sent):
        times, values = sent[i]
        assert values[-1] == plan.final[i]
        assert np.all(np.abs(values - plan.tracks[i].position(times)) <= bound)


def test_without_matplotlib_plot_says_how_to_get_it(monkeypatch, capsys, tmp_path):
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    monkeypatch.setitem(sys.modules, "matplotlib.figure", None)
    assert gestc.main(["plot", "peace", "-o", str(tmp_path / "p.png")]) == 1
    assert capsys.readouterr().err == (
        "gestc: error: gestc plot needs matplotlib, which is not installed\n"
        "  hint: pip install 'inmoov-dsl[plot]'\n")


@pytest.mark.parametrize("length", [60, 200])
def test_a_long_name_leaves_title_and_legend_apart(length, tmp_path):
    """The title and the legend never cover each other, however long the gesture's name
    (a long one wraps), and both stay inside the picture."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from inmoov_dsl.views.plot import figure

    name = ("a_gesture_with_a_long_name_" * 8)[:length]
    gest = tmp_path / "long.gest"
    gest.write_text(f"{name}:\n    index 180, middle 90 over 1s\n    hold 300ms\n    index 0\n")
    compiled, plan = compile_program(load(str(gest)), name)
    fig = figure(plan, compiled)
    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    renderer = canvas.get_renderer()
    title = fig._suptitle.get_window_extent(renderer)
    legend = fig.legends[0].get_window_extent(renderer)
    assert not title.overlaps(legend)
    whole = fig.bbox
    for box in (title, legend):
        assert whole.x0 <= box.x0 and box.x1 <= whole.x1 + 1
        assert whole.y0 <= box.y0 and box.y1 <= whole.y1 + 1
    assert name in fig._suptitle.get_text().replace("\n", "")  # all of it, wrapped
