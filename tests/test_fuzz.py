"""Whatever the input, the compiler answers with diagnostics, never a crash or a hang."""

import random
import time

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from mutate import KINDS, Hang, attempt, mutate, seeds, within

from inmoov_dsl import compile_source
from inmoov_dsl.errors import GestError
from inmoov_dsl.language.parse import parse

WORDS = ["peace", "g", "index", "middle", "fingers", "all", "fist", "pose", "group", "use",
         "wait", "hold", "repeat", "over", "stagger", ":", ",", "90", "180", "200", "-3",
         "0.5", "1s", "300ms", "2 s", "x", '"peace.gest"', "#c", "\n", "\n    ", "\n        ",
         "\t", "@"]

FUZZ = settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@FUZZ
@given(st.text(max_size=200))
def test_any_text_parses_or_is_a_diagnostic(text):
    try:
        parse(text, "fuzz.gest")
    except GestError as exc:
        assert exc.diagnostics  # every error the text has, each at its place
        for diagnostic in exc.diagnostics:
            assert diagnostic.pos.file == "fuzz.gest" and diagnostic.pos.line >= 1
        assert exc.format().startswith("fuzz.gest:")


@FUZZ
@given(st.lists(st.sampled_from(WORDS), max_size=40).map(" ".join))
def test_any_token_soup_compiles_or_is_a_diagnostic(text):
    source = "g:\n    " + text
    try:
        compile_source(source, gesture="g", file="soup.gest")
    except GestError as exc:
        assert all(d.severity == "error" for d in exc.diagnostics)
        assert exc.format()


# -- seeded mutants of real files (tests/mutate.py; benchmarks/fuzz.py runs 20,000) ----
MUTANTS = {"gest": 100, "toml": 160, "gestc": 300}  #: per kind: the file runs in ~8 s
LIMIT = 5.0  #: s of CPU per input (the wall clock may take ten times; most take ms)


@pytest.fixture(scope="module")
def library_seeds():
    return seeds()


@pytest.mark.parametrize("kind", KINDS)
def test_mutants_are_accepted_or_refused_with_a_place(library_seeds, kind):
    """Every mutant is accepted (and then keeps every rule of the protocol) or refused
    with GestErrors that each read ``file:line:col: error: ...``; none raises anything
    else, none takes more than LIMIT seconds of CPU (a timer interrupts it)."""
    problems, statuses = [], set()
    for n in range(MUTANTS[kind]):
        rng = random.Random(f"test:{kind}:{n}")
        seed = rng.choice(library_seeds[kind])
        outcome = attempt(seed, mutate(seed.data, rng, kind), LIMIT)
        statuses.add(outcome.status)
        if outcome.status not in ("accepted", "refused"):
            problems.append(f"mutant {n} of {seed.name}: {outcome.status} after "
                            f"{outcome.seconds:.1f} s {outcome.detail}")
    assert not problems, "\n".join(problems[:5])
    assert statuses == {"accepted", "refused"}  # the mutants do reach both ends


def test_the_seeds_themselves_are_accepted(library_seeds):
    assert all(library_seeds[kind] for kind in KINDS)  # seeds of every kind
    for kind in KINDS:
        for seed in library_seeds[kind]:
            assert attempt(seed, seed.data, 30.0).status == "accepted", seed.name


def test_an_input_that_loops_or_waits_is_called_a_hang():
    """The fuzzers' time bound: a loop is stopped by the CPU it spends, whatever the
    machine's load (time spent waiting for a core is not counted); a wait, by ten
    times the bound on the wall clock."""
    def spin():
        while True:
            pass

    started = time.monotonic()
    with pytest.raises(Hang):
        within(0.2, spin)
    with pytest.raises(Hang):
        within(0.05, lambda: time.sleep(5))
    assert time.monotonic() - started < 4.5  # neither ran on (a bound a loaded machine meets)
    assert within(0.1, lambda: time.sleep(0.2) or 42) == 42  # waiting spends no CPU
