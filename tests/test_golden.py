"""The card's line and a multi-step gesture compile to the reviewed streams in golden/."""

from pathlib import Path

import pytest

from inmoov_dsl import compile_file, to_timed

ROOT = Path(__file__).resolve().parent.parent
GOLDEN = Path(__file__).parent / "golden"


def parse_timed(text):
    rows = [line.split() for line in text.splitlines()]
    return [float(t) for t, _ in rows], [int(b) for _, b in rows]


@pytest.mark.parametrize(("source", "golden"), [
    (GOLDEN / "card.gest", "card.timed"),
    (ROOT / "gestures" / "count.gest", "count.timed"),
])
def test_compiles_to_the_golden_stream(source, golden):
    times, data = parse_timed(to_timed(compile_file(source).stream()))
    want_times, want_data = parse_timed((GOLDEN / golden).read_text())
    assert data == want_data
    assert times == pytest.approx(want_times, abs=2e-6)
