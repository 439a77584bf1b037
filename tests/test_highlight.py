"""Gesture code highlighted: the Pygments lexer against the grammar's own tokens (Lark,
grammar/gest.lark), found by Pygments through its entry point, and gestc show's
coloured code."""

import re
import subprocess
import sys
import tomllib
from importlib.metadata import entry_points
from pathlib import Path

import pytest
from lark import Lark
from pygments.lexers import get_lexer_by_name, get_lexer_for_filename, get_lexer_for_mimetype
from pygments.plugin import iter_entry_points
from pygments.token import Comment, Error, Keyword, Name, Number, Operator, Punctuation, String
from pygments.token import Whitespace as Space

from inmoov_dsl.cli import gestc
from inmoov_dsl.cli.common import wants_color
from inmoov_dsl.cli.gestc.show import source_text
from inmoov_dsl.editor.lexer import GestLexer
from inmoov_dsl.language.indent import GestIndenter
from inmoov_dsl.language.load import load
from inmoov_dsl.language.parse import parse
from inmoov_dsl.language.syntax import GestureDef, GroupDef, PoseDef
from inmoov_dsl.resources import grammar_path

ROOT = Path(__file__).resolve().parent.parent
LIBRARY = sorted((ROOT / "gestures").glob("*.gest"))
ESCAPE = re.compile(r"\x1b\[[0-9;]*m")

#: every token the language has, in one file the grammar parses
SAMPLE = """\
# a sample of every token of the language
robot rhand-maestro
use "peace.gest"

group wave_order: pinky, ring, middle, index
pose overall: fingers 90, thumb +5
# say_hi: named like a keyword, and is not one
say_hi:
    left peace & say "Hello" & wrist 30
    index 90, middle 0 over 0.4s through
    hold 1 s
    wait .5s
    repeat 2: wrist 90 stagger 400ms  # a comment
    repeat 3:
        overall over 1.5s
        right peace
    index 10, \\
        middle 20
one: index 0
"""

#: a grammar terminal -> the token type the lexer must give its text, and whether
#: exactly that type (else any type under it)
EXPECTED = {"NAME": (Name, True), "ROBOT_NAME": (Name.Namespace, True),
            "NUMBER": (Number, False), "UNIT": (Keyword.Type, True),
            "STRING": (String, False), "COLON": (Punctuation, True),
            "COMMA": (Punctuation, True), "AMPERSAND": (Operator, True),
            "THROUGH": (Keyword, True), "SIDE": (Keyword, True), "SAY": (Keyword, True),
            "LOOK": (Keyword, True), "LPAR": (Punctuation, True), "RPAR": (Punctuation, True)}
DEFINED = (Name.Function, True)  #: the name a gesture, pose or group line defines
COMMENT, SPACE, GOES_ON = (Comment, False), (Space, False), (Punctuation, True)


@pytest.fixture(scope="module")
def grammar():
    """The grammar's parser, without the syntax tree: its tokens, as the compiler's
    lexer (contextual, with the indentation post-lexer) makes them."""
    return Lark(grammar_path().read_text(encoding="utf-8"), parser="lalr",
                lexer="contextual", postlex=GestIndenter(), maybe_placeholders=False)


def expected_types(grammar, text):
    """The token type each character of ``text`` should get, from the grammar's tokens
    and the syntax tree (which names are defined), never from the Pygments lexer."""
    lines = text.split("\n")
    offset = [0]
    for line in lines:
        offset.append(offset[-1] + len(line) + 1)
    defined = {offset[item.name.pos.line - 1] + item.name.pos.column - 1
               for item in parse(text, "sample.gest").items
               if isinstance(item, GestureDef | PoseDef | GroupDef)}
    want = [None] * len(text)
    for tok in grammar.parse_interactive(text).iter_parse():
        if tok.type in ("_INDENT", "_DEDENT"):
            continue
        if tok.type == "_NL":  # newlines, indentation, and the comments among them
            kinds = [SPACE] * len(tok)
            for comment in re.finditer(r"#[^\n]*", str(tok)):
                kinds[comment.start():comment.end()] = [COMMENT] * len(comment[0])
        else:
            pattern = grammar.get_terminal(tok.type).pattern
            keyword = pattern.type == "str" and pattern.value.isalpha()
            kind = (Keyword, True) if keyword else EXPECTED[tok.type]
            kinds = [DEFINED if tok.start_pos in defined else kind] * len(tok)
        want[tok.start_pos:tok.end_pos] = kinds
    for gap in re.finditer(r"\\[\t ]*\r?\n", text):  # ignored: the line goes on
        want[gap.start():gap.end()] = [GOES_ON] * len(gap[0])
    return [kind or SPACE for kind in want]  # the rest: blanks the grammar ignores


