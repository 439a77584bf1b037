"""What a newcomer tripped on: a gesture file named like a library gesture, stored
gestures named one way in every option, hints for the first mistakes people make,
counts in words, and what the service and gestc show say."""

import pytest

from inmoov_dsl.cli import gestc, gestplay
from inmoov_dsl.cli.gestc.show import link_text
from inmoov_dsl.cli.gestplay import sounds
from inmoov_dsl.compiling.metrics import LinkReport
from inmoov_dsl.errors import GestError, counted
from inmoov_dsl.language.parse import parse
from inmoov_dsl.profiles.profile import load_profile
from inmoov_dsl.service.core import BadRequest, problem
from inmoov_dsl.wire.stored import read_blob, read_set


def test_a_name_is_its_file_here_before_the_library(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "mine.gest").write_text("mine: index 90\n")
    (tmp_path / "peace.gest").write_text("peace: index 45\n")  # my own peace
    assert gestc.main(["show", "mine"]) == 0
    assert capsys.readouterr().out.startswith("mine: 0.")
    assert gestplay.main(["mine", "--dry-run"]) == 0
    assert gestplay.main(["peace", "--port", "sim://"]) == 0
    assert "index       45" in capsys.readouterr().out  # this folder's peace.gest


def stored(tmp_path, *options):
    """The names the board stores, in order, and its triggers."""
    book = tmp_path / "book"
    assert gestc.main(["firmware", "rhand", "-o", str(book), *options]) == 0
    flash = read_set(read_blob(book / "servo_rhand"))
    names = [g.name for g in flash.gestures]
    return names, flash


@pytest.fixture
def files(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "hi.gest").write_text("hi: index 90 over 0.5s\n")
    (tmp_path / "several.gest").write_text("wave: index 90\nfist: fingers 180\n"
                                           "point: thumb 180, middle 180\n")
    return tmp_path


@pytest.mark.parametrize("options", [["--store", "hi.gest", "--on-boot", "hi"],
                                     ["--store", "hi.gest", "--on-boot", "hi.gest"],
                                     ["--store", "hi", "--on-boot", "hi.gest"],
                                     ["--on-boot", "hi.gest"]])
def test_a_stored_gesture_is_named_the_same_way_in_every_option(files, options):
    names, flash = stored(files, *options)
    assert names == ["hi"] and flash.boot == 0


def test_a_file_of_several_gestures_stores_the_ones_asked_for(files, capsys):
    names, flash = stored(files, "--store", "several.gest", "--button", "D8=fist")
    assert names == ["wave", "fist", "point"]  # the file: all of its gestures
    assert flash.buttons == ((8, 1),)
    names, flash = stored(files, "--store", "several.gest:point", "--idle", "several.gest:wave")
    assert names == ["point", "wave"] and flash.idle == 1
    assert gestc.main(["firmware", "rhand", "-o", str(files / "b"), "--on-boot",
                       "several.gest"]) == 1
    err = capsys.readouterr().err
    assert "gestc: error: several.gest defines 3 gestures: wave, fist, point" in err
    assert "hint: name one: several.gest:wave, or store them all: --store several.gest" in err
    assert "--gesture" not in err


def test_two_gestures_of_one_name_cannot_both_be_stored(files, capsys):
    (files / "other.gest").write_text("wave: index 45\n")
    assert gestc.main(["firmware", "rhand", "-o", str(files / "b"), "--store",
                       "several.gest:wave,other.gest"]) == 1
    assert "two gestures named 'wave' to store" in capsys.readouterr().err


