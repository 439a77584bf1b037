"""Other tools' animations, mangled: ``gestc import`` answers each with a gesture or a
message and exit 1 (nothing written), never a traceback or a hang (seeded)."""

from __future__ import annotations

import random

import pytest
from test_fuzz_cli import run_watched

from inmoov_dsl.cli import gestc

SEED, MUTANTS = 52, 30
EXTS = {"bsa-json": ".json", "bsa-h": ".h", "bottango": ".txt", "csv": ".csv"}
#: what a mangled file may hold: markers, signs, huge and odd numbers, other formats' words
PIECES = ["0", "9", "-1", "1e9", "99999999999999999999", ",", "{", "}", "[", "]", '"', ":",
          "\n", "0x3c", "0x0a", "sC,", "rSVPin,", "nan", "inf", "null", "true", "é", "\x00",
          "FPS = 0;", "time,", ",,", "-0", "1.5", " "]


@pytest.fixture(scope="module")
def exported(tmp_path_factory) -> dict[str, str]:
    """The library's ``peace`` in each format."""
    home = tmp_path_factory.mktemp("exported")
    out = {}
    for fmt, ext in EXTS.items():
        path = home / f"peace{ext}"
        assert gestc.main(["export", "peace", "--format", fmt, "-o", str(path)]) == 0
        out[fmt] = path.read_text()
    return out


def mutants(texts: dict[str, str], seed: int, count: int):
    rng = random.Random(seed)
    for _ in range(count):
        fmt = rng.choice(sorted(texts))
        text = texts[fmt]
        digits = [k for k, c in enumerate(text) if c.isdigit()]
        for _ in range(rng.randint(1, 4)):
            if rng.random() < 0.7:  # a number changed: the file still reads as its format
                k = rng.choice(digits)
                text = text[:k] + rng.choice("0123456789") + text[k + 1:]
            else:  # the file's shape broken
                k = rng.randrange(len(text))
                cut = rng.choice([0, 1, 1, 3, 20])
                text = text[:k] + rng.choice(PIECES) + text[k + cut:]
        if rng.random() < 0.1:
            text = text[:rng.randrange(len(text))]  # cut short
        yield fmt, text


def test_mangled_animations_are_a_gesture_or_a_message(exported, tmp_path):
    answers = {0: 0, 1: 0}
    for n, (fmt, text) in enumerate(mutants(exported, SEED, MUTANTS)):
        src, out = tmp_path / f"m{n}{EXTS[fmt]}", tmp_path / f"m{n}.gest"
        src.write_text(text, encoding="utf-8", errors="surrogatepass")
        status, said = run_watched(gestc, ["import", str(src), "-o", str(out)])
        assert status in (0, 1), f"{fmt} mutant {n}: {status!r}\n{said}"
        assert "Traceback" not in said, f"{fmt} mutant {n}\n{said}"
        if status == 1:
            assert f"m{n}" in said and not out.exists(), f"{fmt} mutant {n}\n{said}"
        answers[status] += 1
    assert answers[0] and answers[1], answers  # both kinds met: the mutants are not all fatal