def lexed_types(text):
    """The token type the lexer gives each character of ``text``."""
    return [kind for kind, value in GestLexer().get_tokens(text) for _ in value]


def examples():
    """Every library file, the sample, and every gest example of the docs."""
    for path in LIBRARY:
        yield pytest.param(path.read_text(encoding="utf-8"), id=path.name)
    yield pytest.param(SAMPLE, id="sample")
    for doc in sorted((ROOT / "docs").glob("*.md")):
        for n, match in enumerate(re.finditer(r"```gest\n(.*?)```", doc.read_text(), re.S)):
            yield pytest.param(match[1], id=f"{doc.name}:{n}")


@pytest.mark.parametrize("path", LIBRARY, ids=[p.name for p in LIBRARY])
def test_every_library_file_lexes_whole_and_without_an_error(path):
    text = path.read_text(encoding="utf-8")
    tokens = list(GestLexer().get_tokens(text))
    assert "".join(value for _, value in tokens) == text
    assert [value for kind, value in tokens if kind in Error] == []


@pytest.mark.parametrize("text", list(examples()))
def test_each_character_gets_the_type_of_its_grammar_token(grammar, text):
    want, got = expected_types(grammar, text), lexed_types(text)
    assert len(got) == len(text)
    wrong = []
    for k, ((kind, exact), have) in enumerate(zip(want, got, strict=True)):
        if not (have is kind if exact else have in kind):
            line = text.count("\n", 0, k) + 1
            wrong.append(f"{line}:{k - text.rfind(chr(10), 0, k)} {text[k]!r}: {have}, "
                         f"expected {kind}")
    assert not wrong, wrong[:10]


def test_the_sample_has_every_kind_of_token():
    kinds = {(str(kind), value) for kind, value in GestLexer().get_tokens(SAMPLE)}
    for kind, value in [("Token.Name.Namespace", "rhand-maestro"),
                        ("Token.Name.Function", "wave_order"),
                        ("Token.Name.Function", "overall"), ("Token.Name.Function", "say_hi"),
                        ("Token.Name", "overall"), ("Token.Keyword", "say"),
                        ("Token.Keyword", "left"), ("Token.Keyword", "through"),
                        ("Token.Keyword.Type", "s"), ("Token.Keyword.Type", "ms"),
                        ("Token.Literal.Number.Float", ".5"),
                        ("Token.Literal.Number.Integer", "+5"),
                        ("Token.Literal.String.Double", '"Hello"'),
                        ("Token.Comment.Single", "# a comment"), ("Token.Operator", "&")]:
        assert (kind, value) in kinds


def test_what_the_language_has_no_place_for_is_an_error():
    tokens = list(GestLexer().get_tokens("a: index 90 @ 3\n"))
    assert [value for kind, value in tokens if kind in Error] == ["@"]


def test_pygments_finds_the_lexer_through_the_entry_point(tmp_path, monkeypatch):
    """The entry point pyproject.toml declares, read by Pygments' own plugin finder from
    a distribution's metadata (a probe, so the shared environment is left as it is)."""
    project = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    table = project["project"]["entry-points"]["pygments.lexers"]
    assert table == {"gest": "inmoov_dsl.editor.lexer:GestLexer"}
    for installed in entry_points(group="pygments.lexers"):  # an install that has it
        if installed.name == "gest":
            assert installed.value == table["gest"]
    info = tmp_path / "gest_probe-0.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: gest-probe\nVersion: 0\n")
    (info / "entry_points.txt").write_text(
        "[pygments.lexers]\n" + "".join(f"{k} = {v}\n" for k, v in table.items()))
    monkeypatch.syspath_prepend(str(tmp_path))
    iter_entry_points.cache_clear()
    try:
        assert type(get_lexer_by_name("gest")) is GestLexer
        assert type(get_lexer_for_filename("hand/wave.gest")) is GestLexer
        assert type(get_lexer_for_mimetype("text/x-gest")) is GestLexer
    finally:
        iter_entry_points.cache_clear()