@pytest.mark.parametrize(("text", "where", "hint"), [
    ("x: index = 90\n", "1:10", "a servo and its value are separated by a space: index 90"),
    ("x:\n    index=90\n", "2:10", "a servo and its value are separated by a space: index 90"),
    ("peace\n    index 90\n", "1:6", "end the gesture's name with ':', then its steps after "
     "it or on the lines below, indented"),
    ("peace index 180\n", "1:7", "a gesture starts with its name and ':', as in  peace: "
     "index 180"),
    ("pose open\n", "1:10", "end the pose's name with ':', then its targets: pose open: "
     "fingers 0"),
    ("group pair\n", "1:11", "end the group's name with ':', then its servos: group pair: "
     "index, middle"),
])
def test_the_first_mistakes_get_a_hint(text, where, hint):
    with pytest.raises(GestError) as info:
        parse(text, "f.gest")
    said = str(info.value)
    assert said.startswith(f"f.gest:{where}: error: ")
    assert said.endswith(f"  hint: {hint}")


def test_counts_are_said_in_words(capsys, tmp_path):
    assert [counted(1, "byte"), counted(2, "byte"), counted(1234, "byte")] == \
        ["1 byte", "2 bytes", "1,234 bytes"]
    still = tmp_path / "still.gest"
    still.write_text("still: wait 0.1s\n")
    assert gestplay.main([str(still), "--port", "sim://"]) == 0
    assert "played still: 0.10 s, 1 byte, " in capsys.readouterr().out


def test_the_service_leaves_out_a_hint_it_does_not_have():
    from inmoov_dsl.errors import Diagnostic
    from inmoov_dsl.service.core import diagnostic

    assert BadRequest("no").json() == {"error": "no"}
    assert BadRequest("no", "yes").json() == {"error": "no", "hint": "yes"}
    assert "hint" not in diagnostic(Diagnostic("error", "no"))
    with pytest.raises(GestError) as info:
        parse("x: index = 90\n", "<request>")
    (said,) = problem(info.value)["diagnostics"]
    assert said["hint"] == "a servo and its value are separated by a space: index 90"


def test_a_profile_that_cannot_speak_opens_no_sound_output(capsys, monkeypatch):
    from inmoov_dsl.wire import audio

    def refuse(*args, **kwargs):
        raise AssertionError("a profile without a mouth opened the sound output")

    monkeypatch.setattr(audio, "Speaker", refuse)
    assert sounds.speaker(None, "gestplay", load_profile("rhand")) is None
    assert "silent" not in capsys.readouterr().err


def report(**changes) -> LinkReport:
    base = dict(board=184, baud=9600, servos=5, bytes=919, values=400, naive_bytes=2851,
                end=4.5, utilisation=0.11, peak_utilisation=0.31, needed=220, covered=219,
                worst_lag=6.1, worst_lag_servo="jaw", worst_lag_time=0.64, max_error=1.3)
    return LinkReport(**{**base, **changes})


def test_show_says_what_keeps_coverage_below_100_percent():
    spare = link_text(report())
    assert "bottleneck" not in spare and "raise the baud" not in spare
    assert spare.endswith("  1 servo-frame got the value a frame late: at a sharp turn of "
                          "the jaw's plan, the value lands on its pair's slot just after the "
                          "frame began; the link has room to spare: nothing to change")
    full = link_text(report(peak_utilisation=1.0, covered=180))
    assert full.endswith("  the link is the bottleneck: its busiest frame is full; raise the "
                         "baud or split the servos over more boards")
    assert not link_text(report(covered=220)).splitlines()[-1].startswith("  1 ")


def test_a_trigger_names_one_gesture_of_a_file_stored_whole(files, capsys):
    assert gestc.main(["firmware", "rhand", "-o", str(files / "b"), "--store", "several.gest",
                       "--on-boot", "several.gest"]) == 1
    assert "several.gest defines 3 gestures" in capsys.readouterr().err
    names, flash = stored(files, "--store", "several.gest", "--on-boot", "several.gest:point")
    assert names == ["wave", "fist", "point"] and flash.boot == 2


def test_a_file_without_gestures_to_store_is_one_message(files, capsys):
    (files / "poses.gest").write_text("pose p: index 9\n")
    assert gestc.main(["firmware", "rhand", "-o", str(files / "b"), "--store",
                       "poses.gest"]) == 1
    assert capsys.readouterr().err == "gestc: error: poses.gest defines no gesture\n"
