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


def _slug(heading: str) -> str:
    """A heading's anchor as GitHub makes it."""
    text = re.sub(r"[^\w\- ]", "", heading.strip().lower())
    return text.replace(" ", "-")


def _anchors(path: Path) -> set[str]:
    text = re.sub(r"```.*?```", "", path.read_text(), flags=re.S)
    return {_slug(m[1]) for m in re.finditer(r"^#+ (.*)$", text, re.M)}


@pytest.mark.parametrize("doc", DOCS, ids=lambda d: d.name)
def test_the_docs_links_lead_somewhere(doc):
    """Every link to a file of the repository reaches it, and its anchor a heading; the
    docs stand on their own (nothing outside the repository is named as a source)."""
    text = doc.read_text()
    for target in re.findall(r"\]\(([^)\s]+)\)", text):
        if re.match(r"[a-z]+:", target):
            continue  # a web address
        file, _, anchor = target.partition("#")
        path = (doc.parent / file).resolve() if file else doc
        assert path.exists(), f"{doc.name}: {target} is not in the repository"
        if anchor:
            assert anchor in _anchors(path), f"{doc.name}: {target} names no heading"
    assert "facts.md" not in text and "../shared" not in text


def test_the_readme_counts_the_library():
    from inmoov_dsl.language.library import scan

    count = len(scan([ROOT / "gestures"]).entries)
    said = re.search(r"the library: (\d+) gestures", (ROOT / "README.md").read_text())
    assert int(said[1]) == count


def test_the_language_reference_lists_every_keyword():
    from inmoov_dsl.language.syntax import KEYWORDS

    text = (ROOT / "docs" / "language.md").read_text()
    listed = re.search(r"The keywords \(([^)]*)\)", text)[1]
    assert set(re.findall(r"`(\w+)`", listed)) == KEYWORDS
    names = re.search(r"Keywords cannot be names:\s*`([^`]*)`", text)[1]
    assert set(names.split()) == KEYWORDS