def test_the_lexer_is_named_for_pygmentize():
    assert (GestLexer.name, GestLexer.aliases, GestLexer.filenames) == \
        ("Gest", ["gest"], ["*.gest"])


# -- gestc show ------------------------------------------------------------------------
PEACE = ["  peace.gest, lines 1-3",
         "    # peace: the V sign, index and middle straight, thumb, ring and pinky curled.",
         "    # (0 is straight and 180 curled on the InMoov hand.)",
         "    peace: thumb 180, ring 180, pinky 180, index 0, middle 0 over 0.7s"]


def show(capsys, *argv):
    assert gestc.main(["show", "peace", *argv]) == 0
    return capsys.readouterr()


def test_show_prints_the_gesture_code_before_the_steps(capsys):
    out = show(capsys, "--color", "never").out
    assert "\x1b" not in out
    lines = out.splitlines()
    assert lines[:2] == ["peace: 0.700 s on profile 'rhand'", ""]
    assert lines[2:7] == [*PEACE, ""] and lines[7].split()[:2] == ["#", "step"]


def test_show_colours_the_code_when_asked(capsys):
    out = show(capsys, "--color", "always").out
    assert "\x1b[" in out
    code = ESCAPE.sub("", out).splitlines()
    assert code[2:6] == PEACE
    coloured = out.splitlines()[5]
    assert coloured.startswith("    \x1b[") and "\x1b[" not in "\n".join(out.splitlines()[6:])


@pytest.mark.parametrize(("tty", "no_color", "coloured"),
                         [(True, None, True), (True, "1", False), (False, None, False),
                          (True, "", True)])
def test_show_colours_a_terminal_unless_no_color(capsys, monkeypatch, tty, no_color,
                                                 coloured):
    monkeypatch.setattr(sys.stdout, "isatty", lambda: tty)
    if no_color is None:
        monkeypatch.delenv("NO_COLOR", raising=False)
    else:
        monkeypatch.setenv("NO_COLOR", no_color)
    assert ("\x1b[" in show(capsys).out) is coloured


def test_the_color_option_wins_over_no_color():
    class Tty:
        def isatty(self):
            return True

    assert wants_color("always", Tty(), {"NO_COLOR": "1"})
    assert not wants_color("never", Tty(), {})
    assert wants_color("auto", Tty(), {}) and not wants_color("auto", Tty(), {"NO_COLOR": "1"})
    assert not wants_color("auto", object(), {})  # no isatty: not a terminal


def test_without_pygments_the_code_is_plain(capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "inmoov_dsl.editor.lexer", None)  # cannot be imported
    seen = show(capsys, "--color", "always")
    assert "\x1b" not in seen.out and seen.out.splitlines()[2:6] == PEACE
    assert seen.err == ("gestc: warning: --color always: colours need pygments (pip install "
                        "'inmoov-dsl[highlight]')\n")


def test_the_package_needs_no_pygments(tmp_path):
    code = ("import sys; sys.modules['pygments'] = None; "
            "import inmoov_dsl, inmoov_dsl.editor, inmoov_dsl.cli.gestc.show; "
            "from inmoov_dsl.cli.gestc import main; sys.exit(main(['show', 'peace']))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          cwd=tmp_path, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines()[2:6] == PEACE


def test_the_code_shown_is_the_gesture_its_comments_and_its_last_line(tmp_path):
    path = tmp_path / "two.gest"
    path.write_text("# the file's header\n\n# a: first\n# and more\na:\n    index 90 over \\\n"
                    "        1s\n    # a comment in a\n\n\n# b: second\nb: index 0\n")
    program = load(str(path))
    assert source_text(program, "a").splitlines() == [
        "  two.gest, lines 3-7", "    # a: first", "    # and more", "    a:",
        "        index 90 over \\", "            1s"]
    assert source_text(program, "b").splitlines() == [
        "  two.gest, lines 11-12", "    # b: second", "    b: index 0"]
    assert source_text(program, "c") is None
    one = tmp_path / "one.gest"
    one.write_text("one: index 0\n")
    assert source_text(load(str(one)), "one") == "  one.gest, line 1\n    one: index 0"
