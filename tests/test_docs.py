"""Every example in the docs compiles, and the Python examples run and assert their
result."""

import ast
import re
from pathlib import Path

import pytest

from inmoov_dsl import compile_source
from inmoov_dsl.language.load import load

ROOT = Path(__file__).resolve().parent.parent
DOCS = sorted((ROOT / "docs").glob("*.md")) + [ROOT / "README.md"]


def blocks(lang):
    for doc in DOCS:
        text = doc.read_text()
        for n, match in enumerate(re.finditer(rf"```{lang}\n(.*?)```", text, re.S)):
            line = text[:match.start()].count("\n") + 2
            yield pytest.param(doc, match[1], id=f"{doc.name}:{line}:{n}")


@pytest.mark.parametrize(("doc", "source"), list(blocks("gest")))
def test_gest_examples_compile(doc, source):
    program = load(str(doc.with_suffix(".gest")), source)
    assert program.own, "an example should define a gesture"
    for name in program.own:  # for the robot its first line names, else rhand
        compiled = compile_source(source, gesture=name, file=str(doc))
        assert compiled.streams[0].data[0] == 255
    assert "--profile" not in source, "an example names its robot with a robot line"


class _NoteAsserts(ast.NodeTransformer):
    """After each ``assert``, a note of its line in ``__asserted__``."""

    def visit_Assert(self, node):
        note = ast.parse(f"__asserted__.add({node.lineno})").body[0]
        return [node, ast.copy_location(note, node)]


def run_example(code, file):
    """Run Python ``code``: the lines of its asserts, and those of the asserts that ran."""
    tree = ast.parse(code, file)
    asserts = {node.lineno for node in ast.walk(tree) if isinstance(node, ast.Assert)}
    asserted = set()
    tree = ast.fix_missing_locations(_NoteAsserts().visit(tree))
    exec(compile(tree, file, "exec"), {"__asserted__": asserted})
    return asserts, asserted


@pytest.mark.parametrize(("doc", "code"), list(blocks("python")))
def test_python_examples_run(doc, code, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    asserts, asserted = run_example(code, str(doc))
    assert asserts, "a Python example asserts its result"
    assert asserted == asserts, "every assert of the example ran (lines of the block)"


def test_an_assert_the_example_skips_is_seen():
    code = "try:\n    1 / 1\nexcept ZeroDivisionError:\n    assert False\nassert 1\n"
    assert run_example(code, "<example>") == ({4, 5}, {5})


def test_language_reference_covers_every_construct():
    language = ROOT / "docs" / "language.md"
    examples = "\n".join(src for doc, src in (p.values for p in blocks("gest"))
                         if doc == language)
    for construct in ("over", "wait", "hold", "pose", "group", "repeat", "stagger", "through",
                      "left", "&", "use", "#"):
        assert re.search(rf"(^|\W){re.escape(construct)}(\W|$)", examples, re.M), construct
    assert "peace: index 180, middle 180 over 0.4s" in language.read_text()


def test_the_readme_shows_what_the_card_really_does(tmp_path, capsys):
    from inmoov_dsl.cli import gestc

    readme = (ROOT / "README.md").read_text()
    card = tmp_path / "card.gest"
    card.write_text("peace: index 180, middle 180 over 0.4s\n")
    assert gestc.main(["check", str(card)]) == 0
    said = capsys.readouterr().err.replace(str(card), "card.gest")
    shown = re.search(r"```text\n(card\.gest:.*?)```", readme, re.S)[1]
    assert said == shown
    final = compile_source(card.read_text()).final
    assert dict(zip(("index", "middle"), final[2:4], strict=True)) == {"index": 180,
                                                                       "middle": 180}
