"""Every example in the docs compiles, and the Python examples run."""

import re
from pathlib import Path

import pytest

from inmoov_dsl import compile_source
from inmoov_dsl.compiler import load

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
    for name in program.own:
        compiled = compile_source(source, gesture=name, file=str(doc))
        assert compiled.streams[0].data[0] == 255


@pytest.mark.parametrize(("doc", "code"), list(blocks("python")))
def test_python_examples_run(doc, code, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    exec(compile(code, str(doc), "exec"), {})


def test_language_reference_covers_every_construct():
    text = (ROOT / "docs" / "language.md").read_text()
    examples = "\n".join(src for _, src in (p.values for p in blocks("gest")))
    for construct in ("over", "wait", "hold", "pose", "group", "repeat", "stagger", "use",
                      "#"):
        assert construct in examples, construct
    assert "peace: index 180, middle 180 over 0.4s" in text
