"""An unknown name's hint asks the library (``language.catalog``): the library is read
once per process, and again only when one of its files changes; the hint names the
library file that defines the name, or the closest name, the library's gestures' too."""

import os

import pytest

from inmoov_dsl.cli import gestc
from inmoov_dsl.language import catalog, library

USE_PEACE = 'add the line  use "peace.gest"  to this file'


@pytest.fixture
def reads(monkeypatch):
    """Every read of the library from now on (a fresh catalog), counted: the scans and
    the files they parse."""
    monkeypatch.setattr(catalog, "_kept", {})
    count = {"scans": 0, "parses": 0}
    scan, parse = library.scan, library.parse

    def counted_scan(*args, **kwargs):
        count["scans"] += 1
        return scan(*args, **kwargs)

    def counted_parse(*args, **kwargs):
        count["parses"] += 1
        return parse(*args, **kwargs)

    monkeypatch.setattr(library, "scan", counted_scan)
    monkeypatch.setattr(library, "parse", counted_parse)
    return count


def unknown_calls(count: int) -> str:
    return "robot rhand\n\nbig:\n" + "".join(f"    nope{i}\n" for i in range(count))


def hints(err: str) -> list[str]:
    return [line.removeprefix("  hint: ") for line in err.splitlines()
            if line.startswith("  hint: ")]


def test_a_file_of_many_unknown_calls_reads_the_library_once(tmp_path, capsys, reads):
    mine = tmp_path / "many.gest"
    mine.write_text(unknown_calls(300))
    assert gestc.main(["check", str(mine)]) == 1
    assert capsys.readouterr().err.count(": error: unknown ") == 300
    files = len(library.library_files())
    assert reads == {"scans": 1, "parses": files}
    assert gestc.main(["check", str(mine)]) == 1  # the same process: read already
    assert reads == {"scans": 1, "parses": files}


def test_a_library_file_changed_added_or_removed_is_seen_at_the_next_lookup(
        tmp_path, capsys, reads):
    lib = tmp_path / "lib"
    lib.mkdir()
    hands = lib / "hands.gest"
    hands.write_text("flap: index 10\n")
    mine = tmp_path / "mine.gest"
    mine.write_text("robot rhand\n\nmine: flip\n")
    check = ["check", str(mine), "--lib", str(lib)]

    assert gestc.main(check) == 1
    assert hints(capsys.readouterr().err) == [
        "did you mean 'flap'? It is a library gesture, defined in hands.gest: add the "
        "line  use \"hands.gest\"  to this file"]
    assert gestc.main(check) == 1
    capsys.readouterr()
    assert reads["scans"] == 1  # nothing changed: not read again

    before = hands.stat()
    hands.write_text("flip: index 10\n")  # the same size; its time moved on for sure
    os.utime(hands, ns=(before.st_atime_ns, before.st_mtime_ns + 2_000_000_000))
    assert gestc.main(check) == 1
    assert hints(capsys.readouterr().err) == [
        "'flip' is a library gesture, defined in hands.gest: add the line  "
        "use \"hands.gest\"  to this file"]
    assert reads["scans"] == 2

    hands.unlink()
    (lib / "more.gest").write_text("flop: index 10\n")
    assert gestc.main(check) == 1
    assert hints(capsys.readouterr().err) == [
        "did you mean 'flop'? It is a library gesture, defined in more.gest: add the "
        "line  use \"more.gest\"  to this file"]
    assert reads["scans"] == 3


def test_a_misspelt_library_gesture_gets_a_did_you_mean_and_its_use_line(
        tmp_path, capsys):
    mine = tmp_path / "mine.gest"
    mine.write_text("robot rhand\n\nmine:\n    peac\n")
    assert gestc.main(["check", str(mine)]) == 1
    assert hints(capsys.readouterr().err) == [
        f"did you mean 'peace'? It is a library gesture, defined in peace.gest: {USE_PEACE}"]
    mine.write_text('robot rhand\nuse "peace.gest"\n\nmine:\n    peac\n')
    assert gestc.main(["check", str(mine)]) == 1  # in the file now: said plainly
    assert hints(capsys.readouterr().err) == ["did you mean 'peace'?"]


def test_a_name_of_the_file_closer_than_the_librarys_is_the_one_meant(tmp_path, capsys):
    mine = tmp_path / "mine.gest"
    mine.write_text("robot rhand\n\npeaces: index 9\nmine: peacess\n")
    assert gestc.main(["check", str(mine)]) == 1
    assert hints(capsys.readouterr().err) == ["did you mean 'peaces'?"]


def test_a_library_that_is_an_error_is_that_error_each_time(tmp_path):
    for name in ("a.gest", "b.gest"):
        (tmp_path / name).write_text("twice: index 9\n")
    for _ in range(2):
        with pytest.raises(library.GestError, match="defined in two library files"):
            catalog.scanned([tmp_path])
