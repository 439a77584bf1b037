"""Files from Windows editors: a UTF-8 byte-order mark at the start of a gesture file, a
file it uses, a library file, a profile or standard input is not part of the text; one
anywhere else is an error, and columns on the first line count from after it."""

import io
import subprocess
import sys
from pathlib import Path

import pytest

from inmoov_dsl import compile_file
from inmoov_dsl.cli import gestc
from inmoov_dsl.profiles.profile import load_profile, parse_profile

ROOT = Path(__file__).resolve().parent.parent
BOM = b"\xef\xbb\xbf"
WAVE = "wave2: index 90 over 1s\n"


def run(capsys, *argv):
    code = gestc.main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def saved(path, text, bom=True):
    """``text`` written as Notepad writes it: UTF-8 with a BOM, lines ended by CR LF."""
    path.write_bytes((BOM if bom else b"") + text.replace("\n", "\r\n").encode())
    return str(path)


def stdin(monkeypatch, data):
    monkeypatch.setattr("sys.stdin", io.TextIOWrapper(io.BytesIO(data), encoding="utf-8"))


def test_a_gesture_file_saved_with_a_bom_checks_and_compiles(capsys, tmp_path):
    file = saved(tmp_path / "bom.gest", WAVE)
    code, out, err = run(capsys, "check", file)
    assert (code, out, err) == (0, f"{file}: ok (1 gesture)\n", "")
    assert compile_file(file).final[2] == 90


def test_columns_on_the_first_line_do_not_count_the_bom(capsys, tmp_path):
    file = saved(tmp_path / "bom.gest", "wave2: indx 90\n")
    code, _, err = run(capsys, "check", file)
    assert code == 1
    assert err.splitlines()[:3] == [f"{file}:1:8: error: unknown servo or group 'indx'",
                                    "    wave2: indx 90", "           ^~~~"]


def test_a_byte_that_is_not_utf8_after_a_bom_is_at_its_column(capsys, tmp_path):
    path = tmp_path / "bad.gest"
    path.write_bytes(BOM + b"x: index 9\xff0\n")
    _, _, err = run(capsys, "check", str(path))
    assert err.splitlines()[0] == (f"{path}:1:11: error: this file is not UTF-8 text: "
                                   "invalid start byte (byte 0xff)")
    assert err.splitlines()[2] == "    " + " " * 10 + "^"


@pytest.mark.parametrize(("data", "where"), [
    (BOM + b"x: index 90\n" + BOM + b"y: index 0\n", "2:1"),  # at the start of line 2
    (BOM + BOM + b"x: index 90\n", "1:1"),  # a second one is text
    (b"x: index 90 \xef\xbb\xbf\n", "1:13"),
])
def test_a_bom_anywhere_else_is_still_an_error(capsys, tmp_path, data, where):
    path = tmp_path / "mid.gest"
    path.write_bytes(data)
    code, _, err = run(capsys, "check", str(path))
    assert code == 1
    assert err.startswith(f"{path}:{where}: error: unexpected character U+FEFF")


def test_a_used_file_and_a_library_file_with_a_bom(capsys, tmp_path):
    saved(tmp_path / "moves.gest", WAVE)
    main = saved(tmp_path / "main.gest", 'use "moves.gest"\n\nboth:\n    wave2\n    wait 1s\n')
    code, _, err = run(capsys, "check", main)
    assert code == 0 and err == ""
    lib = tmp_path / "lib"
    lib.mkdir()
    saved(lib / "mine.gest", WAVE)
    code, out, err = run(capsys, "show", "wave2", "--lib", str(lib))
    assert code == 0 and out.startswith("wave2: 1.000 s on profile 'rhand'"), err


def test_a_profile_saved_with_a_bom(capsys, tmp_path):
    rhand = (ROOT / "gestures" / "profiles" / "rhand.toml").read_text()
    toml = saved(tmp_path / "myhand.toml", rhand)
    assert load_profile(toml).servos == load_profile("rhand").servos
    code, out, _ = run(capsys, "show", "peace", "--profile", toml)
    assert code == 0 and out.startswith("peace: ")
    # an error on the first line is at its column
    bad = saved(tmp_path / "bad.toml", "name = \n" + rhand)
    code, _, err = run(capsys, "show", "peace", "--profile", bad)
    assert code == 1 and err.startswith(f"{bad}:1:8: error: invalid TOML")
    # the text of a profile as an editor keeps it (gestplay calibrate edits that text)
    assert parse_profile("\ufeff" + rhand).servos == load_profile("rhand").servos


def test_fmt_writes_the_file_without_its_bom(capsys, tmp_path):
    path = tmp_path / "bom.gest"
    path.write_bytes(BOM + WAVE.encode())  # otherwise in the canonical layout
    code, out, _ = run(capsys, "fmt", "--check", str(path))
    assert (code, out) == (1, f"{path}: would be reformatted\n")
    assert path.read_bytes().startswith(BOM)
    code, _, err = run(capsys, "fmt", str(path))
    assert code == 0 and err == f"{path}: reformatted\n"
    assert path.read_bytes() == WAVE.encode()
    assert run(capsys, "fmt", "--check", str(path))[:2] == (0, "")


def test_standard_input_with_a_bom(capsys, monkeypatch):
    stdin(monkeypatch, BOM + b"wave2:  index 90  over 1s\n")
    code, out, _ = run(capsys, "fmt", "-")
    assert (code, out) == (0, WAVE)
    stdin(monkeypatch, BOM + WAVE.encode())
    code, out, err = run(capsys, "check", "-")
    assert (code, out, err) == (0, "<stdin>: ok (1 gesture)\n", "")
    stdin(monkeypatch, BOM + b"wave2: indx 90\n")
    code, _, err = run(capsys, "check", "-")
    assert code == 1 and err.startswith("<stdin>:1:8: error: unknown servo or group")


def test_a_pipe_from_another_program(tmp_path):
    """The real standard input, bytes as a Windows shell pipes them."""
    done = subprocess.run([sys.executable, "-m", "inmoov_dsl.cli.gestc", "fmt", "-"],
                          input=BOM + b"wave2:  index 90 over 1s\r\n", capture_output=True,
                          timeout=60)
    assert done.returncode == 0, done.stderr
    assert done.stdout.replace(b"\r\n", b"\n") == WAVE.encode()
