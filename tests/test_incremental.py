"""An editor's analysis after an edit is the same as a fresh one: the blocks a parse
keeps (``language.incremental``) and the checks a server keeps (``editor.memo``) give
what ``parse`` and ``gestc check`` give the whole text, errors, warnings, places and
plans included, whatever the edits: typed characters, new lines, lines moved, mutants."""

import random
import re

import pytest
from mutate import mutate, seeds

from inmoov_dsl.editor.analysis import analyse
from inmoov_dsl.editor.memo import Memo
from inmoov_dsl.errors import GestError
from inmoov_dsl.language.incremental import BlockParser
from inmoov_dsl.language.parse import parse

EDITS = 150


def parsed(fn):
    try:
        return fn()
    except GestError as exc:
        return [d.format() for d in exc.diagnostics]


def told(found):
    return ([d.format() for d in found.diagnostics],
            {g: [(s.pos, s.start, s.end, s.stretched) for s in p.steps]
             for g, p in found.plans.items()})


def edited(lines: list[str], rng: random.Random) -> None:
    """One edit as typing makes it, in place."""
    k = rng.randrange(len(lines))
    row = lines[k]
    cut = rng.randrange(len(row) + 1)
    match rng.randrange(6):
        case 0:
            lines[k] = row[:cut] + rng.choice("abx0 9:,.s#\"&") + row[cut:]
        case 1:
            lines[k] = row[:cut] + row[cut + 1:]
        case 2:
            lines[k:k + 1] = [row[:cut], row[cut:]]  # Enter
        case 3:
            if k + 1 < len(lines):
                lines[k:k + 2] = [row + lines[k + 1]]  # a line joined to the next
        case 4:
            lines.insert(rng.randrange(len(lines) + 1), lines.pop(k))  # a line moved
        case 5:
            lines[k] = re.sub(r"\d+", lambda m: str(rng.randrange(200)), row, count=1)


@pytest.fixture(scope="module")
def library():
    return seeds()["gest"]


def test_blocks_kept_parse_as_the_whole_text(library):
    parser = BlockParser()
    for n in range(EDITS):
        rng = random.Random(f"blocks:{n}")
        seed = rng.choice(library)
        lines = seed.data.decode().split("\n")
        for _ in range(rng.randrange(1, 4)):
            edited(lines, rng)
            text = "\n".join(lines)
            assert parsed(lambda t=text, f=seed.name: parser.parse(t, f)) == parsed(
                lambda t=text, f=seed.name: parse(t, f)), text


def test_checks_kept_tell_what_a_fresh_analysis_tells(library, tmp_path):
    memo = Memo()
    path = str(tmp_path / "typed.gest")
    parts: list[str] = []
    for seed in library:  # the library's hand files that go together in one file
        if b"robot" not in seed.data and b"use" not in seed.data and not analyse(
                "\n".join([*parts, seed.data.decode()]), path).diagnostics:
            parts.append(seed.data.decode())
    base = "\n".join(parts).split("\n")
    assert len(base) > 100
    rng = random.Random("checks")
    kept = 0
    for n in range(40):
        lines = list(base)
        for _ in range(rng.randrange(1, 3)):
            edited(lines, rng)
        text = "\n".join(lines)
        found = analyse(text, path, memo=memo)
        kept += bool(memo.checks)
        assert told(found) == told(analyse(text, path)), n
    assert kept > 20  # most versions were checked with checks kept


def test_mutants_one_after_another_on_one_memo(library, tmp_path):
    memo = Memo()
    for n in range(8):
        rng = random.Random(f"memo:{n}")
        seed = rng.choice(library)
        text = mutate(seed.data, rng, "gest").decode("utf-8", "replace")
        path = str(tmp_path / seed.name.split("/")[-1])
        assert told(analyse(text, path, memo=memo)) == told(analyse(text, path)), n
