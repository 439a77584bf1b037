"""gestc fmt: one canonical layout, comments kept, the same bytes after formatting."""

import io
from pathlib import Path

import numpy as np
import pytest
from conftest import library_profile
from hypothesis import HealthCheck, given, settings
from test_stream import gestures

from inmoov_dsl.cli import gestc
from inmoov_dsl.compiling.compiler import compile_program
from inmoov_dsl.language.fmt import format_source
from inmoov_dsl.language.load import load

ROOT = Path(__file__).resolve().parent.parent
LIBRARY = sorted((ROOT / "gestures").glob("*.gest"))

MESSY = """\


# header comment

use   "peace.gest"   # imports
group  wave_order :pinky,ring ,  middle,index
pose fist: thumb 180,index 180, \\
   middle 180
# about g
g:   index +090 over .50s   # trailing
h:
  # inside h
  index 90 stagger 10ms over 1.0s

  hold 500ms # held


  wait   1 s
  repeat 2 :
      index 0
      # inside repeat
      index 180   # r
  # end of h
# before k
k: repeat 3: fist
x:  # header comment
    wave_order 10
"""

CANONICAL = """\
# header comment

use "peace.gest"  # imports
group wave_order: pinky, ring, middle, index
pose fist: thumb 180, index 180, middle 180
# about g
g: index 90 over 0.5s  # trailing

h:
    # inside h
    index 90 over 1s stagger 10ms

    hold 500ms  # held

    wait 1s
    repeat 2:
        index 0
        # inside repeat
        index 180  # r
    # end of h

# before k
k: repeat 3: fist

x:  # header comment
    wave_order 10
"""


def same_bytes(before: str, after: str, file: str, profile: str = "rhand") -> None:
    old, new = load(file, before), load(file, after)
    assert old.own == new.own
    for name in old.own:
        a = compile_program(old, name, profile)[0]
        b = compile_program(new, name, profile)[0]
        for x, y in zip(a.streams, b.streams, strict=True):
            assert x.data == y.data
            assert np.array_equal(x.times, y.times)


def test_the_canonical_layout():
    assert format_source(MESSY) == CANONICAL
    assert format_source(CANONICAL) == CANONICAL
    same_bytes(MESSY, CANONICAL, str(ROOT / "gestures" / "messy.gest"))


def test_trailing_comments_align_within_a_block():
    source = "g:\n    index 90  # a\n    hold 1s\n    thumb 180, index 0 over 1s  # b\n"
    assert format_source(source).splitlines() == [
        "g:",
        "    index 90                    # a",
        "    hold 1s",
        "    thumb 180, index 0 over 1s  # b",
    ]


def squash(line: str) -> str:
    """The same line laid out carelessly: two-space indents, no space after commas,
    a trailing comment moved; the comment's own text kept."""
    code, hash_, comment = line.rstrip("\n").partition("#")
    pieces = code.split('"')  # a string's own text (say "Hello, I am") stays as it is
    code = '"'.join(p if k % 2 else p.replace("    ", "  ").replace(", ", ",")
                    for k, p in enumerate(pieces)).rstrip()
    if hash_ and code.strip():
        code += "   "
    return f"{code}{hash_}{comment}\n"


@pytest.mark.parametrize("path", LIBRARY, ids=lambda p: p.name)
def test_the_library_is_formatted_and_formatting_keeps_its_bytes(path):
    text = path.read_text()
    assert format_source(text, str(path)) == text
    squashed = "".join(squash(line) for line in text.splitlines(keepends=True))
    formatted = format_source(squashed, str(path))
    assert formatted == text
    same_bytes(text, squashed, str(path), library_profile(path))


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(gestures(["wrist", "thumb", "index", "middle", "ring", "pinky"]))
def test_formatting_is_idempotent_and_keeps_the_bytes(source):
    once = format_source(source)
    assert format_source(once) == once
    same_bytes(source, once, "gen.gest")


def test_fmt_rewrites_checks_and_reads_stdin(tmp_path, capsys, monkeypatch):
    messy = tmp_path / "messy.gest"
    messy.write_text(MESSY)
    tidy = tmp_path / "tidy.gest"
    tidy.write_text(CANONICAL)
    assert gestc.main(["fmt", "--check", str(messy), str(tidy)]) == 1
    assert capsys.readouterr().out == f"{messy}: would be reformatted\n"
    assert messy.read_text() == MESSY
    assert gestc.main(["fmt", str(messy)]) == 0
    assert capsys.readouterr().err == f"{messy}: reformatted\n"
    assert messy.read_text() == CANONICAL
    assert gestc.main(["fmt", "--check", str(messy)]) == 0
    monkeypatch.setattr("sys.stdin", io.StringIO("g:  index   9\n"))
    assert gestc.main(["fmt", "-"]) == 0
    assert capsys.readouterr().out == "g: index 9\n"


def test_a_file_that_does_not_parse_is_reported_and_left_alone(tmp_path, capsys):
    bad = tmp_path / "bad.gest"
    bad.write_text("g: index 90 over\n")
    assert gestc.main(["fmt", str(bad)]) == 1
    assert capsys.readouterr().err.startswith(f"{bad}:1:17: error: unexpected end of line; "
                                              "expected a number\n")
    assert bad.read_text() == "g: index 90 over\n"
